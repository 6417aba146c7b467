// The fused reduction's GPU path: per slab, channels up (pinned staging, async copies),
// features and normalisation on the device, placement on the device, coordinates down;
// slabs alternate between two streams so that one slab's host work and transfers overlap
// the other's kernels.
#include "FusedPlacementCuda.h"

#include "CudaCheck.h"
#include "FeatureKernels.cuh"

#include <algorithm>
#include <chrono>
#include <cstring>

namespace mcv
{
namespace cuda
{

namespace
{

constexpr int kThreads = 256;
constexpr int kSlots = 2; // slabs in flight: one per stream

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

int blocksFor(std::int64_t work)
{
  const std::int64_t b = (work + kThreads - 1) / kThreads;
  return static_cast<int>(std::max<std::int64_t>(1, std::min<std::int64_t>(b, 65535 * 16)));
}

std::size_t sliceVoxels(const ImageGrid& g)
{
  return static_cast<std::size_t>(g.dims[0]) * static_cast<std::size_t>(g.dims[1]);
}

// Device bytes per slot for a slab of `slices` slices: channels with ghosts, features,
// coordinates, placement scratch.
std::size_t slotBytes(const FusedPlacementSetup& s, int slices)
{
  const std::size_t nxy = sliceVoxels(s.grid), rows = static_cast<std::size_t>(slices) * nxy;
  const int d = s.references.d;
  return static_cast<std::size_t>(s.channels) * (rows + 2 * nxy) * sizeof(float) +
    rows * static_cast<std::size_t>(s.cols + d) * sizeof(float) + PlacementOnDevice::scratchBytesPerSlot(rows);
}

// Everything the path holds, given back (after the streams are idle) however it ends.
struct Resources
{
  cudaStream_t streams[kSlots] = { nullptr, nullptr };
  float* channels[kSlots] = { nullptr, nullptr }; // device, C x (slices + 2) x nxy
  float* features[kSlots] = { nullptr, nullptr }; // device, slices x nxy x F
  float* coords[kSlots] = { nullptr, nullptr };   // device, slices x nxy x d
  float* stageIn[kSlots] = { nullptr, nullptr };  // pinned host, as channels
  float* stageOut[kSlots] = { nullptr, nullptr }; // pinned host, as coords
  double* columnParams = nullptr;                 // device, offset then scale
  PlacementOnDevice placement;

  ~Resources()
  {
    for (cudaStream_t s : streams)
    {
      if (s)
      {
        cudaStreamSynchronize(s);
      }
    }
    for (int i = 0; i < kSlots; ++i)
    {
      cudaFree(channels[i]);
      cudaFree(features[i]);
      cudaFree(coords[i]);
      cudaFreeHost(stageIn[i]);
      cudaFreeHost(stageOut[i]);
      if (streams[i])
      {
        cudaStreamDestroy(streams[i]);
      }
    }
    cudaFree(columnParams);
    placement.release();
    (void)cudaGetLastError(); // a failed run's error must not leak into the next call
  }
};

// The slab that a slot holds between its launch and its download.
struct Pending
{
  bool busy = false;
  std::size_t firstRow = 0, rows = 0;
};

} // namespace

std::size_t fusedPlacementBytes(const FusedPlacementSetup& setup, int slices)
{
  const PlacementInput& r = setup.references;
  return PlacementOnDevice::referenceBytes(r.M, r.D, r.d) + 2 * static_cast<std::size_t>(setup.cols) * sizeof(double) +
    kSlots * slotBytes(setup, std::max(1, slices));
}

bool placeFused(const FusedPlacementSetup& setup, const FusedChannelFill& fill, float* out,
  const std::function<void(double)>& progress, FusedPlacementStats* statsOut, std::size_t* rowsDone,
  std::string* error)
{
  FaultStage stage("fused");
  const auto start = Clock::now();
  FusedPlacementStats local;
  FusedPlacementStats& st = statsOut ? *statsOut : local;
  st = FusedPlacementStats{};
  std::size_t doneLocal = 0;
  std::size_t& done = rowsDone ? *rowsDone : doneLocal;
  done = 0;

  const ImageGrid& grid = setup.grid;
  const int C = setup.channels, F = setup.cols, d = setup.references.d, nz = grid.dims[2];
  const std::size_t nxy = sliceVoxels(grid), total = grid.voxelCount();
  if (C < 1 || F != C * setup.selection.perChannel() || setup.offset.size() != static_cast<std::size_t>(F) ||
    setup.scale.size() != static_cast<std::size_t>(F) || setup.references.dim != F || !fill || (!out && !setup.writeCoordinates))
  {
    return detail::fail(error, "invalid arguments of the GPU fused placement");
  }
  if (total == 0)
  {
    return true;
  }

  // --- The slab thickness from the device budget --------------------------------------------
  std::size_t freeBytes = 0, cardBytes = 0;
  MCV_CUDA_TRY(cudaMemGetInfo(&freeBytes, &cardBytes));
  std::size_t budget = setup.deviceBytes;
  if (budget == 0)
  {
    const std::size_t margin = std::max<std::size_t>(std::size_t(512) << 20, cardBytes / 16);
    budget = freeBytes > margin ? freeBytes - margin : 0;
  }
  if (fusedPlacementBytes(setup, 1) > budget)
  {
    return detail::fail(error, "the GPU fused placement needs " + std::to_string(fusedPlacementBytes(setup, 1) >> 20) +
        " MiB of device memory for a slab of one slice; it may use " + std::to_string(budget >> 20) + " MiB");
  }
  const int maxSlices = static_cast<int>(std::max<std::size_t>(1, std::min<std::size_t>(nz, kMaxSlabVoxels / std::max<std::size_t>(1, nxy))));
  int S = 1;
  {
    // The largest S <= maxSlices that fits: bytes grow linearly in S (bisection is exact).
    int lo = 1, hi = maxSlices;
    while (lo < hi)
    {
      const int mid = lo + (hi - lo + 1) / 2;
      if (fusedPlacementBytes(setup, mid) <= budget)
      {
        lo = mid;
      }
      else
      {
        hi = mid - 1;
      }
    }
    S = lo;
  }
  st.slabSlices = S;
  const std::size_t slabRows = static_cast<std::size_t>(S) * nxy;
  const std::size_t plane = static_cast<std::size_t>(S + 2) * nxy; // one channel's slab with ghosts

  // --- Buffers, references, normalisation ---------------------------------------------------
  Resources res;
  if (!res.placement.upload(setup.references, kSlots, slabRows, error))
  {
    return false;
  }
  for (int i = 0; i < kSlots; ++i)
  {
    MCV_CUDA_TRY(cudaStreamCreateWithFlags(&res.streams[i], cudaStreamNonBlocking));
    MCV_CUDA_TRY(cudaMalloc(&res.channels[i], static_cast<std::size_t>(C) * plane * sizeof(float)));
    MCV_CUDA_TRY(cudaMalloc(&res.features[i], slabRows * static_cast<std::size_t>(F) * sizeof(float)));
    MCV_CUDA_TRY(cudaMalloc(&res.coords[i], slabRows * static_cast<std::size_t>(d) * sizeof(float)));
    MCV_CUDA_TRY(cudaMallocHost(&res.stageIn[i], static_cast<std::size_t>(C) * plane * sizeof(float)));
    MCV_CUDA_TRY(cudaMallocHost(&res.stageOut[i], slabRows * static_cast<std::size_t>(d) * sizeof(float)));
  }
  MCV_CUDA_TRY(cudaMalloc(&res.columnParams, 2 * static_cast<std::size_t>(F) * sizeof(double)));
  MCV_CUDA_TRY(cudaMemcpy(res.columnParams, setup.offset.data(), F * sizeof(double), cudaMemcpyHostToDevice));
  MCV_CUDA_TRY(cudaMemcpy(res.columnParams + F, setup.scale.data(), F * sizeof(double), cudaMemcpyHostToDevice));
  st.deviceBytes = fusedPlacementBytes(setup, S);
  st.pinnedBytes = kSlots * (static_cast<std::size_t>(C) * plane + slabRows * static_cast<std::size_t>(d)) * sizeof(float);
  const PlacementInput& r = setup.references;
  st.bytesToDevice = PlacementOnDevice::referenceBytes(r.M, r.D, r.d) + 2 * static_cast<std::size_t>(F) * sizeof(double);
  {
    std::size_t freeNow = 0;
    MCV_CUDA_TRY(cudaMemGetInfo(&freeNow, &cardBytes));
    st.deviceUsedPeak = cardBytes - freeNow;
  }
  st.setupMs = msSince(start);

  // --- The slabs ------------------------------------------------------------------------------
  Pending pending[kSlots];
  // Waits for slot i's slab and copies its coordinates out; slabs finish in order.
  auto finish = [&](int i) -> bool {
    if (!pending[i].busy)
    {
      return true;
    }
    const auto waitStart = Clock::now();
    MCV_CUDA_TRY(cudaStreamSynchronize(res.streams[i]));
    st.waitMs += msSince(waitStart);
    if (setup.writeCoordinates)
    {
      setup.writeCoordinates(pending[i].firstRow, pending[i].rows, res.stageOut[i]);
    }
    else
    {
      std::memcpy(out + pending[i].firstRow * static_cast<std::size_t>(d), res.stageOut[i],
        pending[i].rows * static_cast<std::size_t>(d) * sizeof(float));
    }
    pending[i].busy = false;
    done = pending[i].firstRow + pending[i].rows;
    if (progress)
    {
      progress(static_cast<double>(done) / static_cast<double>(total));
    }
    return true;
  };

  const int perChannel = setup.selection.perChannel();
  std::size_t slab = 0;
  for (int z0 = 0; z0 < nz; z0 += S, ++slab)
  {
    const int i = static_cast<int>(slab % kSlots);
    const cudaStream_t stream = res.streams[i];
    if (!finish(i))
    {
      return false;
    }
    const int z1 = std::min(nz, z0 + S), g0 = std::max(0, z0 - 1), g1 = std::min(nz, z1 + 1);
    const std::size_t withGhosts = static_cast<std::size_t>(g1 - g0) * nxy;
    const std::size_t rows = static_cast<std::size_t>(z1 - z0) * nxy;
    const std::int64_t vBegin = static_cast<std::int64_t>(z0 - g0) * static_cast<std::int64_t>(nxy);
    ImageGrid sub = grid;
    sub.dims[2] = g1 - g0;

    // The host converts this slab's channels while the device works on the other slot's.
    const auto fillStart = Clock::now();
    bool anyBad = false;
    std::vector<bool> bad(static_cast<std::size_t>(C));
    for (int c = 0; c < C; ++c)
    {
      bad[static_cast<std::size_t>(c)] =
        fill(c, static_cast<std::size_t>(g0) * nxy, withGhosts, res.stageIn[i] + static_cast<std::size_t>(c) * plane) > 0;
      anyBad = anyBad || bad[static_cast<std::size_t>(c)];
    }
    st.fillMs += msSince(fillStart);

    for (int c = 0; c < C; ++c)
    {
      MCV_CUDA_TRY(cudaMemcpyAsync(res.channels[i] + static_cast<std::size_t>(c) * plane,
        res.stageIn[i] + static_cast<std::size_t>(c) * plane, withGhosts * sizeof(float), cudaMemcpyHostToDevice, stream));
      st.bytesToDevice += withGhosts * sizeof(float);
    }
    for (int c = 0; c < C; ++c)
    {
      ChannelParams p = channelParams(sub, setup.selection, F, c * perChannel);
      p.vBegin = vBegin;
      p.vEnd = vBegin + static_cast<std::int64_t>(rows);
      const float* channel = res.channels[i] + static_cast<std::size_t>(c) * plane;
      if (bad[static_cast<std::size_t>(c)])
      {
        channelFeaturesKernel<true><<<blocksFor(static_cast<std::int64_t>(rows)), kThreads, 0, stream>>>(
          channel, res.features[i], p);
      }
      else
      {
        channelFeaturesKernel<false><<<blocksFor(static_cast<std::int64_t>(rows)), kThreads, 0, stream>>>(
          channel, res.features[i], p);
      }
      MCV_CUDA_TRY(cudaGetLastError());
    }
    normalizeSlabKernel<<<blocksFor(static_cast<std::int64_t>(rows) * F), kThreads, 0, stream>>>(res.features[i],
      static_cast<std::int64_t>(rows), F, res.columnParams, res.columnParams + F, res.channels[i], C,
      static_cast<std::int64_t>(plane), vBegin, anyBad ? 1 : 0);
    MCV_CUDA_TRY(cudaGetLastError());
    if (!res.placement.place(res.features[i], rows, res.coords[i], nullptr, i, stream, setup.mergeEqualRows, error))
    {
      return false;
    }
    MCV_CUDA_TRY(cudaMemcpyAsync(res.stageOut[i], res.coords[i], rows * static_cast<std::size_t>(d) * sizeof(float),
      cudaMemcpyDeviceToHost, stream));
    st.bytesFromDevice += rows * static_cast<std::size_t>(d) * sizeof(float);
    pending[i] = Pending{ true, static_cast<std::size_t>(z0) * nxy, rows };
  }
  // The last slabs, in order.
  for (std::size_t k = 0; k < static_cast<std::size_t>(kSlots); ++k)
  {
    if (!finish(static_cast<int>((slab + k) % kSlots)))
    {
      return false;
    }
  }
  st.slabs = slab;
  if (!res.placement.radiusScans(&st.radiusScans, error))
  {
    return false;
  }
  st.totalMs = msSince(start);
  return true;
}

} // namespace cuda
} // namespace mcv
