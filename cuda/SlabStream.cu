// The slab stream of the fused passes: per slab, channels up through pinned staging, raw
// features (and the normalisation) on the device, then the pass's own work; two streams.
#include "SlabStream.cuh"

#include "CudaCheck.h"
#include "FeatureKernels.cuh"

#include <algorithm>

namespace mcv
{
namespace cuda
{

namespace
{

constexpr int kThreads = 256;

using Clock = std::chrono::steady_clock;
double msSince(Clock::time_point t)
{
  return std::chrono::duration<double, std::milli>(Clock::now() - t).count();
}

// Rows [0, count) of the slab: (x - offset) * scale as applyNormalizationCPU rounds it; a
// row with a non-finite channel value (checked only when the slab has one) is zeros.
// channels: C planes of `stride` floats; the slab's first row is voxel vBegin of each.
__global__ void normalizeSlabKernel(float* __restrict__ features, std::int64_t count, int cols,
  const double* __restrict__ offset, const double* __restrict__ scale, const float* __restrict__ channels,
  int C, std::int64_t stride, std::int64_t vBegin, int checkRows)
{
  const std::int64_t elements = count * cols;
  for (std::int64_t e = blockIdx.x * static_cast<std::int64_t>(blockDim.x) + threadIdx.x; e < elements;
       e += static_cast<std::int64_t>(gridDim.x) * blockDim.x)
  {
    const std::int64_t row = e / cols;
    const int col = static_cast<int>(e - row * cols);
    bool bad = false;
    if (checkRows)
    {
      for (int c = 0; c < C; ++c)
      {
        bad = bad || !isfinite(channels[c * stride + vBegin + row]);
      }
    }
    const double sc = scale[col];
    const float y = __double2float_rn(__dmul_rn(__dsub_rn(static_cast<double>(features[e]), offset[col]), sc));
    features[e] = (!bad && sc != 0.0 && isfinite(y)) ? y : 0.0f;
  }
}

std::size_t sliceVoxels(const ImageGrid& g)
{
  return static_cast<std::size_t>(g.dims[0]) * static_cast<std::size_t>(g.dims[1]);
}

// Device bytes per slot for a slab of `slices` slices: channels with ghosts, features, the pass's.
std::size_t slotBytes(const SlabStreamSetup& s, int slices)
{
  const std::size_t nxy = sliceVoxels(s.grid), rows = static_cast<std::size_t>(slices) * nxy;
  return static_cast<std::size_t>(s.channels) * (rows + 2 * nxy) * sizeof(float) +
    rows * (static_cast<std::size_t>(s.cols) * sizeof(float) + s.pass.perRowDevice) +
    (s.pass.perSlotDevice ? s.pass.perSlotDevice(rows) : 0);
}

} // namespace

int slabBlocksFor(std::int64_t work)
{
  const std::int64_t b = (work + kThreads - 1) / kThreads;
  return static_cast<int>(std::max<std::int64_t>(1, std::min<std::int64_t>(b, 65535 * 16)));
}

std::size_t SlabStream::bytesFor(const SlabStreamSetup& setup, int slices)
{
  return setup.pass.fixedDevice + 2 * static_cast<std::size_t>(setup.cols) * sizeof(double) +
    kSlabSlots * slotBytes(setup, std::max(1, slices));
}

std::size_t SlabStream::slabRows() const
{
  return static_cast<std::size_t>(slices_) * sliceVoxels(setup_.grid);
}

SlabStream::~SlabStream()
{
  release();
}

void SlabStream::release()
{
  for (cudaStream_t s : streams_)
  {
    if (s)
    {
      cudaStreamSynchronize(s);
    }
  }
  for (int i = 0; i < kSlabSlots; ++i)
  {
    cudaFree(channels_[i]);
    cudaFree(features_[i]);
    cudaFreeHost(stageIn_[i]);
    cudaFreeHost(passPinned_[i]);
    if (streams_[i])
    {
      cudaStreamDestroy(streams_[i]);
    }
    channels_[i] = features_[i] = stageIn_[i] = nullptr;
    passPinned_[i] = nullptr;
    streams_[i] = nullptr;
  }
  cudaFree(columnParams_);
  columnParams_ = nullptr;
  (void)cudaGetLastError(); // a failed run's error must not leak into the next call
}

bool SlabStream::open(const SlabStreamSetup& setup, std::string* error)
{
  release();
  setup_ = setup;
  stats_ = SlabStreamStats{};
  opened_ = Clock::now();
  const ImageGrid& grid = setup.grid;
  const int F = setup.cols;
  const bool normalise = !setup.offset.empty();
  if (setup.channels < 1 || F != setup.channels * setup.selection.perChannel() ||
    (normalise && (setup.offset.size() != static_cast<std::size_t>(F) || setup.scale.size() != static_cast<std::size_t>(F))))
  {
    return detail::fail(error, "invalid arguments of the GPU slab stream");
  }
  std::size_t freeBytes = 0, cardBytes = 0;
  MCV_CUDA_TRY(cudaMemGetInfo(&freeBytes, &cardBytes));
  std::size_t budget = setup.deviceBytes;
  if (budget == 0)
  {
    const std::size_t margin = std::max<std::size_t>(std::size_t(512) << 20, cardBytes / 16);
    budget = freeBytes > margin ? freeBytes - margin : 0;
  }
  if (bytesFor(setup, 1) > budget)
  {
    return detail::fail(error, "the GPU fused pass needs " + std::to_string(bytesFor(setup, 1) >> 20) +
        " MiB of device memory for a slab of one slice; it may use " + std::to_string(budget >> 20) + " MiB");
  }
  const std::size_t nxy = sliceVoxels(grid);
  const int maxSlices = static_cast<int>(std::max<std::size_t>(1,
    std::min<std::size_t>(static_cast<std::size_t>(std::max(1, grid.dims[2])), setup.maxSlabVoxels / std::max<std::size_t>(1, nxy))));
  // The largest thickness that fits: bytes grow linearly with it (bisection is exact).
  int lo = 1, hi = maxSlices;
  while (lo < hi)
  {
    const int mid = lo + (hi - lo + 1) / 2;
    if (bytesFor(setup, mid) <= budget)
    {
      lo = mid;
    }
    else
    {
      hi = mid - 1;
    }
  }
  slices_ = lo;
  plane_ = static_cast<std::size_t>(slices_ + 2) * nxy;
  const std::size_t rows = slabRows(), C = static_cast<std::size_t>(setup.channels);
  for (int i = 0; i < kSlabSlots; ++i)
  {
    MCV_CUDA_TRY(cudaStreamCreateWithFlags(&streams_[i], cudaStreamNonBlocking));
    MCV_CUDA_TRY(cudaMalloc(&channels_[i], C * plane_ * sizeof(float)));
    MCV_CUDA_TRY(cudaMalloc(&features_[i], rows * static_cast<std::size_t>(F) * sizeof(float)));
    MCV_CUDA_TRY(cudaMallocHost(&stageIn_[i], C * plane_ * sizeof(float)));
    if (setup.pass.perRowPinned > 0)
    {
      MCV_CUDA_TRY(cudaMallocHost(&passPinned_[i], rows * setup.pass.perRowPinned));
    }
  }
  MCV_CUDA_TRY(cudaMalloc(&columnParams_, 2 * static_cast<std::size_t>(F) * sizeof(double)));
  if (normalise)
  {
    MCV_CUDA_TRY(cudaMemcpy(columnParams_, setup.offset.data(), F * sizeof(double), cudaMemcpyHostToDevice));
    MCV_CUDA_TRY(cudaMemcpy(columnParams_ + F, setup.scale.data(), F * sizeof(double), cudaMemcpyHostToDevice));
    stats_.bytesToDevice += 2 * static_cast<std::size_t>(F) * sizeof(double);
  }
  stats_.slabSlices = slices_;
  stats_.deviceBytes = bytesFor(setup, slices_);
  stats_.pinnedBytes = kSlabSlots * (C * plane_ * sizeof(float) + rows * setup.pass.perRowPinned);
  return true;
}

bool SlabStream::run(const FusedChannelFill& fill, const Launch& launch, const Done& done, std::string* error)
{
  const ImageGrid& grid = setup_.grid;
  const int C = setup_.channels, F = setup_.cols, nz = grid.dims[2], S = slices_;
  const std::size_t nxy = sliceVoxels(grid);
  const bool normalise = !setup_.offset.empty();
  {
    std::size_t freeNow = 0, cardBytes = 0;
    MCV_CUDA_TRY(cudaMemGetInfo(&freeNow, &cardBytes));
    stats_.deviceUsedPeak = std::max(stats_.deviceUsedPeak, cardBytes - freeNow);
  }
  stats_.setupMs = msSince(opened_);

  Slab pending[kSlabSlots];
  bool busy[kSlabSlots] = { false, false };
  // Waits for slot i's slab and hands it to `done`; slabs finish in order.
  auto finish = [&](int i) -> bool {
    if (!busy[i])
    {
      return true;
    }
    const auto waitStart = Clock::now();
    MCV_CUDA_TRY(cudaStreamSynchronize(streams_[i]));
    stats_.waitMs += msSince(waitStart);
    busy[i] = false;
    return done(pending[i]);
  };

  const int perChannel = setup_.selection.perChannel();
  std::size_t slab = 0;
  for (int z0 = 0; z0 < nz; z0 += S, ++slab)
  {
    const int i = static_cast<int>(slab % kSlabSlots);
    if (!finish(i))
    {
      return false;
    }
    Slab& s = pending[i];
    const int z1 = std::min(nz, z0 + S), g0 = std::max(0, z0 - 1), g1 = std::min(nz, z1 + 1);
    const std::size_t withGhosts = static_cast<std::size_t>(g1 - g0) * nxy;
    s.slot = i;
    s.stream = streams_[i];
    s.z0 = z0;
    s.z1 = z1;
    s.firstRow = static_cast<std::size_t>(z0) * nxy;
    s.rows = static_cast<std::size_t>(z1 - z0) * nxy;
    s.features = features_[i];
    s.channels = channels_[i];
    s.plane = plane_;
    s.vBegin = static_cast<std::int64_t>(z0 - g0) * static_cast<std::int64_t>(nxy);
    s.pinned = passPinned_[i];
    ImageGrid sub = grid;
    sub.dims[2] = g1 - g0;

    // The host converts this slab's channels while the device works on the other slot's.
    const auto fillStart = Clock::now();
    s.nonFinite.assign(static_cast<std::size_t>(C), false);
    s.anyNonFinite = false;
    for (int c = 0; c < C; ++c)
    {
      const bool bad = fill(c, static_cast<std::size_t>(g0) * nxy, withGhosts, stageIn_[i] + static_cast<std::size_t>(c) * plane_) > 0;
      s.nonFinite[static_cast<std::size_t>(c)] = bad;
      s.anyNonFinite = s.anyNonFinite || bad;
    }
    stats_.fillMs += msSince(fillStart);

    for (int c = 0; c < C; ++c)
    {
      MCV_CUDA_TRY(cudaMemcpyAsync(channels_[i] + static_cast<std::size_t>(c) * plane_,
        stageIn_[i] + static_cast<std::size_t>(c) * plane_, withGhosts * sizeof(float), cudaMemcpyHostToDevice, s.stream));
      stats_.bytesToDevice += withGhosts * sizeof(float);
    }
    for (int c = 0; c < C; ++c)
    {
      ChannelParams p = channelParams(sub, setup_.selection, F, c * perChannel);
      p.vBegin = s.vBegin;
      p.vEnd = s.vBegin + static_cast<std::int64_t>(s.rows);
      const float* channel = channels_[i] + static_cast<std::size_t>(c) * plane_;
      if (s.nonFinite[static_cast<std::size_t>(c)])
      {
        channelFeaturesKernel<true><<<slabBlocksFor(static_cast<std::int64_t>(s.rows)), kThreads, 0, s.stream>>>(
          channel, features_[i], p);
      }
      else
      {
        channelFeaturesKernel<false><<<slabBlocksFor(static_cast<std::int64_t>(s.rows)), kThreads, 0, s.stream>>>(
          channel, features_[i], p);
      }
      MCV_CUDA_TRY(cudaGetLastError());
    }
    if (normalise)
    {
      normalizeSlabKernel<<<slabBlocksFor(static_cast<std::int64_t>(s.rows) * F), kThreads, 0, s.stream>>>(features_[i],
        static_cast<std::int64_t>(s.rows), F, columnParams_, columnParams_ + F, channels_[i], C,
        static_cast<std::int64_t>(plane_), s.vBegin, s.anyNonFinite ? 1 : 0);
      MCV_CUDA_TRY(cudaGetLastError());
    }
    if (!launch(s))
    {
      return false;
    }
    busy[i] = true;
  }
  // The last slabs, in order.
  for (std::size_t k = 0; k < static_cast<std::size_t>(kSlabSlots); ++k)
  {
    if (!finish(static_cast<int>((slab + k) % kSlabSlots)))
    {
      return false;
    }
  }
  stats_.slabs = slab;
  stats_.totalMs = msSince(opened_);
  return true;
}

} // namespace cuda
} // namespace mcv
