// The fused reduction's statistics, column-sum and strata passes on the GPU: the slab stream
// (SlabStream.cuh) computes each slab's features on the device; the kernels below reduce
// them there, in a fixed order (no floating-point atomics), so a pass gives the same bits on
// every run.
#include "FusedPassesCuda.h"

#include "cuda/CudaCheck.h"
#include "cuda/DeviceBuffer.cuh"
#include "cuda/OrderedKey.cuh"
#include "SlabStream.cuh"
#include "cuda/StagingCopy.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>

namespace mcv
{
namespace cuda
{

namespace
{

constexpr int kThreads = 256;
// Threads of a statistics kernel: about 32 elements each, at most 1024 blocks (enough warps
// per SM to hide the loads' latency: 256 blocks left the column sums latency-bound) -- fixed
// by the slab, not by the card, so the order of the sums (hence their bits) is the same
// everywhere.
constexpr int kReduceBlocks = 1024;
constexpr std::size_t kElementsPerThread = 32;
// Exponent fields whose exact sums a thread keeps in registers: |x| in [2^-7, 2^9), where
// normalised features mostly lie; the others go straight to the global bins.
constexpr int kWindowLow = 120;
constexpr int kWindow = 16;

// Column-major partial slots: thread t (t < S, S a multiple of cols) takes column t % cols of
// elements t, t + S, t + 2S, ... of the slab.
int reduceThreads(int cols, std::size_t rows)
{
  const std::size_t wanted = std::max<std::size_t>(1, rows * static_cast<std::size_t>(cols) / kElementsPerThread);
  const std::size_t most = static_cast<std::size_t>(kReduceBlocks) * kThreads;
  return static_cast<int>(std::max<std::size_t>(1, std::min(wanted, most) / static_cast<std::size_t>(cols))) * cols;
}

__device__ __forceinline__ bool rowHasNonFinite(const float* channels, int C, std::int64_t plane, std::int64_t at)
{
  bool bad = false;
  for (int c = 0; c < C; ++c)
  {
    bad = bad || !isfinite(channels[c * plane + at]);
  }
  return bad;
}

struct SlabRows
{
  const float* features;
  std::int64_t rows;
  int cols;
  const float* channels; // for the rows' non-finite check (checkRows)
  int C;
  std::int64_t plane, vBegin;
  int checkRows;
};

// Statistics, first pass (mean null: count, sum, min, max per thread) or second (sqdev about
// mean), over the rows whose channels are finite and the finite values, as columnStatsCPU.
__global__ void slabStatsKernel(SlabRows s, int S, const double* __restrict__ mean, double* pCount, double* pSum,
  float* pMin, float* pMax, double* pSq)
{
  const int t = blockIdx.x * blockDim.x + threadIdx.x;
  if (t >= S)
  {
    return;
  }
  const int col = t % s.cols;
  const double m = mean ? mean[col] : 0.0;
  double count = 0.0, sum = 0.0, sq = 0.0;
  float lo = INFINITY, hi = -INFINITY;
  const std::int64_t elements = s.rows * s.cols;
  for (std::int64_t e = t; e < elements; e += S)
  {
    const std::int64_t row = e / s.cols;
    if (s.checkRows && rowHasNonFinite(s.channels, s.C, s.plane, s.vBegin + row))
    {
      continue;
    }
    const float x = s.features[e];
    if (!isfinite(x))
    {
      continue;
    }
    if (mean)
    {
      const double d = __dsub_rn(static_cast<double>(x), m);
      sq = __dadd_rn(sq, __dmul_rn(d, d));
    }
    else
    {
      count += 1.0;
      sum = __dadd_rn(sum, static_cast<double>(x));
      lo = fminf(lo, x);
      hi = fmaxf(hi, x);
    }
  }
  if (mean)
  {
    pSq[t] = sq;
  }
  else
  {
    pCount[t] = count;
    pSum[t] = sum;
    pMin[t] = lo;
    pMax[t] = hi;
  }
}

// Per column, the threads' partials in thread order: out = [count, sum, min, max, sqdev] x
// cols; the first pass also leaves the slab's mean in `mean`.
__global__ void slabStatsReduceKernel(int S, int cols, int second, const double* pCount, const double* pSum,
  const float* pMin, const float* pMax, const double* pSq, double* mean, double* out)
{
  const int c = blockIdx.x * blockDim.x + threadIdx.x;
  if (c >= cols)
  {
    return;
  }
  if (second)
  {
    double sq = 0.0;
    for (int t = c; t < S; t += cols)
    {
      sq = __dadd_rn(sq, pSq[t]);
    }
    out[4 * cols + c] = sq;
    return;
  }
  double count = 0.0, sum = 0.0;
  float lo = INFINITY, hi = -INFINITY;
  for (int t = c; t < S; t += cols)
  {
    count += pCount[t];
    sum = __dadd_rn(sum, pSum[t]);
    lo = fminf(lo, pMin[t]);
    hi = fmaxf(hi, pMax[t]);
  }
  out[c] = count;
  out[cols + c] = sum;
  out[2 * cols + c] = lo;
  out[3 * cols + c] = hi;
  mean[c] = count > 0 ? sum / count : 0.0;
}

// The slab's non-finite voxels per channel and with any: counts[0..C), counts[C].
__global__ void nonFiniteCountKernel(const float* channels, int C, std::int64_t plane, std::int64_t vBegin,
  std::int64_t rows, unsigned long long* counts)
{
  for (std::int64_t r = blockIdx.x * static_cast<std::int64_t>(blockDim.x) + threadIdx.x; r < rows;
       r += static_cast<std::int64_t>(gridDim.x) * blockDim.x)
  {
    bool any = false;
    for (int c = 0; c < C; ++c)
    {
      if (!isfinite(channels[c * plane + vBegin + r]))
      {
        atomicAdd(&counts[c], 1ull);
        any = true;
      }
    }
    if (any)
    {
      atomicAdd(&counts[C], 1ull);
    }
  }
}

// Exact integer sums per exponent field (a float is m 2^(e - 150), |m| < 2^24), extremes and
// non-finite values of the normalised features; integer atomics only, so any order gives the
// same result. firstRow: the slab's first row in the volume (for the first non-finite value).
// A thread keeps the exponents of kWindow in registers; the others go to the block's bins in
// shared memory (cols x 256, when sharedBins; else straight to the global ones), which the
// block adds to the global bins at its end: few global atomics, so no contention there.
__global__ void exactSumsKernel(const float* __restrict__ features, std::int64_t rows, int cols, int S,
  std::uint64_t firstRow, unsigned long long* bins, int* minKey, int* maxKey, unsigned long long* nonFinite,
  unsigned long long* firstBad, int sharedBins)
{
  extern __shared__ unsigned long long blockBins[];
  const int binCount = cols * kExactExponents;
  if (sharedBins)
  {
    for (int i = threadIdx.x; i < binCount; i += blockDim.x)
    {
      blockBins[i] = 0ull;
    }
    __syncthreads();
  }
  unsigned long long* const spill = sharedBins ? blockBins : bins;
  const int t = blockIdx.x * blockDim.x + threadIdx.x;
  if (t < S)
  {
    const int col = t % cols;
    long long window[kWindow];
#pragma unroll
    for (int w = 0; w < kWindow; ++w)
    {
      window[w] = 0;
    }
    float lo = INFINITY, hi = -INFINITY;
    unsigned long long bad = 0, firstBadHere = ~0ull;
    const std::int64_t elements = rows * cols;
#pragma unroll 4
    for (std::int64_t e = t; e < elements; e += S)
    {
      const float x = features[e];
      if (!isfinite(x))
      {
        ++bad;
        firstBadHere = min(firstBadHere, static_cast<unsigned long long>(firstRow * cols + e));
        continue;
      }
      lo = fminf(lo, x);
      hi = fmaxf(hi, x);
      const unsigned bits = __float_as_uint(x);
      const int ex = static_cast<int>((bits >> 23) & 0xFFu);
      const long long mag = static_cast<long long>((bits & 0x7FFFFFu) | (ex != 0 ? 0x800000u : 0u));
      const long long m = (bits >> 31) != 0 ? -mag : mag;
      const int w = ex - kWindowLow;
      if (w >= 0 && w < kWindow)
      {
#pragma unroll
        for (int k = 0; k < kWindow; ++k)
        {
          window[k] += (k == w) ? m : 0;
        }
      }
      else if (m != 0)
      {
        atomicAdd(&spill[col * kExactExponents + max(ex, 1)], static_cast<unsigned long long>(m));
      }
    }
#pragma unroll
    for (int w = 0; w < kWindow; ++w)
    {
      if (window[w] != 0)
      {
        atomicAdd(&spill[col * kExactExponents + kWindowLow + w], static_cast<unsigned long long>(window[w]));
      }
    }
    atomicMin(&minKey[col], orderedKey(lo));
    atomicMax(&maxKey[col], orderedKey(hi));
    if (bad > 0)
    {
      atomicAdd(nonFinite, bad);
      atomicMin(firstBad, firstBadHere);
    }
  }
  if (sharedBins)
  {
    __syncthreads();
    for (int i = threadIdx.x; i < binCount; i += blockDim.x)
    {
      if (blockBins[i] != 0ull)
      {
        atomicAdd(&bins[i], blockBins[i]);
      }
    }
  }
}

// One row per thread: its stratum, as Sampler::assignStrata computes it (double steps
// without contraction, the square root and the float rounding correctly rounded).
__global__ void strataKernel(const float* __restrict__ features, std::int64_t rows, int cols,
  const int* __restrict__ columns, int D, const double* __restrict__ center, const float* __restrict__ edges,
  int edgeCount, const unsigned char* __restrict__ eligible, unsigned char notEligible, unsigned char* stratum)
{
  for (std::int64_t r = blockIdx.x * static_cast<std::int64_t>(blockDim.x) + threadIdx.x; r < rows;
       r += static_cast<std::int64_t>(gridDim.x) * blockDim.x)
  {
    if (eligible && eligible[r] == 0)
    {
      stratum[r] = notEligible;
      continue;
    }
    const float* x = features + r * cols;
    double s = 0.0;
    for (int k = 0; k < D; ++k)
    {
      const double v = __dsub_rn(static_cast<double>(x[columns[k]]), center ? center[k] : 0.0);
      s = __dadd_rn(s, __dmul_rn(v, v));
    }
    const float norm = __double2float_rn(__dsqrt_rn(s));
    int below = 0; // std::upper_bound: the edges <= norm
    while (below < edgeCount && !(norm < edges[below]))
    {
      ++below;
    }
    stratum[r] = static_cast<unsigned char>(below);
  }
}

SlabStreamSetup streamSetup(const FusedPassSetup& s, const SlabPassBytes& pass)
{
  SlabStreamSetup st = slabStreamSetup(s);
  st.pass = pass;
  return st;
}

void copyStats(const SlabStreamStats& from, FusedPassStats* to)
{
  if (to)
  {
    *to = FusedPassStats{ from.slabSlices, from.slabs, from.bytesToDevice, from.bytesFromDevice, from.deviceBytes,
      from.deviceUsedPeak, from.pinnedBytes, from.setupMs, from.fillMs, from.waitMs, from.totalMs };
  }
}

void reportProgress(const std::function<void(double)>& progress, const Slab& s, const ImageGrid& grid)
{
  if (progress)
  {
    progress(static_cast<double>(s.firstRow + s.rows) / static_cast<double>(std::max<std::size_t>(1, grid.voxelCount())));
  }
}

// Pinned host memory given back however the pass ends.
struct PinnedSlots
{
  unsigned char* slot[kSlabSlots] = { nullptr, nullptr };
  ~PinnedSlots()
  {
    for (unsigned char* p : slot)
    {
      cudaFreeHost(p);
    }
  }
};

} // namespace

bool fusedRawStatistics(const FusedPassSetup& setup, const FusedChannelFill& fill, RawStatistics* out,
  const std::function<void(double)>& progress, FusedPassStats* stats, std::string* error)
{
  FaultStage stage("fusedpasses");
  const int F = setup.cols, C = setup.channels;
  *out = RawStatistics{};
  out->badPerChannel.assign(static_cast<std::size_t>(std::max(0, C)), 0.0);
  if (!fill || F < 1 || !setup.offset.empty())
  {
    return detail::fail(error, "invalid arguments of the GPU statistics pass");
  }
  // Per slot: thread partials (count, sum, sqdev as double; min, max as float), the slab's
  // mean, its 5 x F results and C + 1 non-finite counts.
  const auto partialBytes = [F](std::size_t rows) {
    return static_cast<std::size_t>(reduceThreads(std::max(1, F), rows)) * (3 * sizeof(double) + 2 * sizeof(float));
  };
  const std::size_t resultBytes = 5 * static_cast<std::size_t>(F) * sizeof(double) + (C + 1) * sizeof(unsigned long long);
  SlabPassBytes pass;
  pass.perSlotDevice = [=](std::size_t rows) { return partialBytes(rows) + F * sizeof(double) + resultBytes; };
  DeviceBuffer partials[kSlabSlots], results[kSlabSlots];
  PinnedSlots pinned;
  SlabStream stream;
  if (!stream.open(streamSetup(setup, pass), error))
  {
    return false;
  }
  for (int i = 0; i < stream.slotsUsed(); ++i)
  {
    MCV_CUDA_TRY(cudaMalloc(&partials[i].ptr, partialBytes(stream.slabRows()) + F * sizeof(double)));
    MCV_CUDA_TRY(cudaMalloc(&results[i].ptr, resultBytes));
    MCV_CUDA_TRY(cudaMallocHost(&pinned.slot[i], resultBytes));
  }
  const auto launch = [&](Slab& s) -> bool {
    const int S = reduceThreads(F, s.rows);
    double* pCount = partials[s.slot].as<double>();
    double* pSum = pCount + S;
    double* pSq = pSum + S;
    double* mean = pSq + S;
    float* pMin = reinterpret_cast<float*>(mean + F);
    float* pMax = pMin + S;
    double* slabStats = results[s.slot].as<double>();
    unsigned long long* counts = reinterpret_cast<unsigned long long*>(slabStats + 5 * F);
    const SlabRows rows{ s.features, static_cast<std::int64_t>(s.rows), F, s.channels, C,
      static_cast<std::int64_t>(s.plane), s.vBegin, s.anyNonFinite ? 1 : 0 };
    const int blocks = (S + kThreads - 1) / kThreads;
    slabStatsKernel<<<blocks, kThreads, 0, s.stream>>>(rows, S, nullptr, pCount, pSum, pMin, pMax, pSq);
    slabStatsReduceKernel<<<(F + 63) / 64, 64, 0, s.stream>>>(S, F, 0, pCount, pSum, pMin, pMax, pSq, mean, slabStats);
    slabStatsKernel<<<blocks, kThreads, 0, s.stream>>>(rows, S, mean, pCount, pSum, pMin, pMax, pSq);
    slabStatsReduceKernel<<<(F + 63) / 64, 64, 0, s.stream>>>(S, F, 1, pCount, pSum, pMin, pMax, pSq, mean, slabStats);
    MCV_CUDA_TRY(cudaMemsetAsync(counts, 0, (C + 1) * sizeof(unsigned long long), s.stream));
    if (s.anyNonFinite)
    {
      nonFiniteCountKernel<<<slabBlocksFor(static_cast<std::int64_t>(s.rows)), kThreads, 0, s.stream>>>(
        s.channels, C, static_cast<std::int64_t>(s.plane), s.vBegin, static_cast<std::int64_t>(s.rows), counts);
    }
    MCV_CUDA_TRY(cudaGetLastError());
    MCV_CUDA_TRY(cudaMemcpyAsync(pinned.slot[s.slot], results[s.slot].ptr, resultBytes, cudaMemcpyDeviceToHost, s.stream));
    stream.stats().bytesFromDevice += resultBytes;
    return true;
  };
  const auto done = [&](const Slab& s) -> bool {
    const double* r = reinterpret_cast<const double*>(pinned.slot[s.slot]);
    const unsigned long long* counts = reinterpret_cast<const unsigned long long*>(r + 5 * F);
    mcv::detail::ColumnStats part;
    part.reset(F);
    part.count.assign(r, r + F);
    part.sum.assign(r + F, r + 2 * F);
    part.min.assign(r + 2 * F, r + 3 * F);
    part.max.assign(r + 3 * F, r + 4 * F);
    part.sqdev.assign(r + 4 * F, r + 5 * F);
    out->slabs.push_back(std::move(part));
    for (int c = 0; c < C; ++c)
    {
      out->badPerChannel[static_cast<std::size_t>(c)] += static_cast<double>(counts[c]);
    }
    out->badVoxels += static_cast<double>(counts[C]);
    reportProgress(progress, s, setup.grid);
    return true;
  };
  const bool ok = stream.run(fill, launch, done, error);
  copyStats(stream.stats(), stats);
  return ok;
}

bool fusedColumnSums(const FusedPassSetup& setup, const FusedChannelFill& fill, DeviceColumnSums* out,
  const std::function<void(double)>& progress, FusedPassStats* stats, std::string* error)
{
  FaultStage stage("fusedpasses");
  const int F = setup.cols;
  out->bins.clear();
  out->minimum.clear();
  out->maximum.clear();
  if (!fill || F < 1 || setup.offset.size() != static_cast<std::size_t>(F))
  {
    return detail::fail(error, "invalid arguments of the GPU column sums");
  }
  // Held once: the bins, the extremes' keys, the non-finite count and the first one.
  const std::size_t binBytes = static_cast<std::size_t>(F) * kExactExponents * sizeof(unsigned long long);
  const std::size_t totalBytes = binBytes + 2 * F * sizeof(int) + 2 * sizeof(unsigned long long);
  SlabPassBytes pass;
  pass.fixedDevice = totalBytes;
  DeviceBuffer sums;
  SlabStream stream;
  if (!stream.open(streamSetup(setup, pass), error))
  {
    return false;
  }
  MCV_CUDA_TRY(cudaMalloc(&sums.ptr, totalBytes));
  unsigned long long* bins = sums.as<unsigned long long>();
  unsigned long long* nonFinite = bins + static_cast<std::size_t>(F) * kExactExponents;
  unsigned long long* firstBad = nonFinite + 1;
  int* minKey = reinterpret_cast<int*>(firstBad + 1);
  int* maxKey = minKey + F;
  {
    std::vector<int> keys(2 * static_cast<std::size_t>(F));
    std::fill(keys.begin(), keys.begin() + F, orderedKey(std::numeric_limits<float>::infinity()));
    std::fill(keys.begin() + F, keys.end(), orderedKey(-std::numeric_limits<float>::infinity()));
    const unsigned long long none[2] = { 0ull, ~0ull };
    MCV_CUDA_TRY(cudaMemset(bins, 0, binBytes));
    MCV_CUDA_TRY(cudaMemcpy(nonFinite, none, sizeof none, cudaMemcpyHostToDevice));
    MCV_CUDA_TRY(cudaMemcpy(minKey, keys.data(), keys.size() * sizeof(int), cudaMemcpyHostToDevice));
  }
  // The block's bins in shared memory where they fit (24 columns: 48 KiB).
  const std::size_t sharedBytes = static_cast<std::size_t>(F) * kExactExponents * sizeof(unsigned long long);
  int sharedLimit = 0, device = 0;
  MCV_CUDA_TRY(cudaGetDevice(&device));
  MCV_CUDA_TRY(cudaDeviceGetAttribute(&sharedLimit, cudaDevAttrMaxSharedMemoryPerBlockOptin, device));
  const bool sharedBins = sharedBytes <= static_cast<std::size_t>(sharedLimit);
  if (sharedBins)
  {
    MCV_CUDA_TRY(cudaFuncSetAttribute(exactSumsKernel, cudaFuncAttributeMaxDynamicSharedMemorySize,
      static_cast<int>(sharedBytes)));
  }
  const auto launch = [&](Slab& s) -> bool {
    const int S = reduceThreads(F, s.rows);
    exactSumsKernel<<<(S + kThreads - 1) / kThreads, kThreads, sharedBins ? sharedBytes : 0, s.stream>>>(s.features,
      static_cast<std::int64_t>(s.rows), F, S, static_cast<std::uint64_t>(s.firstRow), bins, minKey, maxKey, nonFinite,
      firstBad, sharedBins ? 1 : 0);
    MCV_CUDA_TRY(cudaGetLastError());
    return true;
  };
  const auto done = [&](const Slab& s) -> bool {
    reportProgress(progress, s, setup.grid);
    return true;
  };
  if (!stream.run(fill, launch, done, error))
  {
    copyStats(stream.stats(), stats);
    return false;
  }
  std::vector<unsigned char> host(totalBytes);
  MCV_CUDA_TRY(cudaMemcpy(host.data(), sums.ptr, totalBytes, cudaMemcpyDeviceToHost));
  stream.stats().bytesFromDevice += totalBytes;
  copyStats(stream.stats(), stats);
  const std::size_t nb = static_cast<std::size_t>(F) * kExactExponents;
  out->bins.resize(nb);
  std::memcpy(out->bins.data(), host.data(), binBytes); // two's complement: the signed sums
  unsigned long long counts[2];
  std::memcpy(counts, host.data() + binBytes, sizeof counts);
  out->nonFinite = static_cast<double>(counts[0]);
  out->firstBad = counts[1] == ~0ull ? std::numeric_limits<double>::infinity() : static_cast<double>(counts[1]);
  std::vector<int> keys(2 * static_cast<std::size_t>(F));
  std::memcpy(keys.data(), host.data() + binBytes + sizeof counts, keys.size() * sizeof(int));
  for (int c = 0; c < F; ++c)
  {
    out->minimum.push_back(fromOrderedKey(keys[static_cast<std::size_t>(c)]));
    out->maximum.push_back(fromOrderedKey(keys[static_cast<std::size_t>(F + c)]));
  }
  return true;
}

bool fusedStrata(const FusedPassSetup& setup, const FusedChannelFill& fill, const DeviceStrata& request,
  FusedPassStats* stats, std::string* error)
{
  FaultStage stage("fusedpasses");
  const int F = setup.cols, D = static_cast<int>(request.columns.size());
  const int E = static_cast<int>(request.edges.size());
  if (!fill || F < 1 || setup.offset.size() != static_cast<std::size_t>(F) || D < 1 || !request.stratum ||
    (!request.center.empty() && static_cast<int>(request.center.size()) != D) || E > 255)
  {
    return detail::fail(error, "invalid arguments of the GPU strata");
  }
  for (int c : request.columns)
  {
    if (c < 0 || c >= F)
    {
      return detail::fail(error, "a used column is out of range (GPU strata)");
    }
  }
  // Held once: the columns, centre and edges. Per slot and row: the eligible mask up, the
  // strata down (one byte each, through the slot's pinned buffer).
  const std::size_t paramBytes = D * sizeof(int) + D * sizeof(double) + std::max(1, E) * sizeof(float);
  SlabPassBytes pass;
  pass.fixedDevice = paramBytes;
  pass.perRowDevice = 2;
  pass.perRowPinned = 1;
  DeviceBuffer params, perRow[kSlabSlots];
  SlabStream stream;
  if (!stream.open(streamSetup(setup, pass), error))
  {
    return false;
  }
  MCV_CUDA_TRY(cudaMalloc(&params.ptr, paramBytes));
  double* center = params.as<double>();
  int* columns = reinterpret_cast<int*>(center + D);
  float* edges = reinterpret_cast<float*>(columns + D);
  MCV_CUDA_TRY(cudaMemcpy(columns, request.columns.data(), D * sizeof(int), cudaMemcpyHostToDevice));
  if (!request.center.empty())
  {
    MCV_CUDA_TRY(cudaMemcpy(center, request.center.data(), D * sizeof(double), cudaMemcpyHostToDevice));
  }
  if (E > 0)
  {
    MCV_CUDA_TRY(cudaMemcpy(edges, request.edges.data(), E * sizeof(float), cudaMemcpyHostToDevice));
  }
  for (int i = 0; i < stream.slotsUsed(); ++i)
  {
    MCV_CUDA_TRY(cudaMalloc(&perRow[i].ptr, 2 * stream.slabRows()));
  }
  const auto launch = [&](Slab& s) -> bool {
    unsigned char* mask = perRow[s.slot].as<unsigned char>();
    unsigned char* strata = mask + stream.slabRows();
    if (request.eligible)
    {
      detail::stagingCopy(s.pinned, request.eligible + s.firstRow, s.rows);
      MCV_CUDA_TRY(cudaMemcpyAsync(mask, s.pinned, s.rows, cudaMemcpyHostToDevice, s.stream));
      stream.stats().bytesToDevice += s.rows;
    }
    strataKernel<<<slabBlocksFor(static_cast<std::int64_t>(s.rows)), kThreads, 0, s.stream>>>(s.features,
      static_cast<std::int64_t>(s.rows), F, columns, D, request.center.empty() ? nullptr : center, edges, E,
      request.eligible ? mask : nullptr, request.notEligible, strata);
    MCV_CUDA_TRY(cudaGetLastError());
    MCV_CUDA_TRY(cudaMemcpyAsync(s.pinned, strata, s.rows, cudaMemcpyDeviceToHost, s.stream));
    stream.stats().bytesFromDevice += s.rows;
    return true;
  };
  const auto done = [&](const Slab& s) -> bool {
    detail::stagingCopy(request.stratum + s.firstRow, s.pinned, s.rows);
    reportProgress(request.progress, s, setup.grid);
    return true;
  };
  const bool ok = stream.run(fill, launch, done, error);
  copyStats(stream.stats(), stats);
  return ok;
}

} // namespace cuda
} // namespace mcv
