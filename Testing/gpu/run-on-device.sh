#!/usr/bin/env bash
# One call on the GPU machine (no ParaView there): configure, build, run the GPU tests and
# the core tests, run the GPU benchmark, print a short table last. Logs go to $OUT when set
# (the device tool brings that folder back), else to build-gpu/logs.
#
#   Testing/gpu/run-on-device.sh [benchmark arguments, e.g. --sizes 64,256 --sweep]
#
# Real volumes: put them in .cache/volumes (scripts/fetch-data.sh) and carry that folder.
# Header-only libraries the device lacks (nanoflann, Spectra): scripts/prepare-device.sh
# copies them into .cache/include; carry that folder too.
# MCV_DEVICE_CMAKE_ARGS: extra configure arguments. MCV_FUSED_BENCH=1: also the fused-reduction
# benchmark at 1 G voxels (mcvBenchmarkFusedGPU).
set -uo pipefail

here="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
repo="$(cd "$here/../.." && pwd)"
cd "$repo"
build=build-gpu
logs="${OUT:-$repo/$build/logs}"
mkdir -p "$logs"
summary="$logs/summary.txt"
: >"$summary"
note() { echo "$*" | tee -a "$summary"; }

note "== machine"
nvidia-smi --query-gpu=name,driver_version,memory.total,clocks.max.sm --format=csv,noheader 2>&1 | tee -a "$summary"
nvcc --version 2>/dev/null | tail -1 | tee -a "$summary"
cmake --version | head -1 | tee -a "$summary"
ls .cache/volumes 2>/dev/null | tr '\n' ' ' | sed 's/^/volumes: /' | tee -a "$summary"; echo | tee -a "$summary"

note "== configure + build"
start=$(date +%s)
extra=()
[ -d .cache/include ] && extra+=(-DCMAKE_INCLUDE_PATH="$repo/.cache/include")
# shellcheck disable=SC2206
extra+=(${MCV_DEVICE_CMAKE_ARGS:-})
if ! { cmake -S . -B "$build" -DMCV_BUILD_PARAVIEW=OFF -DCMAKE_CUDA_ARCHITECTURES=90 \
         -DCMAKE_BUILD_TYPE=Release "${extra[@]}" &&
       cmake --build "$build" -j16; } >"$logs/build.log" 2>&1; then
  tail -40 "$logs/build.log"
  note "BUILD FAILED (see build.log)"
  exit 1
fi
note "built in $(( $(date +%s) - start )) s"
# Registers / spills of the Harris kernels (sm_90).
cuobjdump -res-usage "$build/Filters/Core/viewpoint/libmcvViewpoint.a" 2>/dev/null | grep -A1 "harrisKernel" |
  grep -o "Function [^ ]*\|REG:[0-9]*\|STACK:[0-9]*\|SHARED:[0-9]*\|LOCAL:[0-9]*" |
  paste -sd' ' | sed 's/Function /\n/g' | sed 's/_ZN3mcv4cuda6detail[^ ]*harrisKernelI/harrisKernel</' |
  tee -a "$logs/build.log" | head -10

note "== GPU tests"
gpu_rc=0
timeout 300 "$build/Testing/gpu/mcvGpuTests" >"$logs/gpu-tests.log" 2>&1 || gpu_rc=$?
grep -E "^\[ (agreement|top-N|view) |overlap|FAILED|Failure|PASSED|SKIPPED|error" "$logs/gpu-tests.log" | head -80
grep -E "^\[  (PASSED|FAILED|SKIPPED) |tests ran" "$logs/gpu-tests.log" | tee -a "$summary"
note "mcvGpuTests exit code $gpu_rc"

note "== core tests"
core_rc=0
timeout 240 "$build/Testing/Core/mcvCoreTests" --gtest_brief=1 >"$logs/core-tests.log" 2>&1 || core_rc=$?
grep -E "FAILED|tests ran|PASSED" "$logs/core-tests.log" | tail -15 | tee -a "$summary"
note "mcvCoreTests exit code $core_rc"

note "== benchmark"
bench_rc=0
timeout 300 "$build/Testing/gpu/mcvBenchmarkGPU" "$@" >"$logs/bench.log" 2>&1 || bench_rc=$?
grep -v "^  \|^$" "$logs/bench.log" | head -20 >/dev/null
cat "$logs/bench.log" | sed -n '/^== /,$p' | grep -E "^==|GPU uint8|GPU float|H2D|CPU:|sweep" | head -60
note "mcvBenchmarkGPU exit code $bench_rc"

note "== dimension-reduction chain (real brain: features + Isomap on 10000 + placement of every voxel)"
red_rc=0
timeout 300 "$build/Testing/Benchmarks/mcvBenchmarkReduction" >"$logs/bench-reduction.log" 2>&1 || red_rc=$?
grep -E "^==|WHOLE CHAIN|GPU vs CPU|baseline|kd-tree placement|in-run|warning|failed" "$logs/bench-reduction.log" |
  tee -a "$summary"
note "mcvBenchmarkReduction exit code $red_rc"

note "== UMAP: fit on the GPU vs the CPU (N = 10000, brain 24D) and the whole brain with UMAP vs Isomap"
umap_rc=0
timeout 120 "$build/Testing/gpu/mcvBenchmarkUMAPGPU" --sizes 10000 --runs 1 >"$logs/bench-umap.log" 2>&1 || umap_rc=$?
grep -E "^N = |^Isomap|^UMAP|failed" "$logs/bench-umap.log" | tee -a "$summary"
note "mcvBenchmarkUMAPGPU exit code $umap_rc"

note "== reduction models: applying a model vs fitting (brain 7.1 M voxels; 20-volume collection), GPU"
model_rc=0
timeout 300 "$build/Testing/Benchmarks/mcvBenchmarkModel" --devices gpu >"$logs/bench-model.log" 2>&1 || model_rc=$?
grep -E "^==|brain|collection|failed" "$logs/bench-model.log" | tee -a "$summary"
note "mcvBenchmarkModel exit code $model_rc"

note "== Gaussian transfer function (256^3 recolouring: baseline loop, CPU path, GPU path)"
tf_rc=0
timeout 180 "$build/Testing/Benchmarks/mcvBenchmarkGaussianTF" >"$logs/bench-gaussiantf.log" 2>&1 || tf_rc=$?
sed -n '/^coords/,$p' "$logs/bench-gaussiantf.log" | tee -a "$summary"
note "mcvBenchmarkGaussianTF exit code $tf_rc"

# Opt-in (about 2 minutes): the fused reduction at 67 M voxels (GPU chain) and its GPU stage at
# 1 G voxels, merged runs against every voxel searched (docs/benchmarks.md section 15).
if [ "${MCV_FUSED_BENCH:-0}" = 1 ]; then
  note "== fused reduction on the GPU (brain tiled to 67 M and 1 G voxels)"
  timeout 300 "$build/Testing/gpu/mcvBenchmarkFusedGPU" --skip-cpu --merge-baseline >"$logs/bench-fused.log" 2>&1
  grep -E "^==|WHOLE CHAIN|GPU stage|statistics pass|columns \+ sample|placement \(|bytes host|whole chain estimate|target of issue" "$logs/bench-fused.log" | tee -a "$summary"
fi

if [ "${MCV_NCU:-0}" = 1 ] && command -v ncu >/dev/null 2>&1; then
  note "== ncu (256^3): kernel durations of one warm topN, then the Harris kernel's stall profile"
  timeout 120 ncu --clock-control none --metrics gpu__time_duration.sum --csv \
    "$build/Testing/gpu/mcvBenchmarkGPU" --sizes 256 --profile >"$logs/ncu-durations.csv" 2>&1
  grep -v "^==PROF==" "$logs/ncu-durations.csv" | tail -12 | cut -c1-400
  timeout 150 ncu --clock-control none -k regex:harrisKernel -s 2 -c 1 --section SpeedOfLight \
    --section Occupancy --section WarpStateStats --section SchedulerStats --section LaunchStats \
    --section ComputeWorkloadAnalysis --section MemoryWorkloadAnalysis \
    "$build/Testing/gpu/mcvBenchmarkGPU" --sizes 256 --profile >"$logs/ncu-harris.txt" 2>&1
  grep -E "Duration|Throughput|Occupancy|Stall|Issue|Eligible|Active Warps|Registers|Shared Memory|Bank|Block Limit|L1/TEX Hit|L2 Hit|Pipe|Executed Ipc|One or More" \
    "$logs/ncu-harris.txt" | head -60
fi

echo
echo "================ summary ================"
cat "$summary"
echo
sed -n '/^Best-viewpoint GPU pipeline/,$p' "$logs/bench.log" | tee -a "$summary"
[ "$gpu_rc" -eq 0 ] && [ "$core_rc" -eq 0 ] && [ "$bench_rc" -eq 0 ] && [ "$red_rc" -eq 0 ] && [ "$tf_rc" -eq 0 ] && [ "$umap_rc" -eq 0 ]
