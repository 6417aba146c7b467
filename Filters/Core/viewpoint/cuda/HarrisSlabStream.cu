#include "HarrisSlabStream.h"

#include "cuda/CudaCheck.h"
#include "cuda/DeviceBuffer.cuh"
#include "HarrisArgs.cuh"
#include "HarrisKernel.cuh"
#include "HarrisPipeline.h"
#include "cuda/StagingCopy.h"
#include "TopNSelect.cuh"

#include <algorithm>
#include <chrono>
#include <vector>

namespace mcv
{
namespace cuda
{

using detail::fail;

namespace
{

using Clock = std::chrono::steady_clock;

double msSince(Clock::time_point t)
{
  return std::chrono::duration<double, std::milli>(Clock::now() - t).count();
}

std::size_t planeOf(const ImageGrid& g)
{
  return static_cast<std::size_t>(g.dims[0]) * static_cast<std::size_t>(g.dims[1]);
}

} // namespace

std::size_t wholeVolumeDeviceBytes(const ImageGrid& grid, int bytesPerValue)
{
  return grid.voxelCount() * (static_cast<std::size_t>(bytesPerValue) + sizeof(float)) +
    kSelectionReserveBytes;
}

SlabPlan planSlabs(const ImageGrid& grid, int bytesPerValue, int kernelWidth,
  std::size_t budgetBytes, int maxOwnedSlices)
{
  SlabPlan plan;
  plan.halo = 1 + kernelWidth / 2; // gradient (1) + Gaussian radius
  const int nz = grid.dims[2];
  const std::size_t plane = planeOf(grid);
  if (nz < 1 || plane == 0 || budgetBytes <= kSelectionReserveBytes)
  {
    return plan;
  }
  const std::size_t value = static_cast<std::size_t>(bytesPerValue);
  // bytes(S) = 2 input buffers of (S + 2 halo) slices + S slices of float scores + reserve
  const std::size_t perOwned = plane * (2 * value + sizeof(float));
  const std::size_t fixed = 4 * static_cast<std::size_t>(plan.halo) * plane * value;
  const std::size_t avail = budgetBytes - kSelectionReserveBytes;
  if (avail < fixed + perOwned)
  {
    return plan;
  }
  std::size_t owned = std::min<std::size_t>((avail - fixed) / perOwned, static_cast<std::size_t>(nz));
  if (maxOwnedSlices > 0)
  {
    owned = std::min<std::size_t>(owned, static_cast<std::size_t>(maxOwnedSlices));
  }
  plan.ownedSlices = static_cast<int>(owned);
  plan.slabs = (nz + plan.ownedSlices - 1) / plan.ownedSlices;
  const std::size_t inSlices = std::min<std::size_t>(owned + 2 * plan.halo, nz);
  plan.deviceBytes = 2 * inSlices * plane * value + owned * plane * sizeof(float) + kSelectionReserveBytes;
  return plan;
}

std::size_t deviceBudgetBytes(std::size_t limitBytes, std::size_t alreadyHeldBytes)
{
  if (limitBytes > 0)
  {
    return limitBytes;
  }
  std::size_t freeBytes = 0, totalBytes = 0;
  if (cudaMemGetInfo(&freeBytes, &totalBytes) != cudaSuccess)
  {
    (void)cudaGetLastError();
    return 0;
  }
  const std::size_t margin = std::max<std::size_t>(std::size_t(512) << 20, totalBytes / 20);
  const std::size_t usable = freeBytes + alreadyHeldBytes;
  return usable > margin ? usable - margin : 0;
}

constexpr std::size_t kMaxSlabInputBytes = std::size_t(512) << 20;

struct HarrisSlabStream::Impl
{
  cudaStream_t compute = nullptr, copy = nullptr;
  // Per buffer b: upload span (upBegin..upEnd, upEnd also says "staging b is free again")
  // and consumed[b] (the kernel has read device slab b).
  cudaEvent_t upBegin[2] = {}, upEnd[2] = {}, consumed[2] = {};
  cudaEvent_t harrisBegin = nullptr, harrisEnd = nullptr, selectBegin = nullptr, selectEnd = nullptr;
  bool uploadPending[2] = { false, false };
  void* device[2] = { nullptr, nullptr };
  std::size_t deviceCap[2] = { 0, 0 };
  // Pinned staging: a ring of pieces, each with the event of its last upload.
  static constexpr int kRingSlots = 4;
  static constexpr std::size_t kPieceBytes = std::size_t(64) << 20;
  void* ring = nullptr;
  cudaEvent_t slotFree[kRingSlots] = {};
  int nextSlot = 0;
  float* scores = nullptr;
  std::size_t scoresCap = 0;
  detail::TopNSelector selector;
  std::size_t budget = 0;
  int maxOwned = 0;

  ~Impl()
  {
    freeBuffers();
    for (cudaEvent_t* e : allEvents())
    {
      if (*e)
      {
        cudaEventDestroy(*e);
      }
    }
    for (cudaStream_t s : { compute, copy })
    {
      if (s)
      {
        cudaStreamDestroy(s);
      }
    }
  }

  std::vector<cudaEvent_t*> allEvents()
  {
    std::vector<cudaEvent_t*> all = { &upBegin[0], &upBegin[1], &upEnd[0], &upEnd[1],
      &consumed[0], &consumed[1], &harrisBegin, &harrisEnd, &selectBegin, &selectEnd };
    for (cudaEvent_t& e : slotFree)
    {
      all.push_back(&e);
    }
    return all;
  }

  std::size_t deviceBytesHeld() const { return deviceCap[0] + deviceCap[1] + scoresCap; }

  void freeBuffers()
  {
    for (cudaStream_t s : { compute, copy })
    {
      if (s)
      {
        (void)cudaStreamSynchronize(s); // no copy or kernel may still use the buffers
      }
    }
    (void)cudaGetLastError();
    selector.release();
    for (int b = 0; b < 2; ++b)
    {
      if (device[b])
      {
        cudaFree(device[b]);
      }
      device[b] = nullptr;
      deviceCap[b] = 0;
      uploadPending[b] = false;
    }
    if (ring)
    {
      cudaFreeHost(ring);
    }
    ring = nullptr;
    if (scores)
    {
      cudaFree(scores);
    }
    scores = nullptr;
    scoresCap = 0;
  }

  bool init(std::string* error)
  {
    // Only what is missing: a failure half-way must not leak what was created.
    for (cudaStream_t* s : { &compute, &copy })
    {
      if (!*s)
      {
        MCV_CUDA_TRY(cudaStreamCreateWithFlags(s, cudaStreamNonBlocking));
      }
    }
    for (cudaEvent_t* e : allEvents())
    {
      if (!*e)
      {
        MCV_CUDA_TRY(cudaEventCreate(e));
      }
    }
    return true;
  }

  bool ensureDevice(void*& buffer, std::size_t& capacity, std::size_t bytes, std::string* error)
  {
    return growDeviceBuffer(buffer, capacity, bytes, error);
  }

  bool ensureRing(std::string* error)
  {
    if (!ring)
    {
      MCV_CUDA_TRY(cudaHostAlloc(&ring, kRingSlots * kPieceBytes, cudaHostAllocDefault));
    }
    return true;
  }

  float elapsed(cudaEvent_t a, cudaEvent_t b)
  {
    float ms = 0.f;
    if (cudaEventElapsedTime(&ms, a, b) != cudaSuccess)
    {
      (void)cudaGetLastError(); // a timing is not worth failing for; leave no error behind
      return 0.f;
    }
    return ms;
  }

  // Waits for buffer b's last upload (its staging buffer is then free) and books its time.
  bool finishUpload(int b, SlabTimings& t, std::string* error)
  {
    MCV_CUDA_TRY(cudaEventSynchronize(upEnd[b]));
    if (uploadPending[b])
    {
      t.uploadMs += elapsed(upBegin[b], upEnd[b]);
      uploadPending[b] = false;
    }
    return true;
  }

  // Input slices [in0, in1) of the host volume -> device slab b, in pieces through the
  // pinned ring: each piece's upload is queued as soon as the host has copied it, so the
  // host copy of piece k+1 overlaps the DMA of piece k; a slot is refilled only after its
  // last DMA (its event). The ring, not the slab, sets the pinned memory.
  template <typename T>
  bool stage(const T* host, std::size_t plane, int in0, int in1, int b, SlabTimings& t,
    std::string* error)
  {
    if (!finishUpload(b, t, error))
    {
      return false;
    }
    MCV_CUDA_TRY(cudaStreamWaitEvent(copy, consumed[b], 0)); // the kernel is done with slab b
    MCV_CUDA_TRY(cudaEventRecord(upBegin[b], copy));
    const std::size_t bytes = static_cast<std::size_t>(in1 - in0) * plane * sizeof(T);
    const char* src = reinterpret_cast<const char*>(host + static_cast<std::size_t>(in0) * plane);
    char* dst = static_cast<char*>(device[b]);
    for (std::size_t at = 0; at < bytes; at += kPieceBytes)
    {
      const std::size_t n = std::min(kPieceBytes, bytes - at);
      const int slot = nextSlot;
      nextSlot = (nextSlot + 1) % kRingSlots;
      MCV_CUDA_TRY(cudaEventSynchronize(slotFree[slot]));
      char* staging = static_cast<char*>(ring) + static_cast<std::size_t>(slot) * kPieceBytes;
      const auto c0 = Clock::now();
      detail::stagingCopy(staging, src + at, n);
      t.stagingMs += msSince(c0);
      MCV_CUDA_TRY(cudaMemcpyAsync(dst + at, staging, n, cudaMemcpyHostToDevice, copy));
      MCV_CUDA_TRY(cudaEventRecord(slotFree[slot], copy));
    }
    MCV_CUDA_TRY(cudaEventRecord(upEnd[b], copy));
    uploadPending[b] = true;
    return true;
  }

  template <typename T>
  bool run(const T* host, const ImageGrid& grid, const HarrisParameters& params, int N,
    InterestPoints& out, std::string* error, SlabTimings* timings)
  {
    const auto start = Clock::now();
    out = InterestPoints();
    SlabTimings t;
    if (!host)
    {
      return fail(error, "no volume given");
    }
    const char* why = gpuUnsupportedReason(grid, params);
    if (*why)
    {
      return fail(error, why);
    }
    if (grid.extendedAxes() != 3)
    {
      return fail(error, "the slab stream needs a 3D grid (every axis with more than one voxel)");
    }
    if (!init(error))
    {
      return false;
    }
    const std::size_t budgetNow = budget ? budget : deviceBudgetBytes(0, deviceBytesHeld());
    const std::size_t plane = planeOf(grid);
    const int halo = 1 + params.kernelWidth / 2;
    // Slabs of at most kMaxSlabInputBytes of input: the first slab's upload is not
    // overlapped, and the halo overhead (2 halo / owned slices) is small at that size.
    const std::size_t sliceBytes = plane * sizeof(T);
    int cap = static_cast<int>(std::max<std::size_t>(1 + 2 * halo, kMaxSlabInputBytes / sliceBytes)) - 2 * halo;
    if (maxOwned > 0)
    {
      cap = std::min(cap, maxOwned);
    }
    const SlabPlan plan = planSlabs(grid, sizeof(T), params.kernelWidth, budgetNow, cap);
    if (plan.ownedSlices < 1)
    {
      return fail(error, "a device budget of " + std::to_string(budgetNow >> 20) +
          " MiB holds not even one z-slab of this volume");
    }
    const int nz = grid.dims[2], S = plan.ownedSlices, H = plan.halo;
    const std::size_t inBytes =
      static_cast<std::size_t>(std::min(S + 2 * H, nz)) * plane * sizeof(T);
    for (int b = 0; b < 2; ++b)
    {
      if (!ensureDevice(device[b], deviceCap[b], inBytes, error))
      {
        return false;
      }
    }
    if (!ensureRing(error))
    {
      return false;
    }
    void* scoreBuffer = scores;
    if (!ensureDevice(scoreBuffer, scoresCap, static_cast<std::size_t>(S) * plane * sizeof(float), error))
    {
      return false;
    }
    scores = static_cast<float*>(scoreBuffer);
    t.slabs = plan.slabs;
    t.ownedSlices = S;
    t.halo = H;
    t.deviceBytes = plan.deviceBytes;
    t.pinnedBytes = kRingSlots * kPieceBytes;

    auto inRange = [&](int i, int& in0, int& in1) {
      in0 = std::max(0, i * S - H);
      in1 = std::min(nz, std::min(nz, (i + 1) * S) + H);
    };
    detail::HarrisKernelArgs base = detail::harrisKernelArgs(grid, params);
    const int radius = params.kernelWidth / 2;
    int in0 = 0, in1 = 0;
    inRange(0, in0, in1);
    if (!stage(host, plane, in0, in1, 0, t, error))
    {
      return false;
    }
    InterestPoints best;
    for (int i = 0; i < plan.slabs; ++i)
    {
      const int b = i & 1;
      const int own0 = i * S, own1 = std::min(nz, own0 + S);
      inRange(i, in0, in1);
      if (!selector.reset(N, compute, error))
      {
        return false;
      }
      detail::HarrisKernelArgs a = base;
      a.nz = in1 - in0;
      a.zOutBegin = own0 - in0;
      a.zOutEnd = own1 - in0;
      a.response = scores;
      a.hist = selector.level1Histogram();
      MCV_CUDA_TRY(cudaStreamWaitEvent(compute, upEnd[b], 0));
      MCV_CUDA_TRY(cudaEventRecord(harrisBegin, compute));
      const cudaError_t launchError =
        detail::launchHarris(static_cast<const T*>(device[b]), a, radius, 0, compute, nullptr);
      MCV_CUDA_TRY(launchError); // the name makes it a "launch" injection point
      MCV_CUDA_TRY(cudaEventRecord(harrisEnd, compute));
      MCV_CUDA_TRY(cudaEventRecord(consumed[b], compute));
      if (i + 1 < plan.slabs)
      {
        int next0 = 0, next1 = 0;
        inRange(i + 1, next0, next1);
        if (!stage(host, plane, next0, next1, b ^ 1, t, error))
        {
          return false;
        }
      }
      InterestPoints slab;
      MCV_CUDA_TRY(cudaEventRecord(selectBegin, compute));
      if (!selector.select(scores, static_cast<std::size_t>(own1 - own0) * plane, N, compute, slab,
            error, nullptr, selectEnd))
      {
        return false;
      }
      t.harrisMs += elapsed(harrisBegin, harrisEnd);
      t.selectMs += elapsed(selectBegin, selectEnd);
      const auto m0 = Clock::now();
      const std::int64_t offset = static_cast<std::int64_t>(own0) * static_cast<std::int64_t>(plane);
      for (std::int64_t& index : slab.indices)
      {
        index += offset;
      }
      best.indices.insert(best.indices.end(), slab.indices.begin(), slab.indices.end());
      best.scores.insert(best.scores.end(), slab.scores.begin(), slab.scores.end());
      best = mergeTopResponses(best, N);
      t.mergeMs += msSince(m0);
    }
    for (int b = 0; b < 2; ++b)
    {
      if (!finishUpload(b, t, error))
      {
        return false;
      }
    }
    out = std::move(best);
    t.totalMs = msSince(start);
    if (timings)
    {
      *timings = t;
    }
    return true;
  }
};

HarrisSlabStream::HarrisSlabStream()
  : impl_(new Impl)
{
}

HarrisSlabStream::~HarrisSlabStream() = default;

bool HarrisSlabStream::topN(const float* host, const ImageGrid& grid, const HarrisParameters& params,
  int N, InterestPoints& out, std::string* error, SlabTimings* timings)
{
  FaultStage stage("harris");
  if (impl_->run(host, grid, params, N, out, error, timings))
  {
    return true;
  }
  impl_->freeBuffers(); // half-allocated or half-used: start clean next time
  out = InterestPoints();
  return false;
}

bool HarrisSlabStream::topN(const std::uint8_t* host, const ImageGrid& grid,
  const HarrisParameters& params, int N, InterestPoints& out, std::string* error,
  SlabTimings* timings)
{
  FaultStage stage("harris");
  if (impl_->run(host, grid, params, N, out, error, timings))
  {
    return true;
  }
  impl_->freeBuffers();
  out = InterestPoints();
  return false;
}

void HarrisSlabStream::setBudgetBytes(std::size_t bytes)
{
  impl_->budget = bytes;
}

void HarrisSlabStream::setMaxOwnedSlices(int slices)
{
  impl_->maxOwned = slices;
}

std::size_t HarrisSlabStream::deviceBytesHeld() const
{
  return impl_->deviceBytesHeld();
}

void HarrisSlabStream::release()
{
  impl_->freeBuffers();
}

} // namespace cuda
} // namespace mcv
