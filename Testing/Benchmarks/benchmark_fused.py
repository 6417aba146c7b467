"""The fused reduction against MultichannelFeatures -> DimensionReduction: time
and peak resident memory at 1, 7.1 and 57 M voxels of the real brain.

    xvfb-run -a pvbatch Testing/Benchmarks/benchmark_fused.py [--upsample 0.53,1,2]
        [--features 24D] [--method Isomap] [--chains fused,features]

The volume is the 3-channel brain (Colin27 T1 + AAL + Brodmann) resampled by F along each
axis (ParaView's trilinear ResampleToImage; F = 0.53: 1.06 M voxels, 1: 7.1 M, 2: 57 M).
Each (F, chain) runs in its own pvbatch process, so that its peak resident memory
(ru_maxrss) is its own: read + resample, then the chain (main job settings: 24D, Isomap,
reference sample 10000, K 10, L 500). Prints, per run, the chain's seconds, the process's
peak resident memory and the memory the volume itself held (peak after the resample), the
chain's nanoseconds per voxel, and per size the ratio old chain / fused in time and peak
memory, measured in the same invocation.
"""
import argparse
import json
import os
import resource
import subprocess
import sys
import time


def rss_gib():
    return resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024.0 ** 2


def one_run(args):
    """In the child: one chain at one size; prints one JSON line."""
    sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "Python"))
    import mcv_testing as T
    from paraview import simple

    T.load_plugin(globals())
    readers = [simple.OpenDataFile(T.data_file(n)) for n in ("ch2.nii.gz", "aal.nii.gz", "brodmann.nii.gz")]
    volume = simple.AppendAttributes(Input=readers)
    volume.UpdatePipeline()
    if args.one_upsample != 1.0:
        extent = volume.GetDataInformation().GetExtent()
        dims = [extent[2 * a + 1] - extent[2 * a] + 1 for a in range(3)]
        volume = simple.ResampleToImage(Input=volume, UseInputBounds=1, SamplingDimensions=[
            max(1, int(round(d * args.one_upsample))) for d in dims])
        volume.UpdatePipeline()
    voxels = volume.GetDataInformation().GetNumberOfPoints()
    input_gib = rss_gib()
    settings = dict(Method=args.method, OutputDimension=3, ReferenceSampleSize=10000,
                    NumberOfNeighbors=10, NumberOfLandmarks=500)
    start = time.time()
    if args.one_chain == "features":
        feats = simple.MultichannelFeatures(Input=volume, FeatureSet=args.features)
        reduction = simple.DimensionReduction(Input=feats, FeatureSet="Use input array", **settings)
        reduction.Features = ["POINTS", "Features"]
    else:
        reduction = simple.DimensionReduction(Input=volume, FeatureSet=args.features, **settings)
    reduction.UpdatePipeline()
    seconds = time.time() - start
    ok = reduction.GetDataInformation().GetPointDataInformation().GetArrayInformation(
        "ReducedCoordinates") is not None
    print("RESULT " + json.dumps(dict(upsample=args.one_upsample, chain=args.one_chain, voxels=voxels,
                                      seconds=seconds, peak_gib=rss_gib(), input_gib=input_gib, ok=ok)))


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--upsample", default="0.53,1,2", help="factors F (default 1, 7.1, 57 M voxels)")
    parser.add_argument("--chains", default="fused,features")
    parser.add_argument("--features", default="24D", choices=["6D", "24D"])
    parser.add_argument("--method", default="Isomap", choices=["PCA", "Isomap", "LLE"])
    parser.add_argument("--one-upsample", type=float, default=None, help=argparse.SUPPRESS)
    parser.add_argument("--one-chain", default=None, help=argparse.SUPPRESS)
    args = parser.parse_args()
    if args.one_chain:
        one_run(args)
        return

    pvbatch = sys.executable if os.path.basename(sys.executable).startswith("pv") else "pvbatch"
    results = []
    print("%-8s %-9s %10s %9s %10s %10s %8s" % ("F", "chain", "voxels", "chain s", "peak GiB",
                                                "input GiB", "ns/voxel"))
    for factor in [float(f) for f in args.upsample.split(",")]:
        for chain in args.chains.split(","):
            run = subprocess.run([pvbatch, os.path.abspath(__file__), "--one-upsample", str(factor),
                                  "--one-chain", chain, "--features", args.features, "--method", args.method],
                                 stdout=subprocess.PIPE, stderr=subprocess.STDOUT, universal_newlines=True)
            lines = [l for l in run.stdout.splitlines() if l.startswith("RESULT ")]
            if run.returncode != 0 or not lines:
                print("%-8g %-9s failed (exit %d): %s" % (factor, chain, run.returncode, run.stdout[-600:]))
                continue
            r = json.loads(lines[-1][len("RESULT "):])
            results.append(r)
            print("%-8g %-9s %10d %9.1f %10.2f %10.2f %8.0f%s" % (
                factor, chain, r["voxels"], r["seconds"], r["peak_gib"], r["input_gib"],
                1e9 * r["seconds"] / r["voxels"], "" if r["ok"] else "  (no coordinates!)"))
            sys.stdout.flush()
    print("\nold chain / fused, same invocation:")
    for factor in sorted({r["upsample"] for r in results}):
        pair = {r["chain"]: r for r in results if r["upsample"] == factor}
        if "fused" in pair and "features" in pair:
            f, o = pair["fused"], pair["features"]
            print("  F = %g (%.1f M voxels): time x%.2f, peak memory x%.2f (%.2f vs %.2f GiB), "
                  "above the input x%.2f" % (
                      factor, f["voxels"] / 1e6, o["seconds"] / f["seconds"], o["peak_gib"] / f["peak_gib"],
                      o["peak_gib"], f["peak_gib"],
                      (o["peak_gib"] - o["input_gib"]) / max(1e-9, f["peak_gib"] - f["input_gib"])))


if __name__ == "__main__":
    main()
