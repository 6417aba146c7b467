#!/usr/bin/env bash
# Issue 20 §4, MPI: the main job's fused reduction (the real brain resampled by F, 24D,
# Isomap) under `mpiexec -np R pvbatch --mpi --symmetric` for R = 1, 2, 4
# (benchmark_mpi_memory.py). Prints, per run, each process's peak resident memory against
# the one-process run's (and the share 1/R of the volume's data: channels + coordinates),
# the stage times, and the largest difference of every process's coordinates from the
# one-process coordinates, voxel by voxel.
#   Testing/Benchmarks/benchmark_mpi_memory.sh [--upsample F] [--ranks "1 2 4"] [BUILD_DIR]
set -euo pipefail
repo="$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)"
upsample=2
ranks_list="1 2 4"
build="$repo/build"
while [ $# -gt 0 ]; do
  case "$1" in
    --upsample) upsample="$2"; shift 2 ;;
    --ranks) ranks_list="$2"; shift 2 ;;
    *) build="$1"; shift ;;
  esac
done
build="$(cd "$build" && pwd)"
plugin_dir="$build/lib/paraview-5.11/plugins/MultichannelExplorer"
export MCV_PLUGIN="$plugin_dir/MultichannelExplorer.so"
export MCV_DATA_DIR="${MCV_DATA_DIR:-$repo/.cache/volumes}"
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 OMPI_MCA_rmaps_base_oversubscribe=1
cores=$(nproc)
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT
for ranks in $ranks_list; do
  threads=$(( cores / ranks )); [ "$threads" -ge 1 ] || threads=1
  echo "== $ranks process(es) x $threads OpenMP thread(s), upsample $upsample" >&2
  OMP_NUM_THREADS=$threads xvfb-run -a -s "-screen 0 640x480x24" \
    mpiexec -np "$ranks" pvbatch --mpi --symmetric "$repo/Testing/Benchmarks/benchmark_mpi_memory.py" \
    --upsample "$upsample" --output "$out/r$ranks" 2>&1 | grep -E '^rank |ERR' >&2 || true
done
/usr/bin/python3 - "$out" "$ranks_list" <<'PY'
import json, os, sys
import numpy as np

out, ranks_list = sys.argv[1], [int(r) for r in sys.argv[2].split()]

def load(R):
    infos = [json.load(open(os.path.join(out, "r%d" % R, "rank%d.json" % r))) for r in range(R)]
    return infos

base = load(ranks_list[0])[0]
dims = base["whole_dims"]
serial = np.fromfile(os.path.join(out, "r%d" % ranks_list[0], "rank0.f32"), dtype=np.float32)
serial = serial.reshape(dims[2], dims[1], dims[0], 3)
span = float((serial.reshape(-1, 3).max(0) - serial.reshape(-1, 3).min(0)).max())
voxels = dims[0] * dims[1] * dims[2]
data_gib = voxels * (3 * 4 + 3 * 4) / float(1 << 30)  # float channels + float coordinates
print("Fused reduction of the brain resampled to %d x %d x %d = %.1f M voxels (24D, Isomap); "
      "channels + coordinates %.2f GiB" % (dims[0], dims[1], dims[2], voxels / 1e6, data_gib))
print("%5s %8s | %9s %9s %9s | %13s %13s | %22s | %s" % ("ranks", "threads", "upsample", "reduction",
      "total s", "peak GiB max", "peak / 1-rank", "reduction: start->peak",
      "largest |coordinate - 1-rank| / range"))
for R in ranks_list:
    infos = load(R)
    worst, points = 0.0, 0
    for r, info in enumerate(infos):
        e = info["extent"]
        if info["points"] == 0:
            continue
        got = np.fromfile(os.path.join(out, "r%d" % R, "rank%d.f32" % r), dtype=np.float32)
        got = got.reshape(e[5] - e[4] + 1, e[3] - e[2] + 1, e[1] - e[0] + 1, 3)
        ref = serial[e[4]:e[5] + 1, e[2]:e[3] + 1, e[0]:e[1] + 1]
        worst = max(worst, float(np.abs(got.astype(np.float64) - ref).max()))
        points += info["points"]
    peaks = [i["peak_rss_gib"] for i in infos]
    stages = infos[0]["stage_seconds"]
    own = " ".join("%.2f->%.2f" % (i["stage_start_rss_gib"]["reduction"],
                                     i["stage_own_peak_gib"]["reduction"] or float("nan"))
                   for i in infos)
    print("%5d %8d | %9.1f %9.1f %9.1f | %13s %13.2f | %22s | %.2e (%d points in %d pieces)"
          % (R, infos[0]["threads"], stages.get("upsample", 0), stages["reduction"],
             sum(stages.values()), " ".join("%.2f" % p for p in peaks),
             max(peaks) / base["peak_rss_gib"], own, worst / span, points, R))
print("peak: ru_maxrss of each process at the end (ParaView, Python and the libraries take "
      "~0.35 GiB of it before any data is read). reduction: each process's resident size when the "
      "reduction started and its peak during the reduction (VmHWM restarted at its start).")
PY
