#!/usr/bin/env bash
# MPI: the main job's fused reduction (the real brain resampled by F, 24D,
# Isomap) under `mpiexec -np R pvbatch --mpi --symmetric` for R = 1, 2, 4
# (benchmark_mpi_memory.py). Prints, per run and process, the resident size before
# anything is read (ParaView + plugin: the baseline), the peak, the data share (peak -
# baseline) and what it still holds after the reduction (VmRSS - baseline), each against
# the one-process run's and 1/R, the stage times, and the largest
# difference of every process's coordinates from the one-process coordinates, voxel by voxel.
#   --source pieces (default): the merged, resampled channels are first saved once, by one
#     process, as one uncompressed .vti; the R-process runs read it with the XML reader,
#     which reads only the extent each process asks for (docs/benchmarks.md §7.2).
#   --source nifti: every process reads the NIfTI files whole and resamples (§7.1).
#   --method PCA: a faster reduction than the main job's Isomap (memory figures at 57 M
#     voxels on a slow machine); the features, the slab and the coordinates are the same.
#   Testing/Benchmarks/benchmark_mpi_memory.sh [--upsample F] [--ranks "1 2 4"]
#       [--source pieces|nifti] [--method Isomap|PCA] [BUILD_DIR]
set -euo pipefail
repo="$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)"
upsample=2
ranks_list="1 2 4"
source=pieces
method=Isomap
build="$repo/build"
while [ $# -gt 0 ]; do
  case "$1" in
    --upsample) upsample="$2"; shift 2 ;;
    --ranks) ranks_list="$2"; shift 2 ;;
    --source) source="$2"; shift 2 ;;
    --method) method="$2"; shift 2 ;;
    *) build="$1"; shift ;;
  esac
done
case "$source" in pieces|nifti) ;; *) echo "--source: pieces or nifti" >&2; exit 2 ;; esac
build="$(cd "$build" && pwd)"
plugin_dir="$build/lib/paraview-5.11/plugins/MultichannelExplorer"
export MCV_PLUGIN="$plugin_dir/MultichannelExplorer.so"
export MCV_DATA_DIR="${MCV_DATA_DIR:-$repo/.cache/volumes}"
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 OMPI_MCA_rmaps_base_oversubscribe=1
script="$repo/Testing/Benchmarks/benchmark_mpi_memory.py"
cores=$(nproc)
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT
source_args=(--upsample "$upsample")
if [ "$source" = pieces ]; then
  echo "== writing the channels (upsample $upsample) once, one process" >&2
  OMP_NUM_THREADS=$cores xvfb-run -a -s "-screen 0 640x480x24 -noreset" \
    pvbatch "$script" --upsample "$upsample" --write-volume "$out/brain.vti" 2>&1 \
    | grep -E '^wrote |ERR' >&2 || true
  [ -s "$out/brain.vti" ] || { echo "writing $out/brain.vti failed" >&2; exit 1; }
  source_args=(--volume "$out/brain.vti")
fi
for ranks in $ranks_list; do
  threads=$(( cores / ranks )); [ "$threads" -ge 1 ] || threads=1
  echo "== $ranks process(es) x $threads OpenMP thread(s), upsample $upsample, source $source, $method" >&2
  OMP_NUM_THREADS=$threads xvfb-run -a -s "-screen 0 640x480x24 -noreset" \
    mpiexec -np "$ranks" pvbatch --mpi --symmetric "$script" \
    "${source_args[@]}" --method "$method" --output "$out/r$ranks" 2>&1 | grep -E '^rank |ERR' >&2 || true
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
volume = os.path.join(out, "brain.vti")
print("Fused reduction of the brain resampled to %d x %d x %d = %.1f M voxels (24D, %s), "
      "source %s; coordinates %.2f GiB%s"
      % (dims[0], dims[1], dims[2], voxels / 1e6, base["method"],
         "one .vti (XML reader)" if base["source"] == "vti" else "NIfTI read whole by every process",
         voxels * 3 * 4 / float(1 << 30),
         ", channels file %.2f GiB" % (os.path.getsize(volume) / float(1 << 30))
         if os.path.exists(volume) else ""))
print("%5s %7s | %9s %9s | %-23s | %-23s | %-23s | %11s | %-23s | %10s | %5s | %s" % (
    "ranks", "threads", "upsample", "reduction", "baseline GiB, per rank", "peak GiB, per rank",
    "share GiB (peak - base)", "max share/1", "held GiB (end - base)", "max held/1", "1/R",
    "largest |coordinate - 1-rank| / range"))


def held(info):
    return info["stage_end_rss_gib"]["reduction"] - info["baseline_rss_gib"]


share1 = base["peak_rss_gib"] - base["baseline_rss_gib"]
held1 = held(base)
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
    shares = [i["peak_rss_gib"] - i["baseline_rss_gib"] for i in infos]
    stages = infos[0]["stage_seconds"]
    helds = [held(i) for i in infos]
    print("%5d %7d | %9.1f %9.1f | %-23s | %-23s | %-23s | %11.3f | %-23s | %10.3f | %5.3f | %.2e (%d points in %d pieces)"
          % (R, infos[0]["threads"], stages.get("upsample", 0), stages["reduction"],
             " ".join("%.2f" % i["baseline_rss_gib"] for i in infos),
             " ".join("%.2f" % i["peak_rss_gib"] for i in infos),
             " ".join("%.2f" % s for s in shares), max(shares) / share1,
             " ".join("%.2f" % h for h in helds), max(helds) / held1, 1.0 / R,
             worst / span, points, R))
    print("%5s %7s   reduction's own peak per rank, GiB (resident at its start -> peak): %s"
          % ("", "", " ".join("%.2f->%.2f" % (i["stage_start_rss_gib"]["reduction"],
                                               i["stage_own_peak_gib"]["reduction"] or float("nan"))
                              for i in infos)))
print("baseline: VmRSS once ParaView, Python and the plugin are loaded, before anything is read; "
      "peak: ru_maxrss at the end; share: peak - baseline, the data and the working memory of "
      "the job; held: VmRSS after the reduction - baseline, what the process keeps (its block of "
      "channels in the reader and the output, coordinates, mask) once the working memory (the "
      "feature slab) is freed; max .../1: the largest of the R processes over the one-process "
      "figure (1/R when it splits). With --source pieces the reduction stage includes the read.")
PY
