#include "HarrisPipeline.h"

#include "cuda/CudaCheck.h"
#include "cuda/DeviceBuffer.cuh"
#include "HarrisArgs.cuh"
#include "HarrisBound.cuh"
#include "HarrisKernel.cuh"
#include "TopNSelect.cuh"

#include <algorithm>
#include <climits>
#include <vector>

namespace mcv
{
namespace cuda
{

using detail::fail;

namespace
{

// The grid as the kernel sees it: a single slice (one axis of size 1) becomes an x,y image
// with nz = 1 (the linear index is unchanged: the two extended axes keep their order).
struct KernelGrid
{
  int nx = 0, ny = 0, nz = 0;
  double sx = 1, sy = 1, sz = 1;
  bool planar = false;
};

KernelGrid kernelGrid(const ImageGrid& g)
{
  KernelGrid k;
  if (g.extendedAxes() == 2)
  {
    const int s = g.dims[0] == 1 ? 0 : (g.dims[1] == 1 ? 1 : 2);
    const int a0 = s == 0 ? 1 : 0, a1 = s == 2 ? 1 : 2;
    k.nx = g.dims[a0];
    k.ny = g.dims[a1];
    k.nz = 1;
    k.sx = g.spacing[a0];
    k.sy = g.spacing[a1];
    k.sz = g.spacing[s];
    k.planar = true;
    return k;
  }
  k.nx = g.dims[0];
  k.ny = g.dims[1];
  k.nz = g.dims[2];
  k.sx = g.spacing[0];
  k.sy = g.spacing[1];
  k.sz = g.spacing[2];
  return k;
}

} // namespace

detail::HarrisKernelArgs detail::harrisKernelArgs(const ImageGrid& grid, const HarrisParameters& params)
{
  const KernelGrid k = kernelGrid(grid);
  HarrisKernelArgs a;
  a.nx = k.nx;
  a.ny = k.ny;
  a.nz = k.nz;
  a.scaleX = static_cast<float>(0.5 / k.sx); // as the CPU path: 0.5 / spacing, in float
  a.scaleY = static_cast<float>(0.5 / k.sy);
  a.scaleZ = static_cast<float>(0.5 / k.sz);
  a.k = static_cast<float>(params.k);
  a.planar = k.planar ? 1 : 0;
  gaussianTaps(params, a.taps); // kernelWidth <= 7 taps (gpuUnsupportedReason)
  return a;
}

const char* gpuUnsupportedReason(const ImageGrid& grid, const HarrisParameters& params)
{
  const char* bad = checkHarrisParameters(params);
  if (bad && *bad)
  {
    return bad;
  }
  if (params.kernelWidth > 2 * detail::kHarrisMaxRadius + 1)
  {
    return "KernelWidth above 7 is not supported on the GPU";
  }
  for (int a = 0; a < 3; ++a)
  {
    if (grid.dims[a] < 1)
    {
      return "the grid has an axis without voxels";
    }
  }
  if (grid.extendedAxes() < 2)
  {
    return "the Harris response needs at least two axes with more than one voxel";
  }
  const KernelGrid k = kernelGrid(grid);
  if (static_cast<long long>(k.nx) * k.ny > INT_MAX)
  {
    return "a slice of more than 2^31 voxels is not supported on the GPU";
  }
  return "";
}

struct HarrisPipeline::Impl
{
  cudaStream_t stream = nullptr;
  cudaEvent_t ev[6] = {};
  bool ready = false;
  void* input = nullptr;
  std::size_t inputCap = 0;
  bool inputIsUint8 = false;
  bool haveVolume = false;
  ImageGrid grid;
  float* scores = nullptr;
  std::size_t scoresCap = 0;
  unsigned* rowMax = nullptr; // the row maxima of the last topN's Harris launch
  std::size_t rowMaxCap = 0;
  detail::RowMaxima rows;     // their layout (the kernel's x rows)
  detail::TopNSelector selector;
  // Exact pruning of topN (HarrisBound.cuh): the bounds per (tile, slice) and per block,
  // and the two phases' gates {lo, hi} (gates[0..1]: phase A, gates[2..3]: phase B).
  Pruning pruning = Pruning::Automatic;
  int pruneZChunk = 16, phaseShare = 64;
  unsigned* sliceMax = nullptr;
  float* blockBound = nullptr;
  float* gates = nullptr;
  std::size_t sliceMaxCap = 0, blockBoundCap = 0, gatesCap = 0;
  int prunedBlocks = 0; // blocks of the last pruned launch (0: the last topN was not pruned)
  int zChunk = 0, lastZChunk = 0;
  int variant = -1, histMode = 1;
  double uploadMs = 0;

  ~Impl()
  {
    freeBuffers();
    for (cudaEvent_t& e : ev)
    {
      if (e)
      {
        cudaEventDestroy(e);
      }
    }
    if (stream)
    {
      cudaStreamDestroy(stream);
    }
  }

  void freeBuffers()
  {
    if (stream)
    {
      (void)cudaStreamSynchronize(stream); // nothing may still use the buffers (errors: moot)
      (void)cudaGetLastError();
    }
    selector.release();
    if (input)
    {
      cudaFree(input);
    }
    if (scores)
    {
      cudaFree(scores);
    }
    for (void* b : { static_cast<void*>(rowMax), static_cast<void*>(sliceMax),
           static_cast<void*>(blockBound), static_cast<void*>(gates) })
    {
      if (b)
      {
        cudaFree(b);
      }
    }
    input = nullptr;
    scores = nullptr;
    rowMax = nullptr;
    sliceMax = nullptr;
    blockBound = nullptr;
    gates = nullptr;
    inputCap = scoresCap = rowMaxCap = sliceMaxCap = blockBoundCap = gatesCap = 0;
    prunedBlocks = 0;
    haveVolume = false;
  }

  bool init(std::string* error)
  {
    if (ready)
    {
      return true;
    }
    // Only what is missing: a failure half-way must not leak what was created.
    if (!stream)
    {
      MCV_CUDA_TRY(cudaStreamCreateWithFlags(&stream, cudaStreamNonBlocking));
    }
    for (cudaEvent_t& e : ev)
    {
      if (!e)
      {
        MCV_CUDA_TRY(cudaEventCreate(&e));
      }
    }
    ready = true;
    return true;
  }

  bool ensure(void*& buffer, std::size_t& capacity, std::size_t bytes, std::string* error)
  {
    return growDeviceBuffer(buffer, capacity, bytes, error);
  }

  bool ensureScores(std::size_t n, std::string* error)
  {
    return ensureTyped(scores, scoresCap, n, error);
  }

  float elapsed(int a, int b)
  {
    float ms = 0.f;
    return cudaEventElapsedTime(&ms, ev[a], ev[b]) == cudaSuccess ? ms : -1.f;
  }

  template <typename T>
  bool upload(const T* host, const ImageGrid& g, std::string* error)
  {
    haveVolume = false;
    if (!init(error))
    {
      return false;
    }
    if (!host)
    {
      return fail(error, "no volume given");
    }
    for (int a = 0; a < 3; ++a)
    {
      if (g.dims[a] < 1)
      {
        return fail(error, "the grid has an axis without voxels");
      }
    }
    const std::size_t bytes = g.voxelCount() * sizeof(T);
    if (!ensure(input, inputCap, bytes, error))
    {
      return false;
    }
    MCV_CUDA_TRY(cudaEventRecord(ev[0], stream));
    MCV_CUDA_TRY(cudaMemcpyAsync(input, host, bytes, cudaMemcpyHostToDevice, stream));
    MCV_CUDA_TRY(cudaEventRecord(ev[1], stream));
    MCV_CUDA_TRY(cudaEventSynchronize(ev[1]));
    uploadMs = elapsed(0, 1);
    grid = g;
    inputIsUint8 = sizeof(T) == 1;
    haveVolume = true;
    return true;
  }

  template <typename B>
  bool ensureTyped(B*& buffer, std::size_t& capacity, std::size_t count, std::string* error)
  {
    void* v = buffer;
    const bool ok = ensure(v, capacity, count * sizeof(B), error);
    buffer = static_cast<B*>(v);
    return ok;
  }

  // The Harris kernel on the volume; withHistogram: also the level-1 histogram and the row
  // maxima for the selection that follows.
  bool harris(const HarrisParameters& params, bool withHistogram, std::string* error)
  {
    detail::HarrisKernelArgs a;
    if (!prepare(params, withHistogram, a, error))
    {
      return false;
    }
    MCV_CUDA_TRY(launch(a, params, zChunk)); // the name makes it a "launch" injection point
    return true;
  }

  cudaError_t launch(const detail::HarrisKernelArgs& a, const HarrisParameters& params, int zc)
  {
    const int radius = params.kernelWidth / 2;
    return inputIsUint8
      ? detail::launchHarris(
          static_cast<const std::uint8_t*>(input), a, radius, zc, stream, &lastZChunk, variant)
      : detail::launchHarris(
          static_cast<const float*>(input), a, radius, zc, stream, &lastZChunk, variant);
  }

  // Whether topN prunes (HarrisBound.cuh): as set (Automatic: a volume of at least
  // pruneMinVoxels), on a 3D grid (the planar response has another bound), with the fast
  // selection (N <= kTopNFastMaxN) and a variant with the gate (not variant 8).
  bool canPrune(const HarrisParameters& params, int N) const
  {
    const bool wanted = pruning == Pruning::Always ||
      (pruning == Pruning::Automatic && grid.voxelCount() >= pruneMinVoxels);
    return wanted && N > 0 && N <= detail::kTopNFastMaxN && variant != detail::kHarrisPairsVariant &&
      !kernelGrid(grid).planar && params.kernelWidth / 2 <= detail::kHarrisMaxRadius;
  }

  // The pruned Harris launches of topN (HarrisBound.cuh's steps 1-4); the level-1 histogram
  // and the row maxima cover the computed blocks.
  bool harrisPruned(const HarrisParameters& params, int N, std::string* error)
  {
    detail::HarrisKernelArgs a;
    if (!prepare(params, true, a, error))
    {
      return false;
    }
    const int tilesX = (a.nx + detail::kHarrisTileX - 1) / detail::kHarrisTileX;
    const int tilesY = (a.ny + detail::kHarrisTileY - 1) / detail::kHarrisTileY;
    const int zc = std::max(1, std::min(pruneZChunk, a.nz));
    const int blocks = tilesX * tilesY * ((a.nz + zc - 1) / zc);
    const std::size_t slices = static_cast<std::size_t>(tilesX) * tilesY * a.nz;
    if (!ensureTyped(sliceMax, sliceMaxCap, slices, error) ||
      !ensureTyped(blockBound, blockBoundCap, static_cast<std::size_t>(blocks), error) ||
      !ensureTyped(gates, gatesCap, 4, error))
    {
      return false;
    }
    MCV_CUDA_TRY(cudaMemsetAsync(sliceMax, 0, slices * sizeof(unsigned), stream));
    MCV_CUDA_TRY(cudaMemsetAsync(rowMax, 0, rowMaxCount(a) * sizeof(unsigned), stream));
    const int radius = params.kernelWidth / 2;
    MCV_CUDA_TRY(inputIsUint8
        ? detail::launchTraceBound(static_cast<const std::uint8_t*>(input), a, radius, sliceMax, stream)
        : detail::launchTraceBound(static_cast<const float*>(input), a, radius, sliceMax, stream));
    MCV_CUDA_TRY(detail::launchBlockBounds(
      sliceMax, tilesX, tilesY, a.nz, zc, radius, a.k, blockBound, stream));
    // Phase A: 1 / phaseShare of the blocks, and at least 128 (a sweep at 256^3 and 512^3,
    // docs/benchmarks.md section 2: the top N's voxels lie in a few hundred blocks).
    const int wanted = std::min(blocks, std::max(blocks / std::max(1, phaseShare), 128));
    MCV_CUDA_TRY(detail::launchPhaseGate(blockBound, blocks, wanted, gates, gates + 2, stream));
    a.blockBound = blockBound;
    a.gate = gates;
    MCV_CUDA_TRY(launch(a, params, zc));
    MCV_CUDA_TRY(detail::launchTauGate(selector.level1Histogram(), N, gates + 2, stream));
    a.gate = gates + 2;
    MCV_CUDA_TRY(launch(a, params, zc));
    prunedBlocks = blocks;
    return true;
  }

  // Row maxima of a launch: one per 32-wide segment of each pair of x rows and slice.
  static std::size_t rowMaxCount(const detail::HarrisKernelArgs& a)
  {
    const int segments = (a.nx + detail::kHarrisTileX - 1) / detail::kHarrisTileX;
    return static_cast<std::size_t>((a.ny + 1) / 2) * a.nz * segments;
  }

  // The kernel's arguments for the uploaded volume, its score buffer, and with
  // withHistogram the level-1 histogram and the row maxima (rows) for the selection.
  bool prepare(const HarrisParameters& params, bool withHistogram, detail::HarrisKernelArgs& out,
    std::string* error)
  {
    if (!haveVolume)
    {
      return fail(error, "no volume on the GPU (uploadVolume first)");
    }
    const char* why = gpuUnsupportedReason(grid, params);
    if (*why)
    {
      return fail(error, why);
    }
    if (!ensureScores(grid.voxelCount(), error))
    {
      return false;
    }
    detail::HarrisKernelArgs a = detail::harrisKernelArgs(grid, params);
    a.response = scores;
    a.hist = withHistogram ? selector.level1Histogram() : nullptr;
    a.histMode = histMode;
    rows = detail::RowMaxima{};
    if (withHistogram)
    {
      // One maximum per 32-wide segment of each pair of x rows of the kernel's grid.
      if (!ensureTyped(rowMax, rowMaxCap, rowMaxCount(a), error))
      {
        return false;
      }
      a.rowMax = rowMax;
      rows.max = rowMax;
      rows.nx = a.nx;
      rows.ny = a.ny;
      rows.segmentsPerRow = (a.nx + detail::kHarrisTileX - 1) / detail::kHarrisTileX;
    }
    out = a;
    return true;
  }
};

HarrisPipeline::HarrisPipeline()
  : impl_(new Impl)
{
}

HarrisPipeline::~HarrisPipeline() = default;

bool HarrisPipeline::uploadVolume(const float* host, const ImageGrid& grid, std::string* error)
{
  FaultStage stage("harris");
  return impl_->upload(host, grid, error);
}

bool HarrisPipeline::uploadVolume(const std::uint8_t* host, const ImageGrid& grid, std::string* error)
{
  FaultStage stage("harris");
  return impl_->upload(host, grid, error);
}

bool HarrisPipeline::topN(const HarrisParameters& params, int N, InterestPoints& out,
  std::string* error, GpuStageTimings* timings)
{
  FaultStage stage("harris");
  Impl& p = *impl_;
  out.indices.clear();
  out.scores.clear();
  if (!p.init(error))
  {
    return false;
  }
  MCV_CUDA_TRY(cudaEventRecord(p.ev[2], p.stream));
  const bool prune = p.canPrune(params, N);
  p.prunedBlocks = 0;
  if (!p.selector.reset(N, p.stream, error) ||
    !(prune ? p.harrisPruned(params, N, error) : p.harris(params, true, error)))
  {
    return false;
  }
  MCV_CUDA_TRY(cudaEventRecord(p.ev[3], p.stream));
  p.selector.setScoresPartial(prune);
  bool selected = p.selector.select(
    p.scores, p.grid.voxelCount(), N, p.stream, out, error, p.ev[4], p.ev[5], &p.rows);
  p.selector.setScoresPartial(false);
  if (!selected && prune && p.selector.lastNeedsCompleteScores())
  {
    // The selection needs every score (its slow path): the whole volume, then again.
    p.prunedBlocks = 0;
    if (!p.selector.reset(N, p.stream, error) || !p.harris(params, true, error))
    {
      return false;
    }
    MCV_CUDA_TRY(cudaEventRecord(p.ev[3], p.stream));
    selected = p.selector.select(
      p.scores, p.grid.voxelCount(), N, p.stream, out, error, p.ev[4], p.ev[5], &p.rows);
  }
  if (!selected)
  {
    return false;
  }
  if (timings)
  {
    timings->uploadMs = p.uploadMs;
    timings->harrisMs = p.elapsed(2, 3);
    timings->selectMs = p.elapsed(3, 4);
    timings->downloadMs = p.elapsed(4, 5);
  }
  return true;
}

bool HarrisPipeline::response(const HarrisParameters& params, float* hostResponse, std::string* error)
{
  FaultStage stage("harris");
  Impl& p = *impl_;
  if (!hostResponse)
  {
    return fail(error, "no output buffer given");
  }
  if (!p.harris(params, false, error))
  {
    return false;
  }
  MCV_CUDA_TRY(cudaMemcpyAsync(hostResponse, p.scores, p.grid.voxelCount() * sizeof(float),
    cudaMemcpyDeviceToHost, p.stream));
  MCV_CUDA_TRY(cudaStreamSynchronize(p.stream));
  return true;
}

bool HarrisPipeline::selectFromScores(
  const float* hostScores, std::size_t count, int N, InterestPoints& out, std::string* error)
{
  FaultStage stage("harris");
  Impl& p = *impl_;
  out.indices.clear();
  out.scores.clear();
  if (!p.init(error))
  {
    return false;
  }
  if (count == 0)
  {
    return true;
  }
  if (!hostScores)
  {
    return fail(error, "no scores given");
  }
  if (!p.ensureScores(count, error))
  {
    return false;
  }
  MCV_CUDA_TRY(cudaMemcpyAsync(
    p.scores, hostScores, count * sizeof(float), cudaMemcpyHostToDevice, p.stream));
  return p.selector.reset(N, p.stream, error) &&
    p.selector.histogramLevel1(p.scores, count, p.stream, error) &&
    p.selector.select(p.scores, count, N, p.stream, out, error);
}

void HarrisPipeline::setZChunk(int zChunk)
{
  impl_->zChunk = zChunk;
}

void HarrisPipeline::setKernelVariant(int variant, int histogramMode)
{
  impl_->variant = variant;
  impl_->histMode = histogramMode;
}

int HarrisPipeline::kernelVariantCount()
{
  return detail::kHarrisVariants;
}

int HarrisPipeline::lastZChunk() const
{
  return impl_->lastZChunk;
}

double HarrisPipeline::lastUploadMs() const
{
  return impl_->uploadMs;
}

long long HarrisPipeline::lastListSize() const
{
  return impl_->selector.lastListSize();
}

bool HarrisPipeline::lastSelectUsedSlowPath() const
{
  return impl_->selector.lastUsedSlowPath();
}

void HarrisPipeline::setForceSlowSelect(bool force)
{
  impl_->selector.setForceSlowPath(force);
}

bool HarrisPipeline::timeHarrisKernel(
  const HarrisParameters& params, bool withHistogram, double* ms, std::string* error)
{
  FaultStage stage("harris");
  Impl& p = *impl_;
  if (!p.init(error) || !p.selector.reset(1, p.stream, error))
  {
    return false;
  }
  MCV_CUDA_TRY(cudaEventRecord(p.ev[2], p.stream));
  if (!p.harris(params, withHistogram, error))
  {
    return false;
  }
  MCV_CUDA_TRY(cudaEventRecord(p.ev[3], p.stream));
  MCV_CUDA_TRY(cudaEventSynchronize(p.ev[3]));
  if (ms)
  {
    *ms = p.elapsed(2, 3);
  }
  return true;
}

void HarrisPipeline::setPruning(Pruning mode, int zChunk, int phaseShare)
{
  impl_->pruning = mode;
  impl_->pruneZChunk = std::max(1, zChunk);
  impl_->phaseShare = std::max(1, phaseShare);
}

double HarrisPipeline::lastComputedBlockShare()
{
  Impl& p = *impl_;
  if (p.prunedBlocks <= 0)
  {
    return 1.0;
  }
  std::vector<float> bounds(static_cast<std::size_t>(p.prunedBlocks));
  float gates[4] = {};
  if (cudaMemcpyAsync(bounds.data(), p.blockBound, bounds.size() * sizeof(float),
        cudaMemcpyDeviceToHost, p.stream) != cudaSuccess ||
    cudaMemcpyAsync(gates, p.gates, sizeof(gates), cudaMemcpyDeviceToHost, p.stream) != cudaSuccess ||
    cudaStreamSynchronize(p.stream) != cudaSuccess)
  {
    return -1.0;
  }
  // The kernel's gate: gate[0] <= bound and not gate[1] <= bound.
  const auto in = [](float b, const float* g) { return b >= g[0] && !(b >= g[1]); };
  std::size_t computed = 0;
  for (float b : bounds)
  {
    computed += in(b, gates) || in(b, gates + 2);
  }
  return static_cast<double>(computed) / static_cast<double>(bounds.size());
}

std::size_t HarrisPipeline::deviceBytesHeld() const
{
  return impl_->inputCap + impl_->scoresCap;
}

void HarrisPipeline::release()
{
  impl_->freeBuffers();
}

} // namespace cuda
} // namespace mcv
