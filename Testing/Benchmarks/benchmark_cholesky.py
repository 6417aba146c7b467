#!/usr/bin/python3
"""The SIMD Cholesky builds (Filters/Core/DenseCholesky*.cpp: Eigen built for AVX2 + FMA and
AVX-512, picked at run time) against plain Eigen LLT (the core's baseline build, forced by
MCV_CHOLESKY_KERNEL=baseline), on the whole user-facing step: the LLE fit of mcvReduceCLI
(locally linear landmarks, K = 10, L = 500, fit on all N points as compare_sklearn.py runs
it) on the real brain samples of dump_brain_samples.py.

Processes alternate A/B (--rounds times); each process reports the fastest of its
--repeat in-process runs; the table keeps the minimum over the rounds of each side (the
2-core machine is shared with other builds: minima of alternating runs survive that).

  /usr/bin/python3 Testing/Benchmarks/benchmark_cholesky.py --cli build-core/Testing/Benchmarks/mcvReduceCLI

Size 0 is the main job as the filter runs it (mcvReduceCLI's defaults: K = 50, L = 500, fit
on 10000 reference voxels, every other row of the voxels file placed out of sample,
trustworthiness on 2000), on the 200000 voxels of dump_brain_samples.py.
"""
import argparse
import json
import os
import subprocess


def run(cli, path, n, d, baseline, repeat, trust, main=False):
    env = dict(os.environ)
    env.pop("MCV_CHOLESKY_KERNEL", None)
    if baseline:
        env["MCV_CHOLESKY_KERNEL"] = "baseline"
    # main: mcvReduceCLI's defaults (the filter's: K = 50, L = 500, 10000 reference voxels,
    # trustworthiness on 2000), the rest placed out of sample; else compare_sklearn's fit.
    opts = (["--neighbors", "50", "--reference", "10000"] if main else
            ["--neighbors", "10", "--reference", str(n)])
    cmd = [cli, "--input", path, "--rows", str(n), "--cols", str(d), "--method", "lle", "--dim", "3",
           "--landmarks", "500", "--seed", "0", "--trust-sample", str(trust), "--repeat", str(repeat),
           "--repeat-below", "1000"] + opts
    out = subprocess.run(cmd, capture_output=True, text=True, env=env, check=True).stdout
    return json.loads(out.strip().splitlines()[-1])


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--cli", default="build-core/Testing/Benchmarks/mcvReduceCLI")
    ap.add_argument("--data", default="/tmp/mcv_libbench")
    ap.add_argument("--sizes", default="2000,5000,10000,0",
                    help="N of the fits on all N; 0: the main job (defaults, fit on 10000 of the voxels file, "
                         "the rest placed)")
    ap.add_argument("--sets", default="6D,24D")
    ap.add_argument("--rounds", type=int, default=8)
    ap.add_argument("--repeat", type=int, default=10)
    args = ap.parse_args()
    print(f"LLE fit (K = 10, L = 500, fit on all N), min over {args.rounds} alternating processes of the fastest "
          f"of {args.repeat} in-process runs; total_ms of mcvReduceCLI")
    print("(pencil: the 'LLE: eigenvectors' stage, Cholesky + Lanczos solves, of the fastest run of each process)")
    print(f"{'set':>4} {'N':>11} | {'SIMD ms':>8} {'plain ms':>8} {'plain/SIMD':>10} | {'pencil SIMD':>11} "
          f"{'pencil plain':>12} {'diff ms':>8} | {'T SIMD':>7} {'T plain':>7}")
    for fs in args.sets.split(","):
        d = int(fs[:-1])
        for n in [int(s) for s in args.sizes.split(",")]:
            main = n == 0
            path = os.path.join(args.data, f"{fs}_voxels.f32" if main else f"{fs}_N{n}.f32")
            if main:
                n = os.path.getsize(path) // (4 * d)
            best = {False: float("inf"), True: float("inf")}
            pencil = {False: float("inf"), True: float("inf")}
            # Trustworthiness (k = 10 on 2000 of the points) in runs of their own: it is part of total_ms.
            trust = {b: run(args.cli, path, n, d, b, 1, 2000, main)["trustworthiness"] for b in (False, True)}
            for r in range(args.rounds):
                for baseline in ((False, True) if r % 2 == 0 else (True, False)):
                    info = run(args.cli, path, n, d, baseline, args.repeat, 2000 if main else 0, main)
                    best[baseline] = min(best[baseline], info["total_ms"])
                    stage = dict((k, v) for k, v in info["stages_ms"]).get("LLE: eigenvectors", float("nan"))
                    pencil[baseline] = min(pencil[baseline], stage)
            print(f"{fs:>4} {('main ' if main else '') + str(n):>11} | {best[False]:8.2f} {best[True]:8.2f} {best[True] / best[False]:9.3f}x | "
                  f"{pencil[False]:11.2f} {pencil[True]:12.2f} {pencil[True] - pencil[False]:8.2f} | "
                  f"{trust[False]:7.4f} {trust[True]:7.4f}", flush=True)


if __name__ == "__main__":
    main()
