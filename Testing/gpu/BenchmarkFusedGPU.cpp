// mcvBenchmarkFusedGPU: the fused reduction chain on a 3-channel volume of
// about 1 G voxels on the GPU, and a 64 M-voxel case where the CPU (all cores) and the GPU
// coordinates are compared, the CPU run being the in-run baseline of the time ratio.
//
// The volume is the real brain (Colin27 T1 + AAL + Brodmann, 181 x 217 x 181) tiled
// periodically in memory to the requested size (float32 channels, as the loader gives them).
// The chain is the main job's: 24D features, Isomap (K = 10, L = 500) fitted on a reference
// sample of 10000 voxels, every voxel placed by its 3 nearest references. Stages:
//   statistics  FeatureBricks::prepare: features of every slab, column statistics (GPU run:
//               on the device, features/cuda/FusedPassesCuda.h; CPU run: on the CPU)
//   columns+sample  reduceDimension's column check and reference sample (two more passes
//               over the slabs' features, on the device in the GPU run), i.e. its total less
//               fit and placement
//   fit         Isomap on the sample (CPU)
//   placement   GPU: per slab channels up, features + normalisation + placement on the
//               device, coordinates down (features/cuda/FusedPlacementCuda.h); CPU: per slab
//               features + kd-tree/brute placement
// and the bytes moved between host and device and the device memory the GPU path held.
//
//   mcvBenchmarkFusedGPU [--voxels 1073741824] [--compare 67108864] [--reference 10000]
//                        [--device-mib 0] [--skip-large] [--skip-compare] [--skip-cpu]
//                        [--stage-only] [--merge-baseline]
//
// At the large size the whole chain runs on the GPU (statistics, column check and strata
// passes, features/cuda/FusedPassesCuda.h, and the placement; the fit on the CPU). --stage-only
// measures instead the GPU stage alone (channels up, features, normalisation, placement,
// coordinates down) with the statistics and fit of the compare size (the same brain, tiled);
// --merge-baseline adds that stage with every voxel searched (the in-run baseline of runs of
// equal voxels placed once).
//
// The placement's tile pruning (PlacementInput::pruneTiles) has its in-run baseline twice:
// the large GPU stage runs with and without it, and at the compare size the placement
// kernels alone place one slab's rows both ways (tiles scanned per row, same neighbours), and
// pruned with and without the warps' box check and the dot-product filter
// (PlacementInput::warpBoxFilter, dotProductFilter).
#include "BrainFeatures.h"
#include "CommandLine.h"
#include "ScaledBrain.h"
#include "DimensionReduction.h"
#include "FeatureBricks.h"
#include "ExactKnn.h"
#include "cuda/FusedPlacementCuda.h"
#include "cuda/DeviceProbe.h"
#include "cuda/OutOfSampleCuda.h"

#include <cuda_runtime.h>
#include <omp.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>
#include <vector>

namespace mt = mcv::testing;
using Clock = std::chrono::steady_clock;

namespace
{
double secondsSince(Clock::time_point t)
{
  return std::chrono::duration<double>(Clock::now() - t).count();
}

struct ChainRun
{
  mcv::ReductionResult result;
  mcv::FeatureBricks::DeviceStats device;
  mcv::FeatureResult prepared;  // offsets and scales of the statistics pass
  std::vector<float> refX;      // the reference sample's features (used columns)
  double statisticsS = 0, reduceS = 0, wholeS = 0;
};

// The placement alone (cuda::placeOutOfSample: rows up, kernels, coordinates down; every
// row searched) on the middle slab's normalised rows, with and without tile pruning.
void placementKernels(mcv::FeatureBricks& bricks, const mcv::ReductionResult& r, const std::vector<float>& refX)
{
  const std::size_t b = bricks.blockCount() / 2, first = bricks.blockBegin(b), n = bricks.blockBegin(b + 1) - first;
  const float* rows = bricks.block(b);
  std::vector<float> refY;
  for (std::int64_t id : r.referenceIndices)
    for (int c = 0; c < 3; ++c)
      refY.push_back(r.coordinates[static_cast<std::size_t>(id) * 3 + static_cast<std::size_t>(c)]);
  mcv::cuda::PlacementInput in;
  in.refX = refX.data();
  in.refY = refY.data();
  in.M = r.referenceIndices.size();
  in.D = static_cast<int>(r.usedColumns.size());
  in.d = 3;
  in.rows = rows;
  in.n = n;
  in.dim = bricks.cols();
  in.columns = in.D == bricks.cols() ? nullptr : r.usedColumns.data();
  in.distanceMargin = mcv::floatDistanceMargin(in.D);
  // Tile pruning 0: with both filters (the default), 1: with the warps' box check alone,
  // 2: with neither (per-row checks, every reference of a scanned tile measured exactly);
  // 3: every reference scanned.
  const char* names[] = { "both filters", "warp box check alone", "per-row checks alone", "every reference" };
  std::vector<float> out[4];
  std::vector<std::uint32_t> nb[4];
  mcv::cuda::PlacementStats st[4];
  for (int pass = 0; pass < 4; ++pass)
  {
    in.pruneTiles = pass < 3;
    in.warpBoxFilter = pass < 2;
    in.dotProductFilter = pass == 0;
    out[pass].resize(n * 3);
    nb[pass].resize(n * 3);
    std::string error;
    if (!mcv::cuda::placeOutOfSample(in, out[pass].data(), nb[pass].data(), {}, &st[pass], &error))
    {
      std::printf("  placement kernels failed: %s\n", error.c_str());
      return;
    }
  }
  std::printf("  placement kernels alone on slab %zu (%.2f M rows, every row searched; tiles of 32 scanned per row "
              "%.2f of %d):\n", b, n / 1e6, st[0].tilesPerRow, st[0].tiles);
  for (int pass = 0; pass < 4; ++pass)
  {
    std::printf("    %-22s %7.1f ms  (x%.2f of it)  tiles per row %6.2f  same neighbours and coordinates as every "
                "reference: %s\n",
      names[pass], st[pass].computeMs, st[pass].computeMs / st[0].computeMs, st[pass].tilesPerRow,
      nb[pass] == nb[3] && out[pass] == out[3] ? "yes" : "NO");
  }
  std::fflush(stdout);
}

ChainRun runChain(const mt::ScaledChannels& t, mcv::Device device, std::size_t reference, std::size_t deviceBytes)
{
  ChainRun run;
  mcv::FeatureOptions fo;
  fo.preset = mcv::FeaturePreset::TwentyFourD;
  fo.device = device; // the statistics pass runs where the chain does
  mcv::FeatureBricks bricks(t.views(), t.grid, fo);
  bricks.setDeviceBytes(deviceBytes);
  // The output array is the caller's, allocated and touched before the clock starts (as the
  // ParaView filter's array is allocated before the reduction).
  std::vector<float> coordinates(t.grid.voxelCount() * 3, 0.0f);
  const auto start = Clock::now();
  mcv::FeatureResult& prepared = run.prepared;
  if (!bricks.prepare(prepared))
  {
    std::printf("statistics pass failed: %s\n", prepared.error.c_str());
    std::exit(1);
  }
  run.statisticsS = secondsSince(start);
  const bool gpuStatistics = prepared.deviceUsed == mcv::Device::GPU;
  if (gpuStatistics)
    std::printf("  statistics pass (GPU): %.2f s\n", run.statisticsS);
  else
    std::printf("  statistics pass (CPU, %d slabs of %d slices): %.2f s\n", static_cast<int>(bricks.blockCount()),
      bricks.slabSlices(), run.statisticsS);
  std::fflush(stdout);
  mcv::ReductionOptions ro = mcv::testing::mainJobReduction(reference, device);
  ro.coordinatesOutput = coordinates.data();
  // When each stage of the reduction starts (its progress messages).
  std::string stage;
  ro.progress = [&](const char* name, double) {
    if (stage != name)
    {
      stage = name;
      std::printf("    %6.2f s  %s\n", secondsSince(start), name);
      std::fflush(stdout);
    }
  };
  const auto reduceStart = Clock::now();
  run.result = mcv::reduceDimension(bricks, ro);
  run.reduceS = secondsSince(reduceStart);
  run.wholeS = secondsSince(start);
  run.result.coordinates = std::move(coordinates);
  run.device = bricks.deviceStats();
  if (!run.result.ok())
  {
    std::printf("reduction failed: %s\n", run.result.error.c_str());
    std::exit(1);
  }
  for (const std::string& w : run.result.warnings)
    std::printf("  warning: %s\n", w.c_str());
  const double fit = run.result.fitMs / 1e3, place = run.result.placeMs / 1e3;
  std::printf("  columns + sample (2 passes, %d of them on the GPU): %.2f s\n",
    bricks.passesOnDevice() - (gpuStatistics ? 1 : 0), run.reduceS - fit - place);
  std::printf("  fit (Isomap on %zu, CPU): %.2f s\n", run.result.referenceIndices.size(), fit);
  std::printf("  placement (%s): %.2f s\n", run.result.deviceUsed == mcv::Device::GPU ? "GPU" : "CPU", place);
  if (run.result.deviceUsed == mcv::Device::GPU)
  {
    const auto& d = run.device;
    std::printf("    GPU slabs: %zu of %d slices; setup %.2f s, host conversion %.2f s, waiting for the device %.2f s\n",
      d.slabs, d.slabSlices, d.setupMs / 1e3, d.fillMs / 1e3, d.waitMs / 1e3);
    std::printf("    bytes host->device %.2f GB, device->host %.2f GB; device memory held %.2f GiB, card in use at peak "
                "%.2f GiB; pinned host %.2f GiB\n",
      d.bytesToDevice / 1e9, d.bytesFromDevice / 1e9, d.deviceBytes / 1073741824.0, d.deviceUsedPeak / 1073741824.0,
      d.pinnedBytes / 1073741824.0);
    const double voxels = static_cast<double>(run.result.coordinates.size() / 3);
    std::printf("    placement rate %.1f M voxels/s, %.2f ns/voxel\n", voxels / place / 1e6, place * 1e9 / voxels);
  }
  for (const mcv::FeatureBricks::DevicePass& p : bricks.devicePasses())
    std::printf("    GPU pass %-11s %6.2f s: setup %.2f s, host conversion %.2f s, waiting for the device %.2f s; %zu "
                "slabs of %d slices; %.2f GB up, %.2f GB down; %.2f GiB held\n",
      p.name.c_str(), p.stats.totalMs / 1e3, p.stats.setupMs / 1e3, p.stats.fillMs / 1e3, p.stats.waitMs / 1e3,
      p.stats.slabs, p.stats.slabSlices, p.stats.bytesToDevice / 1e9, p.stats.bytesFromDevice / 1e9,
      p.stats.deviceBytes / 1073741824.0);
  std::printf("  WHOLE CHAIN (statistics + reduction): %.2f s (%.1f ns/voxel)\n", run.wholeS,
    run.wholeS * 1e9 / static_cast<double>(t.grid.voxelCount()));
  std::fflush(stdout);
  // The reference features, for placing a larger volume with this fit (stageOnly).
  const std::vector<std::int64_t>& ids = run.result.referenceIndices;
  std::vector<std::size_t> index(ids.begin(), ids.end());
  std::vector<float> rows(index.size() * static_cast<std::size_t>(bricks.cols()));
  bricks.gather(index.data(), index.size(), rows.data());
  for (std::size_t i = 0; i < index.size(); ++i)
    for (int c : run.result.usedColumns)
      run.refX.push_back(rows[i * static_cast<std::size_t>(bricks.cols()) + static_cast<std::size_t>(c)]);
  if (run.result.deviceUsed == mcv::Device::GPU)
    placementKernels(bricks, run.result, run.refX);
  return run;
}

// The GPU stage alone (channels up, features + normalisation + placement on the device,
// coordinates down: what this path adds) on volume t, with the statistics pass's offsets and
// scales and the fit of `fitted` (a smaller tiling of the same brain, whose statistics are
// nearly the same). Reference i's embedding is the coordinate of its own voxel (the
// placement returns a reference's embedding exactly).
double stageOnly(
  const mt::ScaledChannels& t, const ChainRun& fitted, std::size_t deviceBytes, bool mergeEqualRows, bool pruneTiles)
{
  const mcv::ReductionResult& r = fitted.result;
  const std::size_t M = r.referenceIndices.size();
  std::vector<float> refY;
  for (std::int64_t id : r.referenceIndices)
    for (int c = 0; c < 3; ++c)
      refY.push_back(r.coordinates[static_cast<std::size_t>(id) * 3 + static_cast<std::size_t>(c)]);
  mcv::cuda::FusedPlacementSetup setup;
  setup.grid = t.grid;
  setup.channels = 3;
  mcv::FeatureOptions fo;
  fo.preset = mcv::FeaturePreset::TwentyFourD;
  setup.selection = mcv::FeatureSelection::forPreset(fo.preset, fo.custom);
  setup.cols = 24;
  setup.offset = fitted.prepared.columnOffset;
  setup.scale = fitted.prepared.columnScale;
  setup.deviceBytes = deviceBytes;
  setup.mergeEqualRows = mergeEqualRows;
  mcv::cuda::PlacementInput& in = setup.references;
  in.refX = fitted.refX.data();
  in.refY = refY.data();
  in.M = M;
  in.D = static_cast<int>(r.usedColumns.size());
  in.d = 3;
  in.dim = 24;
  in.columns = static_cast<int>(r.usedColumns.size()) == 24 ? nullptr : r.usedColumns.data();
  in.distanceMargin = mcv::floatDistanceMargin(in.D);
  in.pruneTiles = pruneTiles;
  const std::vector<mcv::ChannelView> views = t.views();
  const mcv::cuda::FusedChannelFill fill = [&](int c, std::size_t first, std::size_t count, float* values) {
    mcv::ChannelView v = views[static_cast<std::size_t>(c)];
    v.data = static_cast<const float*>(v.data) + first;
    return mcv::detail::channelToFloat(v, count, values, nullptr);
  };
  std::vector<float> out(t.grid.voxelCount() * 3);
  mcv::cuda::FusedPlacementStats st;
  std::size_t done = 0;
  std::string error;
  const auto start = Clock::now();
  const bool ok = mcv::cuda::placeFused(setup, fill, out.data(), {}, &st, &done, &error);
  const double s = secondsSince(start);
  if (!ok)
  {
    std::printf("GPU stage failed after %zu rows: %s\n", done, error.c_str());
    return 0;
  }
  const double voxels = static_cast<double>(t.grid.voxelCount());
  std::printf("  GPU stage (channels -> features -> placement -> coordinates%s%s): %.2f s, %.2f ns/voxel, %.1f M "
              "voxels/s\n",
    mergeEqualRows ? "" : ", every voxel searched", pruneTiles ? ", tile pruning" : ", every reference scanned", s,
    s * 1e9 / voxels, voxels / s / 1e6);
  std::printf("    %zu slabs of %d slices; setup %.2f s, host conversion %.2f s, waiting for the device %.2f s; %zu rows "
              "needed the exact scan\n",
    st.slabs, st.slabSlices, st.setupMs / 1e3, st.fillMs / 1e3, st.waitMs / 1e3, st.radiusScans);
  std::printf("    bytes host->device %.2f GB, device->host %.2f GB; device memory held %.2f GiB, card in use at peak %.2f "
              "GiB; pinned host %.2f GiB\n",
    st.bytesToDevice / 1e9, st.bytesFromDevice / 1e9, st.deviceBytes / 1073741824.0, st.deviceUsedPeak / 1073741824.0,
    st.pinnedBytes / 1073741824.0);
  const double perVoxelCpu = (fitted.statisticsS + fitted.reduceS - fitted.result.fitMs / 1e3 - fitted.result.placeMs / 1e3) /
    static_cast<double>(fitted.result.coordinates.size() / 3);
  std::printf("  the passes before the placement (statistics, columns, sample) cost %.1f ns/voxel at the smaller size: %.1f s at this "
              "size; fit %.2f s; whole chain estimate %.1f s\n",
    perVoxelCpu * 1e9, perVoxelCpu * voxels, fitted.result.fitMs / 1e3, perVoxelCpu * voxels + fitted.result.fitMs / 1e3 + s);
  std::fflush(stdout);
  return s;
}

} // namespace

int main(int argc, char** argv)
{
  const double large = mcv::testing::optionNumber(argc, argv, "--voxels", 1073741824.0);
  const double compare = mcv::testing::optionNumber(argc, argv, "--compare", 67108864.0);
  const std::size_t reference = static_cast<std::size_t>(mcv::testing::optionNumber(argc, argv, "--reference", 10000));
  const std::size_t deviceBytes = static_cast<std::size_t>(mcv::testing::optionNumber(argc, argv, "--device-mib", 0)) << 20;
  std::string why;
  if (!mcv::cuda::deviceUsable(&why))
  {
    std::printf("no usable GPU (%s): nothing to measure\n", why.c_str());
    return 0;
  }
  cudaDeviceProp prop{};
  cudaGetDeviceProperties(&prop, 0);
  std::printf("GPU %s (%.1f GiB), %d OpenMP threads\n", prop.name, prop.totalGlobalMem / 1073741824.0,
    omp_get_max_threads());
  if (!mt::haveBrain())
  {
    std::printf("brain volumes not in %s (scripts/fetch-data.sh)\n", mt::dataDir().c_str());
    return 1;
  }
  const std::vector<mt::Volume> brain = mt::loadBrain();

  // The compare size: GPU chain, then the CPU chain as the in-run baseline.
  ChainRun gpuSmall;
  if (!mcv::testing::hasFlag(argc, argv, "--skip-compare"))
  {
    const auto t0 = Clock::now();
    const mt::ScaledChannels t = mt::tileBrain(brain, compare);
    std::printf("\n== %d x %d x %d = %.1f M voxels (brain tiled in %.1f s): CPU (all cores) vs GPU\n", t.grid.dims[0],
      t.grid.dims[1], t.grid.dims[2], t.grid.voxelCount() / 1e6, secondsSince(t0));
    std::printf(" GPU:\n");
    gpuSmall = runChain(t, mcv::Device::GPU, reference, deviceBytes);
    if (!mcv::testing::hasFlag(argc, argv, "--skip-cpu"))
    {
      std::printf(" CPU (baseline):\n");
      const ChainRun cpu = runChain(t, mcv::Device::CPU, reference, 0);
      const auto mm = std::minmax_element(cpu.result.coordinates.begin(), cpu.result.coordinates.end());
      float diff = 0;
      std::size_t differing = 0;
      for (std::size_t i = 0; i < cpu.result.coordinates.size(); ++i)
      {
        const float e = std::abs(cpu.result.coordinates[i] - gpuSmall.result.coordinates[i]);
        diff = std::max(diff, e);
        differing += e > 1e-5f * (*mm.second - *mm.first);
      }
      std::printf("GPU vs CPU coordinates: max |difference| %.3g, range %.3g, max / range %.2g (%zu values over 1e-5 of "
                  "the range); same reference sample: %s\n",
        diff, *mm.second - *mm.first, diff / (*mm.second - *mm.first), differing,
        cpu.result.referenceIndices == gpuSmall.result.referenceIndices ? "yes" : "NO");
      std::printf("placement CPU / GPU: %.1f x; whole chain CPU / GPU: %.1f x\n",
        cpu.result.placeMs / gpuSmall.result.placeMs, cpu.wholeS / gpuSmall.wholeS);
    }
  }

  // The large size: the whole chain (every pass on the device), then with --stage-only or
  // --merge-baseline the GPU stage alone with the compare size's statistics and fit.
  if (!mcv::testing::hasFlag(argc, argv, "--skip-large"))
  {
    const auto t0 = Clock::now();
    const mt::ScaledChannels t = mt::tileBrain(brain, large);
    std::printf("\n== %d x %d x %d = %.3f G voxels (brain tiled in %.1f s), 3 float channels (%.1f GB): GPU\n",
      t.grid.dims[0], t.grid.dims[1], t.grid.dims[2], t.grid.voxelCount() / 1e9, secondsSince(t0),
      3.0 * 4.0 * t.grid.voxelCount() / 1e9);
    if (!mcv::testing::hasFlag(argc, argv, "--stage-only") || gpuSmall.refX.empty())
    {
      const ChainRun gpu = runChain(t, mcv::Device::GPU, reference, deviceBytes);
      std::printf("target: whole chain <= 10 s at 1 G voxels on one H100; measured %.2f s (GPU stage %.2f s)\n",
        gpu.wholeS, gpu.result.placeMs / 1e3);
    }
    if (!gpuSmall.refX.empty() &&
      (mcv::testing::hasFlag(argc, argv, "--stage-only") || mcv::testing::hasFlag(argc, argv, "--merge-baseline")))
    {
      const double pruned = stageOnly(t, gpuSmall, deviceBytes, true, true);
      // The in-run baseline of the tile pruning: every reference scanned for every row.
      const double all = stageOnly(t, gpuSmall, deviceBytes, true, false);
      if (pruned > 0 && all > 0)
        std::printf("GPU stage, every reference scanned / tile pruning: x%.2f (%.2f s / %.2f s, same call)\n",
          all / pruned, all, pruned);
      if (mcv::testing::hasFlag(argc, argv, "--merge-baseline"))
        stageOnly(t, gpuSmall, deviceBytes, false, true); // the in-run baseline of equal runs placed once
    }
  }
  return 0;
}
