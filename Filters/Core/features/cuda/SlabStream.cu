// The slab stream of the fused passes: per slab, channels up through pinned staging, raw
// features (and the normalisation) on the device, then the pass's own work; two streams.
#include "SlabStream.cuh"

#include "cuda/CudaCheck.h"
#include "FeatureKernels.cuh"

#include <algorithm>

namespace mcv
{
namespace cuda
{

namespace
{

constexpr int kThreads = 256;
static_assert(kThreads == kFeatureThreads, "the feature kernel's blocks are counted in kThreads");

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

// Device bytes per slot for a slab of `slices` slices: channels with ghosts (unless the
// volume's are resident), features, the pass's.
std::size_t slotBytes(const SlabStreamSetup& s, int slices)
{
  const std::size_t nxy = sliceVoxels(s.grid), rows = static_cast<std::size_t>(slices) * nxy;
  return (s.resident ? 0 : static_cast<std::size_t>(s.channels) * (rows + 2 * nxy) * sizeof(float)) +
    rows * (static_cast<std::size_t>(s.cols) * sizeof(float) + s.pass.perRowDevice) +
    (s.pass.perSlotDevice ? s.pass.perSlotDevice(rows) : 0);
}

} // namespace

bool fusedDeviceBudget(std::size_t deviceBytes, std::size_t* budget, std::size_t* cardBytes, std::string* error)
{
  std::size_t freeBytes = 0;
  MCV_CUDA_TRY(cudaMemGetInfo(&freeBytes, cardBytes));
  *budget = deviceBytes;
  if (deviceBytes == 0)
  {
    const std::size_t margin = std::max<std::size_t>(std::size_t(512) << 20, *cardBytes / 16);
    *budget = freeBytes > margin ? freeBytes - margin : 0;
  }
  return true;
}

ResidentChannels::~ResidentChannels()
{
  release();
}

void* ResidentChannels::takePinned(std::size_t bytes, std::size_t* capacity)
{
  std::size_t best = pinned_.size();
  for (std::size_t i = 0; i < pinned_.size(); ++i)
  {
    if (pinned_[i].second >= bytes && (best == pinned_.size() || pinned_[i].second < pinned_[best].second))
    {
      best = i;
    }
  }
  if (best == pinned_.size())
  {
    return nullptr;
  }
  void* p = pinned_[best].first;
  *capacity = pinned_[best].second;
  pinned_.erase(pinned_.begin() + static_cast<std::ptrdiff_t>(best));
  return p;
}

void ResidentChannels::keepPinned(void* p, std::size_t bytes)
{
  if (p)
  {
    pinned_.emplace_back(p, bytes);
  }
}

void ResidentChannels::freePinned()
{
  for (const auto& kept : pinned_)
  {
    cudaFreeHost(kept.first);
  }
  pinned_.clear();
}

void ResidentChannels::release()
{
  freePinned();
  cudaFree(data_);
  data_ = nullptr;
  channels_ = 0;
  voxels_ = 0;
  filled = false;
  nonFinite.clear();
}

bool ResidentChannels::reserveIfFits(int channels, std::size_t voxels, std::size_t deviceBytes)
{
  release();
  std::size_t budget = 0, card = 0;
  const std::size_t need = static_cast<std::size_t>(std::max(0, channels)) * voxels * sizeof(float);
  if (need == 0 || !fusedDeviceBudget(deviceBytes, &budget, &card, nullptr) || need > budget / 2 ||
    cudaMalloc(&data_, need) != cudaSuccess)
  {
    data_ = nullptr;
    (void)cudaGetLastError();
    return false;
  }
  channels_ = channels;
  voxels_ = voxels;
  nonFinite.assign(static_cast<std::size_t>(channels), false);
  return true;
}

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
    if (uploaded_[i])
    {
      cudaEventDestroy(uploaded_[i]);
      uploaded_[i] = nullptr;
    }
    // Staging of a resident volume's pass goes back to its cache for the next pass.
    if (setup_.resident)
    {
      setup_.resident->keepPinned(stageIn_[i], stageInBytes_[i]);
      setup_.resident->keepPinned(passPinned_[i], passPinnedBytes_[i]);
    }
    else
    {
      cudaFreeHost(stageIn_[i]);
      cudaFreeHost(passPinned_[i]);
    }
    if (streams_[i])
    {
      cudaStreamDestroy(streams_[i]);
    }
    channels_[i] = features_[i] = stageIn_[i] = nullptr;
    passPinned_[i] = nullptr;
    stageInBytes_[i] = passPinnedBytes_[i] = 0;
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
  uploadedEnd_ = 0;
  const ImageGrid& grid = setup.grid;
  const int F = setup.cols;
  const bool normalise = !setup.offset.empty();
  if (setup.channels < 1 || F != setup.channels * setup.selection.perChannel() ||
    (normalise && (setup.offset.size() != static_cast<std::size_t>(F) || setup.scale.size() != static_cast<std::size_t>(F))))
  {
    return detail::fail(error, "invalid arguments of the GPU slab stream");
  }
  if (setup.resident && (!setup.resident->data() || setup.resident->voxels() != grid.voxelCount()))
  {
    return detail::fail(error, "the resident channels do not hold this volume");
  }
  std::size_t budget = 0, cardBytes = 0;
  if (!fusedDeviceBudget(setup.deviceBytes, &budget, &cardBytes, error))
  {
    return false;
  }
  if (setup.resident && setup.deviceBytes > 0)
  {
    // A given budget covers the resident channels too (the free memory already lacks them).
    budget = budget > setup.resident->bytes() ? budget - setup.resident->bytes() : 0;
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
  // Buffers for the slots the slabs will use: pinning host memory costs about as much as
  // moving it, so a second slot's staging for a one-slab volume would be pure overhead.
  const int slabCount = (std::max(1, grid.dims[2]) + slices_ - 1) / slices_;
  slotsUsed_ = std::min(kSlabSlots, std::max(1, slabCount));
  for (int i = 0; i < slotsUsed_; ++i)
  {
    MCV_CUDA_TRY(cudaStreamCreateWithFlags(&streams_[i], cudaStreamNonBlocking));
    if (!setup.resident)
    {
      MCV_CUDA_TRY(cudaMalloc(&channels_[i], C * plane_ * sizeof(float)));
    }
    MCV_CUDA_TRY(cudaMalloc(&features_[i], rows * static_cast<std::size_t>(F) * sizeof(float)));
    if (!setup.resident || !setup.resident->filled)
    {
      stageInBytes_[i] = C * plane_ * sizeof(float);
      if (!(setup.resident &&
            (stageIn_[i] = static_cast<float*>(setup.resident->takePinned(stageInBytes_[i], &stageInBytes_[i])))))
      {
        MCV_CUDA_TRY(cudaMallocHost(&stageIn_[i], stageInBytes_[i]));
      }
    }
    if (setup.resident && !setup.resident->filled)
    {
      MCV_CUDA_TRY(cudaEventCreateWithFlags(&uploaded_[i], cudaEventDisableTiming));
    }
    if (setup.pass.perRowPinned > 0)
    {
      passPinnedBytes_[i] = rows * setup.pass.perRowPinned;
      if (!(setup.resident && (passPinned_[i] = static_cast<unsigned char*>(
                                 setup.resident->takePinned(passPinnedBytes_[i], &passPinnedBytes_[i])))))
      {
        MCV_CUDA_TRY(cudaMallocHost(&passPinned_[i], passPinnedBytes_[i]));
      }
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
  stats_.deviceBytes = bytesFor(setup, slices_) + (setup.resident ? setup.resident->bytes() : 0);
  stats_.pinnedBytes = static_cast<std::size_t>(slotsUsed_) * ((stageIn_[0] ? C * plane_ * sizeof(float) : 0) + rows * setup.pass.perRowPinned);
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
    s.vBegin = static_cast<std::int64_t>(z0 - g0) * static_cast<std::int64_t>(nxy);
    s.pinned = passPinned_[i];
    ImageGrid sub = grid;
    sub.dims[2] = g1 - g0;
    if (!channelsUp(s, g0, g1, withGhosts, fill, error))
    {
      return false;
    }
    for (int c = 0; c < C; ++c)
    {
      ChannelParams p = channelParams(sub, setup_.selection, F, c * perChannel);
      p.vBegin = s.vBegin;
      p.vEnd = s.vBegin + static_cast<std::int64_t>(s.rows);
      const float* channel = s.channels + static_cast<std::size_t>(c) * s.plane;
      if (s.nonFinite[static_cast<std::size_t>(c)])
      {
        channelFeaturesKernel<true><<<slabBlocksFor(static_cast<std::int64_t>(s.rows)), kFeatureThreads, 0, s.stream>>>(
          channel, features_[i], p);
      }
      else
      {
        channelFeaturesKernel<false><<<slabBlocksFor(static_cast<std::int64_t>(s.rows)), kFeatureThreads, 0, s.stream>>>(
          channel, features_[i], p);
      }
      MCV_CUDA_TRY(cudaGetLastError());
    }
    if (normalise)
    {
      normalizeSlabKernel<<<slabBlocksFor(static_cast<std::int64_t>(s.rows) * F), kThreads, 0, s.stream>>>(features_[i],
        static_cast<std::int64_t>(s.rows), F, columnParams_, columnParams_ + F, s.channels, C,
        static_cast<std::int64_t>(s.plane), s.vBegin, s.anyNonFinite ? 1 : 0);
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
  if (setup_.resident && !setup_.resident->filled)
  {
    setup_.resident->nonFinite = residentNonFinite_;
    setup_.resident->filled = true;
  }
  return true;
}

bool SlabStream::channelsUp(Slab& s, int g0, int g1, std::size_t withGhosts, const FusedChannelFill& fill, std::string* error)
{
  const int C = setup_.channels, i = s.slot;
  const std::size_t nxy = sliceVoxels(setup_.grid);
  ResidentChannels* const resident = setup_.resident;
  s.nonFinite.assign(static_cast<std::size_t>(C), false);
  if (resident && resident->filled)
  {
    // Everything is on the device already.
    s.channels = resident->data() + static_cast<std::size_t>(g0) * nxy;
    s.plane = resident->voxels();
    s.nonFinite = resident->nonFinite;
    s.anyNonFinite = std::find(s.nonFinite.begin(), s.nonFinite.end(), true) != s.nonFinite.end();
    return true;
  }
  // The host converts the slices that go up while the device works on the other slot's
  // slab: the slab with its ghosts, or, filling the resident copy, the slices not up yet.
  const int u0 = resident ? std::max(g0, uploadedEnd_) : g0;
  const std::size_t count = resident ? static_cast<std::size_t>(g1 - u0) * nxy : withGhosts;
  if (resident && s.firstRow == 0)
  {
    residentNonFinite_.assign(static_cast<std::size_t>(C), false);
  }
  const auto fillStart = Clock::now();
  for (int c = 0; c < C; ++c)
  {
    const bool bad = count > 0 && fill(c, static_cast<std::size_t>(u0) * nxy, count, stageIn_[i] + static_cast<std::size_t>(c) * plane_) > 0;
    s.nonFinite[static_cast<std::size_t>(c)] = bad;
  }
  stats_.fillMs += msSince(fillStart);
  if (resident)
  {
    // The slab's lower slices came up with earlier slabs (on the other stream): wait for them.
    // Its flags are those of every slice up so far (a superset of its own: the guarded
    // kernel equals the other on finite data).
    const int previous = (i + kSlabSlots - 1) % kSlabSlots;
    if (s.firstRow > 0)
    {
      MCV_CUDA_TRY(cudaStreamWaitEvent(s.stream, uploaded_[previous], 0));
    }
    for (int c = 0; c < C; ++c)
    {
      residentNonFinite_[static_cast<std::size_t>(c)] =
        residentNonFinite_[static_cast<std::size_t>(c)] || s.nonFinite[static_cast<std::size_t>(c)];
    }
    s.nonFinite = residentNonFinite_;
    s.channels = resident->data() + static_cast<std::size_t>(g0) * nxy;
    s.plane = resident->voxels();
    uploadedEnd_ = g1;
  }
  else
  {
    s.channels = channels_[i];
    s.plane = plane_;
  }
  s.anyNonFinite = std::find(s.nonFinite.begin(), s.nonFinite.end(), true) != s.nonFinite.end();
  float* const target = resident ? resident->data() + static_cast<std::size_t>(u0) * nxy : channels_[i];
  const std::size_t targetPlane = resident ? resident->voxels() : plane_;
  for (int c = 0; c < C && count > 0; ++c)
  {
    MCV_CUDA_TRY(cudaMemcpyAsync(target + static_cast<std::size_t>(c) * targetPlane,
      stageIn_[i] + static_cast<std::size_t>(c) * plane_, count * sizeof(float), cudaMemcpyHostToDevice, s.stream));
    stats_.bytesToDevice += count * sizeof(float);
  }
  if (resident)
  {
    MCV_CUDA_TRY(cudaEventRecord(uploaded_[i], s.stream));
  }
  return true;
}

} // namespace cuda
} // namespace mcv
