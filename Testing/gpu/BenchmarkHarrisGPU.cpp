// GPU benchmark of the best-viewpoint pipeline (Harris response + top-N) against the CPU
// path, both measured in this run on the same deterministic structured volumes (uint8
// opacity 0..255 on the GPU, the same values /255 in float on the CPU).
//
//   mcvBenchmarkGPU [--sizes 64,128,256,384,512] [--runs R] [--cpu-runs R] [--cpu-max N]
//                   [--sweep] [--variants] [--variant V] [--no-float] [--profile]
//                   [--slabs] [--slab-budget-mib M] [--slab-runs R] [--large N] [--dense]
//
// Per size: GPU stage times (CUDA events, median of R runs, volume resident on the GPU):
// harris (fused kernel + level-1 histogram), select (radix select + compaction + sort, with
// its one host synchronisation), download of the N points; "device" = their sum (the
// volume already on the GPU, points on the host); wall = the host's clock around the same
// call; "+H2D" adds the upload of the uint8 volume from pinned (and pageable) memory.
// CPU: computeHarrisResponseCPU + selectTopResponsesCPU (OpenMP, all cores), median of
// --cpu-runs runs, up to --cpu-max voxels per side. Agreement: top-N overlap between the
// GPU (uint8) and CPU (float) points, and the angle between their PCA best views.
// --sweep times the Harris kernel for several z chunks, --variants the kernel variants
// (z-loop unrolling, 3 blocks/SM, histogram atomics) from 256^3 up;
// --variant V runs every measurement with Harris kernel variant V instead of the default.
// The float path (the plugin's input) is timed too unless --no-float.
// --slabs also runs the z-slab path (HarrisSlabStream: volume on the host, streamed in
// slabs with halos, running top-N) under a forced device budget (--slab-budget-mib, default
// a quarter of what the whole volume needs), checks that its points equal the whole-volume
// points, and prints its stages and the ratio slabs / whole (volume resident, and with the
// whole volume's pageable upload). --large N streams an N^3 uint8 volume (tiles of the
// structured volume) whose whole-volume buffers exceed the device, under the default budget.
// Per size it prints the share of the Harris kernel's (tile, slice) steps that empty-space
// skipping leaves out on the volume. --dense raises every voxel by 1 (saturating at 255):
// no voxel is zero, nothing can be skipped (the skipping's worst case), and the CPU
// compares against the same raised values.
#include "cuda/DeviceProbe.h"
#include "cuda/HarrisCuda.h"
#include "cuda/HarrisPipeline.h"
#include "cuda/HarrisKernel.cuh"
#include "cuda/HarrisSlabStream.h"

#include "HarrisResponse.h"
#include "TopResponses.h"
#include "ViewFromPoints.h"

#include "CommandLine.h"
#include "PointComparison.h"
#include "TestVolumes.h"

#include <cuda_runtime.h>
#include <omp.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <sstream>
#include <string>
#include <unordered_set>
#include <vector>

namespace
{

namespace mt = mcv::testing;
using Clock = std::chrono::steady_clock;

struct Config
{
  std::vector<int> sizes{ 64, 128, 256, 384, 512 };
  int runs = 20;
  int cpuRuns = 10;
  int cpuMax = 256;
  bool sweep = false;
  bool variants = false;
  int variant = -1; // Harris kernel variant of every measurement (-1: the default)
  bool floatPath = true;
  bool profile = false; // one warm topN on the first size, then exit (for ncu)
  bool slabs = false;
  std::size_t slabBudgetMiB = 0; // 0: a quarter of the whole-volume need
  int slabRuns = 3;
  int large = 0;
  bool dense = false; // every voxel + 1: no empty space
  bool pruneSweep = false; // pruning's z chunk and phase share (HarrisBound.cuh)
};

struct SlabRow
{
  double total = -1, harris = 0, select = 0, upload = 0, staging = 0, merge = 0;
  int slabs = 0, owned = 0;
  bool same = false;
};

struct Row
{
  int n = 0;
  double harris = 0, select = 0, download = 0, device = 0, wall = 0;
  double h2dPinned = 0, h2dPageable = 0;
  double floatHarris = -1, floatDevice = -1, floatH2D = -1;
  SlabRow slabU8, slabF;
  double cpu = -1;
  double overlap = -1, angle = -1;
  int zChunk = 0;
  std::size_t points = 0;
  long long listSize = 0;
  bool slow = false;
};

double median(std::vector<double> v)
{
  if (v.empty())
  {
    return 0;
  }
  std::sort(v.begin(), v.end());
  const std::size_t m = v.size() / 2;
  return v.size() % 2 ? v[m] : 0.5 * (v[m - 1] + v[m]);
}

double msSince(Clock::time_point t)
{
  return std::chrono::duration<double, std::milli>(Clock::now() - t).count();
}

[[noreturn]] void die(const std::string& what)
{
  std::fprintf(stderr, "mcvBenchmarkGPU: %s\n", what.c_str());
  std::exit(1);
}

mcv::Vec3 bestView(const mcv::InterestPoints& p, const mcv::ImageGrid& g)
{
  return mcv::computeViewDirections(mcv::worldPositions(p, g)).best;
}

// A PyTorch pipeline (torch.gradient, conv3d, topk, SVD; H200, volume resident, median of
// 10; docs/benchmarks.md section 2), for orientation only: it was not measured in this run.
double pytorchAnchorMs(int n)
{
  switch (n)
  {
    case 64:
      return 1.9;
    case 128:
      return 3.8;
    case 256:
      return 20.5;
    case 384:
      return 68.0;
    case 512:
      return 160.0;
    default:
      return -1;
  }
}

// The slab path on a host volume: one warm-up, then the median of `runs` of each stage.
template <typename T>
SlabRow runSlabs(mcv::cuda::HarrisSlabStream& stream, const std::vector<T>& values,
  const mcv::ImageGrid& grid, std::size_t budget, int runs, const mcv::InterestPoints* whole)
{
  const mcv::HarrisParameters params;
  stream.setBudgetBytes(budget);
  mcv::InterestPoints pts;
  std::string error;
  if (!stream.topN(values.data(), grid, params, 2048, pts, &error))
    die(error);
  std::vector<double> tot, h, s, u, st, m;
  SlabRow row;
  for (int r = 0; r < runs; ++r)
  {
    mcv::cuda::SlabTimings t;
    if (!stream.topN(values.data(), grid, params, 2048, pts, &error, &t))
      die(error);
    tot.push_back(t.totalMs);
    h.push_back(t.harrisMs);
    s.push_back(t.selectMs);
    u.push_back(t.uploadMs);
    st.push_back(t.stagingMs);
    m.push_back(t.mergeMs);
    row.slabs = t.slabs;
    row.owned = t.ownedSlices;
  }
  row.total = median(tot);
  row.harris = median(h);
  row.select = median(s);
  row.upload = median(u);
  row.staging = median(st);
  row.merge = median(m);
  row.same = whole && pts.indices == whole->indices && pts.scores == whole->scores;
  return row;
}

// The share of the Harris kernel's work that empty-space skipping leaves out on an n^3
// uint8 volume (width 5, radius 2), over all (xy tile, slice) pairs of the grid: `products`
// the slices whose three input slices (z - 1, z, z + 1, clamped) are zero over the tile's
// input tile (the tile with a halo of 3, clamped), whose gradient products, x and y passes
// are not computed; `outputs` the slices whose five window slices (z - 2 .. z + 2, clamped)
// are all such, whose z pass and response are not computed. The kernel decides the same
// per block (a block's z chunk also reads a halo of slices that a neighbour owns).
struct EmptyShare
{
  double products = 0, outputs = 0;
};

EmptyShare emptyShare(const std::vector<std::uint8_t>& b, int n)
{
  constexpr int TX = mcv::cuda::detail::kHarrisTileX, TY = mcv::cuda::detail::kHarrisTileY, R = 2;
  const int tilesX = (n + TX - 1) / TX, tilesY = (n + TY - 1) / TY;
  long long skippedProducts = 0, skippedOutputs = 0;
  auto clampN = [n](int v) { return std::min(std::max(v, 0), n - 1); };
#pragma omp parallel for schedule(dynamic) reduction(+ : skippedProducts, skippedOutputs)
  for (int t = 0; t < tilesX * tilesY; ++t)
  {
    const int x0 = (t % tilesX) * TX, y0 = (t / tilesX) * TY;
    std::vector<char> nonZero(n), zeroProducts(n);
    for (int z = 0; z < n; ++z)
    {
      bool any = false;
      for (int y = y0 - R - 1; y < y0 + TY + R + 1 && !any; ++y)
        for (int x = x0 - R - 1; x < x0 + TX + R + 1 && !any; ++x)
          any = b[(static_cast<std::size_t>(z) * n + clampN(y)) * n + clampN(x)] != 0;
      nonZero[z] = any;
    }
    for (int z = 0; z < n; ++z)
    {
      zeroProducts[z] = !nonZero[clampN(z - 1)] && !nonZero[z] && !nonZero[clampN(z + 1)];
      skippedProducts += zeroProducts[z];
    }
    for (int z = 0; z < n; ++z)
    {
      bool all = true;
      for (int d = -R; d <= R; ++d)
        all = all && zeroProducts[clampN(z + d)];
      skippedOutputs += all;
    }
  }
  const double pairs = static_cast<double>(tilesX) * tilesY * n;
  return { skippedProducts / pairs, skippedOutputs / pairs };
}

void printSlabRow(const char* kind, const SlabRow& r, double wholeDevice, double wholeWithUpload,
  bool compared)
{
  std::printf("  slabs %s: %d slabs of %d slices: total %.2f ms (harris %.2f, select %.2f, upload "
              "span %.2f, host staging %.2f, merge %.2f); slabs/whole-resident %.1fx, "
              "slabs/(whole+pageable H2D) %.2fx; points %s\n",
    kind, r.slabs, r.owned, r.total, r.harris, r.select, r.upload, r.staging, r.merge,
    r.total / wholeDevice, r.total / wholeWithUpload,
    compared ? (r.same ? "identical to the whole-volume run" : "DIFFER from the whole-volume run")
             : "not compared");
}

} // namespace

int main(int argc, char** argv)
{
  Config cfg;
  for (int i = 1; i < argc; ++i)
  {
    const std::string a = argv[i];
    auto next = [&]() -> const char* {
      if (i + 1 >= argc)
        die("missing value after " + a);
      return argv[++i];
    };
    if (a == "--sizes")
      cfg.sizes = mt::integerList(next());
    else if (a == "--runs")
      cfg.runs = std::max(1, std::atoi(next()));
    else if (a == "--cpu-runs")
      cfg.cpuRuns = std::max(1, std::atoi(next()));
    else if (a == "--cpu-max")
      cfg.cpuMax = std::atoi(next());
    else if (a == "--sweep")
      cfg.sweep = true;
    else if (a == "--variants")
      cfg.variants = true;
    else if (a == "--variant")
      cfg.variant = std::atoi(next());
    else if (a == "--profile")
      cfg.profile = true;
    else if (a == "--no-float")
      cfg.floatPath = false;
    else if (a == "--slabs")
      cfg.slabs = true;
    else if (a == "--slab-budget-mib")
      cfg.slabBudgetMiB = static_cast<std::size_t>(std::atoll(next()));
    else if (a == "--slab-runs")
      cfg.slabRuns = std::max(1, std::atoi(next()));
    else if (a == "--large")
      cfg.large = std::atoi(next());
    else if (a == "--dense")
      cfg.dense = true;
    else if (a == "--prune-sweep")
      cfg.pruneSweep = true;
    else
      die("unknown argument " + a);
  }

  std::string why;
  if (!mcv::cuda::deviceUsable(&why))
  {
    std::printf("mcvBenchmarkGPU: no usable GPU (%s): nothing to measure.\n", why.c_str());
    return 0;
  }
  int device = 0;
  cudaGetDevice(&device);
  cudaDeviceProp prop{};
  cudaGetDeviceProperties(&prop, device);
  std::printf("GPU: %s, %d SMs, %.0f MB L2, compute %d.%d; CPU threads: %d\n", prop.name,
    prop.multiProcessorCount, prop.l2CacheSize / 1048576.0, prop.major, prop.minor,
    omp_get_max_threads());
  std::printf("N = 2048 interest points, Harris width 5, sigma 1.5, k 0.004; Harris kernel "
              "variant %s; GPU runs %d (median), CPU runs %d (median)\n\n",
    cfg.variant < 0 ? "default" : std::to_string(cfg.variant).c_str(), cfg.runs, cfg.cpuRuns);

  const mcv::HarrisParameters params;
  const int N = 2048;
  std::vector<Row> rows;
  mcv::cuda::HarrisPipeline pipeline;
  if (cfg.variant >= mcv::cuda::HarrisPipeline::kernelVariantCount())
    die("--variant: no such Harris kernel variant");
  pipeline.setKernelVariant(cfg.variant, 1);
  std::string error;

  for (int n : cfg.sizes)
  {
    Row row;
    row.n = n;
    const auto t0 = Clock::now();
    mt::Volume vol = mt::structuredVolume(n);
    std::vector<std::uint8_t> bytes(vol.values.size());
    for (std::size_t i = 0; i < bytes.size(); ++i)
    {
      bytes[i] = static_cast<std::uint8_t>(std::lround(vol.values[i] * 255.0f));
      if (cfg.dense)
      {
        bytes[i] = static_cast<std::uint8_t>(std::min(bytes[i] + 1, 255));
        vol.values[i] = static_cast<float>(bytes[i]) / 255.0f;
      }
    }
    const EmptyShare empty = emptyShare(bytes, n);
    std::printf("== %d^3%s (%zu voxels; volume made in %.0f ms); empty-space skipping leaves out "
                "%.1f %% of the (tile, slice) gradient/x/y steps and %.1f %% of the z pass + "
                "response steps\n",
      n, cfg.dense ? " dense (+1)" : "", bytes.size(), msSince(t0), 100.0 * empty.products,
      100.0 * empty.outputs);

    // Upload, pageable then pinned (the same bytes).
    std::vector<double> up;
    for (int r = 0; r < 5; ++r)
    {
      if (!pipeline.uploadVolume(bytes.data(), vol.grid, &error))
        die(error);
      up.push_back(pipeline.lastUploadMs());
    }
    row.h2dPageable = median(up);
    up.clear();
    const bool pinned = cudaHostRegister(bytes.data(), bytes.size(), cudaHostRegisterDefault) == cudaSuccess;
    (void)cudaGetLastError();
    for (int r = 0; r < 5; ++r)
    {
      if (!pipeline.uploadVolume(bytes.data(), vol.grid, &error))
        die(error);
      up.push_back(pipeline.lastUploadMs());
    }
    row.h2dPinned = pinned ? median(up) : -1;
    if (pinned)
      cudaHostUnregister(bytes.data());

    // Device-resident pipeline.
    mcv::InterestPoints gpu;
    pipeline.setZChunk(0);
    if (cfg.profile)
    {
      for (int r = 0; r < 3; ++r)
        if (!pipeline.topN(params, N, gpu, &error))
          die(error);
      std::printf("profile: 3 topN calls on %d^3 (the last one is warm), list %lld\n", n,
        pipeline.lastListSize());
      return 0;
    }
    for (int r = 0; r < 3; ++r) // warm-up (allocations, CUB temporaries)
    {
      if (!pipeline.topN(params, N, gpu, &error))
        die(error);
    }
    std::vector<double> h, s, d, dev, wall;
    for (int r = 0; r < cfg.runs; ++r)
    {
      mcv::cuda::GpuStageTimings t;
      const auto w0 = Clock::now();
      if (!pipeline.topN(params, N, gpu, &error, &t))
        die(error);
      wall.push_back(msSince(w0));
      h.push_back(t.harrisMs);
      s.push_back(t.selectMs);
      d.push_back(t.downloadMs);
      dev.push_back(t.harrisMs + t.selectMs + t.downloadMs);
    }
    row.harris = median(h);
    row.select = median(s);
    row.download = median(d);
    row.device = median(dev);
    row.wall = median(wall);
    row.zChunk = pipeline.lastZChunk();
    row.points = gpu.size();
    row.listSize = pipeline.lastListSize();
    row.slow = pipeline.lastSelectUsedSlowPath();
    std::printf("  GPU uint8: harris %.3f ms, select %.3f ms, download %.3f ms, device total "
                "%.3f ms (wall %.3f ms), zChunk %d, %zu points, list %lld (%s path)\n",
      row.harris, row.select, row.download, row.device, row.wall, row.zChunk, row.points,
      row.listSize, row.slow ? "slow" : "fast");
    {
      // Exact pruning (HarrisBound.cuh) always against never, alternated
      // run by run in this call, and whether both give the same points.
      std::vector<double> on, off;
      mcv::InterestPoints pruned, whole;
      for (int r = 0; r < cfg.runs; ++r)
      {
        for (const bool prune : { true, false })
        {
          pipeline.setPruning(prune ? mcv::cuda::HarrisPipeline::Pruning::Always : mcv::cuda::HarrisPipeline::Pruning::Never);
          mcv::cuda::GpuStageTimings t;
          if (!pipeline.topN(params, N, prune ? pruned : whole, &error, &t))
            die(error);
          (prune ? on : off).push_back(t.harrisMs + t.selectMs + t.downloadMs);
        }
      }
      pipeline.setPruning(mcv::cuda::HarrisPipeline::Pruning::Always);
      if (!pipeline.topN(params, N, pruned, &error))
        die(error);
      const double share = pipeline.lastComputedBlockShare();
      pipeline.setPruning(mcv::cuda::HarrisPipeline::Pruning::Automatic);
      std::printf("  pruning: device total %.3f ms pruned, %.3f ms whole volume (x%.2f), %.1f %% "
                  "of the blocks computed, same points and scores: %s\n",
        median(on), median(off), median(off) / median(on), 100.0 * share,
        pruned.indices == whole.indices && pruned.scores == whole.scores ? "yes" : "NO");
      if (cfg.pruneSweep)
      {
        std::printf("  pruning sweep (device total ms, median of %d; computed blocks):", cfg.runs);
        for (int zc : { 4, 8, 16 })
          for (int share : { 16, 64, 256 })
          {
            pipeline.setPruning(mcv::cuda::HarrisPipeline::Pruning::Always, zc, share);
            std::vector<double> ts;
            for (int r = 0; r < cfg.runs; ++r)
            {
              mcv::cuda::GpuStageTimings t;
              if (!pipeline.topN(params, N, pruned, &error, &t))
                die(error);
              ts.push_back(t.harrisMs + t.selectMs + t.downloadMs);
            }
            std::printf("  z%d/1:%d %.3f (%.1f %%)", zc, share, median(ts),
              100.0 * pipeline.lastComputedBlockShare());
          }
        std::printf("\n");
        pipeline.setPruning(mcv::cuda::HarrisPipeline::Pruning::Automatic);
      }
    }
    {
      double withHist = 0, without = 0;
      std::vector<double> a, b;
      for (int r = 0; r < cfg.runs; ++r)
      {
        if (!pipeline.timeHarrisKernel(params, true, &withHist, &error) ||
          !pipeline.timeHarrisKernel(params, false, &without, &error))
          die(error);
        a.push_back(withHist);
        b.push_back(without);
      }
      std::printf("  Harris kernel alone: %.3f ms with the level-1 histogram, %.3f ms without\n",
        median(a), median(b));
    }
    if (cfg.variants && n >= 256)
    {
      std::printf("  kernel variants (harris+histogram ms, median of %d):", cfg.runs);
      for (int v = 0; v < mcv::cuda::HarrisPipeline::kernelVariantCount(); ++v)
        for (int hm = 0; hm < 2; ++hm)
        {
          pipeline.setKernelVariant(v, hm);
          std::vector<double> hs;
          for (int r = 0; r < cfg.runs; ++r)
          {
            double ms = 0;
            if (!pipeline.timeHarrisKernel(params, true, &ms, &error))
              die(error);
            hs.push_back(ms);
          }
          std::printf("  v%d%s %.3f", v, hm ? "a" : "m", median(hs));
        }
      std::printf("  (v: bit0 unrolled, bit1 3 blocks/SM, bit2 position table + 2 barriers; v8: v5 with two slices per round; m: match_any, a: plain atomics)\n");
      pipeline.setKernelVariant(cfg.variant, 1);
    }
    std::printf("  H2D uint8: pinned %.3f ms, pageable %.3f ms\n", row.h2dPinned, row.h2dPageable);

    if (cfg.sweep)
    {
      std::printf("  z-chunk sweep (harris ms, median of %d):", cfg.runs);
      for (int zc : { 4, 8, 16, 32, 64, 128, 256, 512 })
      {
        if (zc > n)
          continue;
        pipeline.setZChunk(zc);
        std::vector<double> hs;
        mcv::InterestPoints tmp;
        for (int r = 0; r < cfg.runs; ++r)
        {
          mcv::cuda::GpuStageTimings t;
          if (!pipeline.topN(params, N, tmp, &error, &t))
            die(error);
          hs.push_back(t.harrisMs);
        }
        std::printf("  %d: %.3f", zc, median(hs));
      }
      std::printf("  (auto %d: %.3f)\n", row.zChunk, row.harris);
      pipeline.setZChunk(0);
    }

    // Float input (what the plugin passes), same values / 255.
    mcv::InterestPoints fp;
    if (cfg.floatPath)
    {
      if (!pipeline.uploadVolume(vol.values.data(), vol.grid, &error))
        die(error);
      row.floatH2D = pipeline.lastUploadMs();
      for (int r = 0; r < 2; ++r)
        if (!pipeline.topN(params, N, fp, &error))
          die(error);
      std::vector<double> fh, fd;
      for (int r = 0; r < cfg.runs; ++r)
      {
        mcv::cuda::GpuStageTimings t;
        if (!pipeline.topN(params, N, fp, &error, &t))
          die(error);
        fh.push_back(t.harrisMs);
        fd.push_back(t.harrisMs + t.selectMs + t.downloadMs);
      }
      row.floatHarris = median(fh);
      row.floatDevice = median(fd);
      std::printf("  GPU float: harris %.3f ms, device total %.3f ms, H2D (pageable) %.3f ms; "
                  "overlap with uint8 %.4f\n",
        row.floatHarris, row.floatDevice, row.floatH2D, mcv::testing::indexOverlap(fp, gpu));
    }

    // The z-slab path on the same host volumes under a forced budget.
    if (cfg.slabs)
    {
      mcv::cuda::HarrisSlabStream stream;
      auto budgetFor = [&](int bytesPerValue) {
        return cfg.slabBudgetMiB ? cfg.slabBudgetMiB << 20
                                 : mcv::cuda::wholeVolumeDeviceBytes(vol.grid, bytesPerValue) / 4;
      };
      row.slabU8 = runSlabs(stream, bytes, vol.grid, budgetFor(1), cfg.slabRuns, &gpu);
      printSlabRow("uint8", row.slabU8, row.device, row.device + row.h2dPageable, true);
      if (cfg.floatPath)
      {
        row.slabF = runSlabs(stream, vol.values, vol.grid, budgetFor(4), cfg.slabRuns, &fp);
        printSlabRow("float", row.slabF, row.floatDevice, row.floatDevice + row.floatH2D, true);
      }
    }

    // CPU path, same volume (float values = bytes / 255).
    if (n <= cfg.cpuMax)
    {
      std::vector<float> response(vol.values.size());
      mcv::InterestPoints cpu;
      std::vector<double> times;
      const int cpuRuns = n >= 256 ? std::min(cfg.cpuRuns, 5) : cfg.cpuRuns;
      for (int r = 0; r < cpuRuns; ++r)
      {
        const auto c0 = Clock::now();
        mcv::computeHarrisResponseCPU(vol.values.data(), vol.grid, params, response.data());
        cpu = mcv::selectTopResponsesCPU(response.data(), response.size(), N);
        times.push_back(msSince(c0));
      }
      row.cpu = median(times);
      row.overlap = mcv::testing::indexOverlap(gpu, cpu);
      row.angle = mcv::axisAngleDegrees(bestView(gpu, vol.grid), bestView(cpu, vol.grid));
      std::printf("  CPU: %.2f ms (median of %d); CPU/GPU-device %.0fx; top-N overlap %.4f; "
                  "best-view angle %.4f deg\n",
        row.cpu, cpuRuns, row.cpu / row.device, row.overlap, row.angle);
    }
    rows.push_back(row);
    std::printf("\n");
  }
  pipeline.release();

  SlabRow largeRow;
  std::size_t largeBudget = 0, largeWhole = 0;
  if (cfg.large > 0)
  {
    // N^3 uint8 from 4^3 tiles of the structured volume of side N/4 (copies tie exactly:
    // the index order decides, as everywhere). Default budget: free memory minus the margin.
    const int n = cfg.large, tile = std::max(8, cfg.large / 4);
    const auto t0 = Clock::now();
    const mt::Volume tv = mt::structuredVolume(tile);
    std::vector<std::uint8_t> tb(tv.values.size());
    for (std::size_t i = 0; i < tb.size(); ++i)
      tb[i] = static_cast<std::uint8_t>(std::lround(tv.values[i] * 255.0f));
    const mcv::ImageGrid grid = mt::makeGrid(n, n, n);
    std::vector<std::uint8_t> big(grid.voxelCount());
#pragma omp parallel for schedule(static)
    for (long long z = 0; z < n; ++z)
      for (int y = 0; y < n; ++y)
      {
        const std::uint8_t* src = tb.data() +
          (static_cast<std::size_t>(z % tile) * tile + static_cast<std::size_t>(y % tile)) * tile;
        std::uint8_t* dst = big.data() + (static_cast<std::size_t>(z) * n + y) * n;
        for (int x = 0; x < n; x += tile)
          std::memcpy(dst + x, src, static_cast<std::size_t>(std::min(tile, n - x)));
      }
    largeBudget = mcv::cuda::deviceBudgetBytes(0);
    largeWhole = mcv::cuda::wholeVolumeDeviceBytes(grid, 1);
    std::printf("== large %d^3 uint8 (%.2f G voxels, %.1f GB on the host; made in %.0f ms): the "
                "whole-volume path needs %.1f GB of device memory, the budget (free minus margin) "
                "is %.1f GB: %s\n",
      n, grid.voxelCount() / 1e9, grid.voxelCount() / 1e9, msSince(t0), largeWhole / 1e9,
      largeBudget / 1e9, largeWhole > largeBudget ? "streamed in slabs" : "it would fit whole");
    mcv::cuda::HarrisSlabStream stream;
    largeRow = runSlabs(stream, big, grid, largeBudget, std::min(cfg.slabRuns, 2), nullptr);
    std::printf("  slabs uint8: %d slabs of %d slices: total %.1f ms (harris %.1f, select %.1f, "
                "upload span %.1f, host staging %.1f, merge %.1f); %.3f ns per voxel\n\n",
      largeRow.slabs, largeRow.owned, largeRow.total, largeRow.harris, largeRow.select,
      largeRow.upload, largeRow.staging, largeRow.merge, largeRow.total * 1e6 / grid.voxelCount());
  }

  std::printf("Best-viewpoint GPU pipeline (Harris 5^3 + top-2048), %s, times in ms "
              "(medians)\n",
    prop.name);
  std::printf("%6s %8s %8s %8s %9s %9s %9s %10s %10s %9s %8s %8s %9s\n", "size", "harris",
    "select", "device", "wall", "+H2Dpin", "+H2Dpage", "float-dev", "CPU", "CPU/GPU", "overlap",
    "angle", "torch-ref");
  for (const Row& r : rows)
  {
    char cpu[32] = "-", ratio[32] = "-", ov[32] = "-", ang[32] = "-", fl[32] = "-", ref[32] = "-";
    if (r.cpu >= 0)
    {
      std::snprintf(cpu, sizeof(cpu), "%.1f", r.cpu);
      std::snprintf(ratio, sizeof(ratio), "%.0fx", r.cpu / r.device);
      std::snprintf(ov, sizeof(ov), "%.4f", r.overlap);
      std::snprintf(ang, sizeof(ang), "%.3f", r.angle);
    }
    if (r.floatDevice >= 0)
      std::snprintf(fl, sizeof(fl), "%.3f", r.floatDevice);
    if (pytorchAnchorMs(r.n) > 0)
      std::snprintf(ref, sizeof(ref), "%.1f", pytorchAnchorMs(r.n));
    std::printf("%5d^3 %8.3f %8.3f %8.3f %9.3f %9.3f %9.3f %10s %10s %9s %8s %8s %9s\n", r.n,
      r.harris, r.select, r.device, r.wall, r.device + r.h2dPinned, r.device + r.h2dPageable, fl,
      cpu, ratio, ov, ang, ref);
  }
  std::printf("device = harris + select + download (volume resident, CUDA events); wall = host "
              "clock of the same call;\n+H2Dpin/+H2Dpage add the uint8 upload from pinned/pageable "
              "memory; float-dev = device total with float input;\nCPU = OpenMP "
              "computeHarrisResponseCPU + selectTopResponsesCPU, this run; overlap/angle: GPU vs CPU "
              "top-N set and PCA best view;\ntorch-ref = a PyTorch pipeline on an H200 "
              "(not measured in this run).\n");
  if (cfg.slabs)
  {
    std::printf("\nZ-slab path (volume on the host, forced budget), total ms (medians of %d), "
                "ratio to the whole-volume path of the same run\n", cfg.slabRuns);
    std::printf("%6s %5s %7s %9s %9s %9s %9s %10s %10s %10s %10s\n", "size", "type", "slabs",
      "total", "harris", "select", "staging", "/resident", "/+H2Dpin", "/+H2Dpage", "ns/voxel");
    for (const Row& r : rows)
    {
      const double voxels = static_cast<double>(r.n) * r.n * r.n;
      for (int f = 0; f < 2; ++f)
      {
        const SlabRow& s = f ? r.slabF : r.slabU8;
        if (s.total < 0)
          continue;
        const double dev = f ? r.floatDevice : r.device;
        const double up = f ? r.floatH2D : r.h2dPageable;
        char pin[32] = "-"; // the pinned upload is timed for uint8 only
        if (!f && r.h2dPinned > 0)
          std::snprintf(pin, sizeof(pin), "%.2fx", s.total / (dev + r.h2dPinned));
        std::printf("%5d^3 %5s %7d %9.2f %9.2f %9.2f %9.2f %9.1fx %10s %9.2fx %10.3f%s\n", r.n,
          f ? "float" : "uint8", s.slabs, s.total, s.harris, s.select, s.staging, s.total / dev,
          pin, s.total / (dev + up), s.total * 1e6 / voxels, s.same ? "" : "  POINTS DIFFER");
      }
    }
  }
  if (largeRow.total >= 0)
  {
    const double voxels = static_cast<double>(cfg.large) * cfg.large * cfg.large;
    std::printf("%5d^3 %5s %7d %9.2f %9.2f %9.2f %9.2f %10s %10s %10s %10.3f  (whole needs %.1f GB, "
                "budget %.1f GB)\n",
      cfg.large, "uint8", largeRow.slabs, largeRow.total, largeRow.harris, largeRow.select,
      largeRow.staging, "-", "-", "-", largeRow.total * 1e6 / voxels, largeWhole / 1e9, largeBudget / 1e9);
  }
  return 0;
}
