#include "TopNSelect.cuh"

#include "CudaCheck.h"
#include "HarrisKernel.cuh" // kLevel1Bins

#include <cub/block/block_scan.cuh>
#include <cub/device/device_radix_sort.cuh>
#include <cub/device/device_select.cuh>
#include <thrust/iterator/counting_iterator.h>

#include <algorithm>
#include <climits>
#include <cstring>

namespace mcv
{
namespace cuda
{
namespace detail
{
namespace
{

constexpr int kLevel2Bins = 2048; // bits 20..10
constexpr int kLevel3Bins = 1024; // bits 9..0
constexpr unsigned kMaxFiniteBits = 0x7F7FFFFFu; // FLT_MAX: larger patterns are inf, NaN, < 0
constexpr int kScanThreads = 1024;
constexpr int kHistThreads = 256;

__device__ __forceinline__ bool isCandidateBits(unsigned bits)
{
  return bits - 1u < kMaxFiniteBits; // 1 <= bits <= FLT_MAX bits: R > 0 and finite
}

// One level of the radix select: finds the bin b (bins scanned from the top) with
// count(bins above b) < need <= count(bins >= b), need = N - state.above.
template <int BINS>
__global__ void __launch_bounds__(kScanThreads) scanLevelKernel(
  const unsigned long long* __restrict__ hist, int level, long long N, SelectState* state)
{
  constexpr int PER = BINS / kScanThreads;
  using Scan = cub::BlockScan<unsigned long long, kScanThreads>;
  __shared__ typename Scan::TempStorage temp;
  const int t = threadIdx.x;
  const int hiBin = BINS - 1 - t * PER; // this thread's bins: hiBin, hiBin-1, ... (descending)
  unsigned long long h[PER];
  unsigned long long mine = 0;
#pragma unroll
  for (int j = 0; j < PER; ++j)
  {
    h[j] = hist[hiBin - j];
    mine += h[j];
  }
  const unsigned long long base = level == 1 ? 0ull : state->above;
  const unsigned int prefix = state->prefix;
  unsigned long long before = 0, total = 0;
  Scan(temp).ExclusiveSum(mine, before, total); // also a barrier after the reads of *state
  const unsigned long long need = static_cast<unsigned long long>(N) - base;
  if (level == 1 && total <= static_cast<unsigned long long>(N))
  {
    if (t == 0)
    {
      state->total = total;
      state->takeAll = 1;
      state->above = total;
      state->need = 0;
      state->listSize = total;
      state->prefix = 0;
      state->threshold = 0;
    }
    return;
  }
  unsigned long long run = before;
#pragma unroll
  for (int j = 0; j < PER; ++j)
  {
    const unsigned long long aboveBin = run;
    run += h[j];
    if (aboveBin < need && run >= need)
    {
      const unsigned bin = static_cast<unsigned>(hiBin - j);
      if (level == 1)
      {
        state->total = total;
        state->takeAll = 0;
        state->prefix = bin;
        state->above = aboveBin;
        state->listSize = run;
      }
      else if (level == 2)
      {
        state->prefix = (prefix << 11) | bin;
        state->above = base + aboveBin;
      }
      else
      {
        state->threshold = (prefix << 10) | bin;
        state->above = base + aboveBin;
        state->need = static_cast<unsigned long long>(N) - (base + aboveBin);
      }
    }
  }
}

__device__ __forceinline__ void flushHistogram(
  const unsigned* sh, int bins, unsigned long long* __restrict__ global)
{
  __syncthreads();
  for (int i = threadIdx.x; i < bins; i += blockDim.x)
  {
    if (sh[i])
    {
      atomicAdd(&global[i], static_cast<unsigned long long>(sh[i]));
    }
  }
}

__global__ void __launch_bounds__(kHistThreads) histogramLevel1Kernel(
  const float* __restrict__ scores, long long n, unsigned long long* __restrict__ hist)
{
  __shared__ unsigned sh[kLevel1Bins];
  for (int i = threadIdx.x; i < kLevel1Bins; i += blockDim.x)
  {
    sh[i] = 0;
  }
  __syncthreads();
  for (long long i = blockIdx.x * static_cast<long long>(blockDim.x) + threadIdx.x; i < n;
       i += static_cast<long long>(gridDim.x) * blockDim.x)
  {
    const unsigned bits = __float_as_uint(scores[i]);
    if (isCandidateBits(bits))
    {
      atomicAdd(&sh[bits >> 21], 1u);
    }
  }
  flushHistogram(sh, kLevel1Bins, hist);
}

// listBits[i] = bits of scores[listIdx[i]]; with `withLevel2`, the level-2 histogram of the
// entries in the level-1 bin `bin1`.
__global__ void __launch_bounds__(kHistThreads) gatherLevel2Kernel(const float* __restrict__ scores,
  const long long* __restrict__ listIdx, long long m, unsigned* __restrict__ listBits,
  int withLevel2, unsigned bin1, unsigned long long* __restrict__ hist2)
{
  __shared__ unsigned sh[kLevel2Bins];
  if (withLevel2)
  {
    for (int i = threadIdx.x; i < kLevel2Bins; i += blockDim.x)
    {
      sh[i] = 0;
    }
    __syncthreads();
  }
  for (long long i = blockIdx.x * static_cast<long long>(blockDim.x) + threadIdx.x; i < m;
       i += static_cast<long long>(gridDim.x) * blockDim.x)
  {
    const unsigned bits = __float_as_uint(scores[listIdx[i]]);
    listBits[i] = bits;
    if (withLevel2 && (bits >> 21) == bin1)
    {
      atomicAdd(&sh[(bits >> 10) & 0x7FFu], 1u);
    }
  }
  if (withLevel2)
  {
    flushHistogram(sh, kLevel2Bins, hist2);
  }
}

__global__ void __launch_bounds__(kHistThreads) level3Kernel(const unsigned* __restrict__ listBits,
  long long m, const SelectState* __restrict__ state, unsigned long long* __restrict__ hist3)
{
  __shared__ unsigned sh[kLevel3Bins];
  for (int i = threadIdx.x; i < kLevel3Bins; i += blockDim.x)
  {
    sh[i] = 0;
  }
  __syncthreads();
  const unsigned prefix = state->prefix; // 22 bits fixed by levels 1 and 2
  for (long long i = blockIdx.x * static_cast<long long>(blockDim.x) + threadIdx.x; i < m;
       i += static_cast<long long>(gridDim.x) * blockDim.x)
  {
    const unsigned bits = listBits[i];
    if ((bits >> 10) == prefix)
    {
      atomicAdd(&sh[bits & 0x3FFu], 1u);
    }
  }
  flushHistogram(sh, kLevel3Bins, hist3);
}

// Survivors in slots: [0, above) entries > T, [above, above + need) the first ties, the
// rest padding (key 0 sorts last; real keys are >= 1).
__global__ void assembleKernel(const long long* __restrict__ abovePos,
  const long long* __restrict__ tiePos, const unsigned* __restrict__ listBits,
  const long long* __restrict__ listIdx, const SelectState* __restrict__ state, int N,
  unsigned* __restrict__ keys, long long* __restrict__ vals)
{
  const int s = blockIdx.x * blockDim.x + threadIdx.x;
  if (s >= N)
  {
    return;
  }
  const unsigned long long above = state->above, need = state->need;
  const unsigned long long us = static_cast<unsigned long long>(s);
  long long p = -1;
  if (us < above)
  {
    p = abovePos[s];
  }
  else if (us < above + need)
  {
    p = tiePos[us - above];
  }
  if (p >= 0)
  {
    keys[s] = listBits[p];
    vals[s] = listIdx[p];
  }
  else
  {
    keys[s] = 0u;
    vals[s] = LLONG_MAX;
  }
}

struct AtLeastBits // compaction predicate over voxel indices
{
  const float* scores;
  unsigned low;
  __device__ bool operator()(long long i) const
  {
    const unsigned bits = __float_as_uint(__ldg(scores + i));
    return bits >= low && bits <= kMaxFiniteBits;
  }
};

struct AboveThreshold // over list positions
{
  const unsigned* bits;
  const SelectState* state;
  __device__ bool operator()(long long p) const { return bits[p] > state->threshold; }
};

struct AtThreshold
{
  const unsigned* bits;
  const SelectState* state;
  __device__ bool operator()(long long p) const { return bits[p] == state->threshold; }
};

int gridFor(long long items, int sms)
{
  const long long blocks = (items + kHistThreads - 1) / kHistThreads;
  return static_cast<int>(std::max(1ll, std::min<long long>(blocks, 8ll * std::max(sms, 1))));
}

} // namespace

TopNSelector::~TopNSelector()
{
  release();
}

void TopNSelector::release()
{
  // Errors on free are ignored: nothing useful can be done with them here.
  for (void* p : { static_cast<void*>(Hist), static_cast<void*>(State), static_cast<void*>(Counts),
         static_cast<void*>(ListIdx), static_cast<void*>(ListBits), static_cast<void*>(TiePos),
         static_cast<void*>(AbovePos), static_cast<void*>(KeysIn), static_cast<void*>(KeysOut),
         static_cast<void*>(ValsIn), static_cast<void*>(ValsOut), static_cast<void*>(Temp) })
  {
    if (p)
    {
      cudaFree(p);
    }
  }
  for (void* p : { static_cast<void*>(HostState), static_cast<void*>(HostCounts),
         static_cast<void*>(HostKeys), static_cast<void*>(HostVals) })
  {
    if (p)
    {
      cudaFreeHost(p);
    }
  }
  Hist = nullptr;
  State = nullptr;
  Counts = nullptr;
  ListIdx = nullptr;
  ListBits = nullptr;
  TiePos = nullptr;
  AbovePos = nullptr;
  KeysIn = KeysOut = nullptr;
  ValsIn = ValsOut = nullptr;
  Temp = nullptr;
  HostState = nullptr;
  HostCounts = nullptr;
  HostKeys = nullptr;
  HostVals = nullptr;
  ListCap = ListBitsCap = TieCap = AboveCap = KeysInCap = KeysOutCap = ValsInCap = ValsOutCap = 0;
  TempCap = HostCap = 0;
}

template <typename T>
bool TopNSelector::grow(T*& buffer, std::size_t& capacity, std::size_t wanted, std::string* error)
{
  if (wanted <= capacity && buffer)
  {
    return true;
  }
  if (buffer)
  {
    MCV_CUDA_TRY(cudaFree(buffer));
    buffer = nullptr;
    capacity = 0;
  }
  const std::size_t n = std::max<std::size_t>(wanted + wanted / 4, 1024);
  MCV_CUDA_TRY(cudaMalloc(reinterpret_cast<void**>(&buffer), n * sizeof(T)));
  capacity = n;
  return true;
}

bool TopNSelector::growHost(std::size_t N, std::string* error)
{
  if (N <= HostCap && HostKeys)
  {
    return true;
  }
  if (HostKeys)
  {
    MCV_CUDA_TRY(cudaFreeHost(HostKeys));
    HostKeys = nullptr;
  }
  if (HostVals)
  {
    MCV_CUDA_TRY(cudaFreeHost(HostVals));
    HostVals = nullptr;
  }
  HostCap = 0;
  MCV_CUDA_TRY(cudaMallocHost(reinterpret_cast<void**>(&HostKeys), N * sizeof(unsigned)));
  MCV_CUDA_TRY(cudaMallocHost(reinterpret_cast<void**>(&HostVals), N * sizeof(long long)));
  HostCap = N;
  return true;
}

bool TopNSelector::reset(cudaStream_t stream, std::string* error)
{
  if (!Hist)
  {
    MCV_CUDA_TRY(cudaMalloc(reinterpret_cast<void**>(&Hist),
      (kLevel1Bins + kLevel2Bins + kLevel3Bins) * sizeof(unsigned long long)));
    MCV_CUDA_TRY(cudaMalloc(reinterpret_cast<void**>(&State), sizeof(SelectState)));
    MCV_CUDA_TRY(cudaMalloc(reinterpret_cast<void**>(&Counts), 4 * sizeof(long long)));
    MCV_CUDA_TRY(cudaMallocHost(reinterpret_cast<void**>(&HostState), sizeof(SelectState)));
    MCV_CUDA_TRY(cudaMallocHost(reinterpret_cast<void**>(&HostCounts), 4 * sizeof(long long)));
    int device = 0;
    MCV_CUDA_TRY(cudaGetDevice(&device));
    MCV_CUDA_TRY(cudaDeviceGetAttribute(&SmCount, cudaDevAttrMultiProcessorCount, device));
  }
  MCV_CUDA_TRY(cudaMemsetAsync(
    Hist, 0, (kLevel1Bins + kLevel2Bins + kLevel3Bins) * sizeof(unsigned long long), stream));
  MCV_CUDA_TRY(cudaMemsetAsync(State, 0, sizeof(SelectState), stream));
  MCV_CUDA_TRY(cudaMemsetAsync(Counts, 0, 4 * sizeof(long long), stream));
  return true;
}

bool TopNSelector::histogramLevel1(
  const float* scores, std::size_t n, cudaStream_t stream, std::string* error)
{
  const long long items = static_cast<long long>(n);
  histogramLevel1Kernel<<<gridFor(items, SmCount), kHistThreads, 0, stream>>>(scores, items, Hist);
  MCV_CUDA_TRY(cudaGetLastError());
  return true;
}

bool TopNSelector::select(const float* scores, std::size_t n, int N, cudaStream_t stream,
  InterestPoints& out, std::string* error, cudaEvent_t beforeDownload, cudaEvent_t afterDownload)
{
  out.indices.clear();
  out.scores.clear();
  if (!Hist)
  {
    return fail(error, "TopNSelector::select called before reset()");
  }
  unsigned long long* hist1 = Hist;
  unsigned long long* hist2 = Hist + kLevel1Bins;
  unsigned long long* hist3 = hist2 + kLevel2Bins;
  const auto recordDownload = [&](cudaEvent_t e) -> cudaError_t {
    return e ? cudaEventRecord(e, stream) : cudaSuccess;
  };
  if (N <= 0 || n == 0)
  {
    MCV_CUDA_TRY(recordDownload(beforeDownload));
    MCV_CUDA_TRY(recordDownload(afterDownload));
    MCV_CUDA_TRY(cudaStreamSynchronize(stream));
    return true;
  }

  // Level 1 -> list size (the one host synchronisation inside the selection).
  scanLevelKernel<kLevel1Bins><<<1, kScanThreads, 0, stream>>>(hist1, 1, N, State);
  MCV_CUDA_TRY(cudaGetLastError());
  MCV_CUDA_TRY(cudaMemcpyAsync(HostState, State, sizeof(SelectState), cudaMemcpyDeviceToHost, stream));
  MCV_CUDA_TRY(cudaStreamSynchronize(stream));
  const SelectState level1 = *HostState;
  const long long m = static_cast<long long>(level1.listSize);
  if (m == 0)
  {
    MCV_CUDA_TRY(recordDownload(beforeDownload));
    MCV_CUDA_TRY(recordDownload(afterDownload));
    MCV_CUDA_TRY(cudaStreamSynchronize(stream));
    return true;
  }
  const std::size_t um = static_cast<std::size_t>(m), uN = static_cast<std::size_t>(N);
  if (!grow(ListIdx, ListCap, um, error) || !grow(ListBits, ListBitsCap, um, error) ||
    !grow(TiePos, TieCap, um, error) || !grow(AbovePos, AboveCap, uN, error) ||
    !grow(KeysIn, KeysInCap, uN, error) || !grow(KeysOut, KeysOutCap, uN, error) ||
    !grow(ValsIn, ValsInCap, uN, error) || !grow(ValsOut, ValsOutCap, uN, error) ||
    !growHost(uN, error))
  {
    return false;
  }

  // Temporary storage for every CUB call of this selection.
  const thrust::counting_iterator<long long> first(0);
  const AtLeastBits compactOp{ scores, level1.takeAll ? 1u : (level1.prefix << 21) };
  const AboveThreshold aboveOp{ ListBits, State };
  const AtThreshold tieOp{ ListBits, State };
  std::size_t bytesCompact = 0, bytesAbove = 0, bytesTie = 0, bytesSort = 0;
  MCV_CUDA_TRY(cub::DeviceSelect::If(nullptr, bytesCompact, first, ListIdx, Counts,
    static_cast<long long>(n), compactOp, stream));
  MCV_CUDA_TRY(cub::DeviceSelect::If(nullptr, bytesAbove, first, AbovePos, Counts + 1, m, aboveOp, stream));
  MCV_CUDA_TRY(cub::DeviceSelect::If(nullptr, bytesTie, first, TiePos, Counts + 2, m, tieOp, stream));
  MCV_CUDA_TRY(cub::DeviceRadixSort::SortPairsDescending(
    nullptr, bytesSort, KeysIn, KeysOut, ValsIn, ValsOut, N, 0, 32, stream));
  const std::size_t bytes = std::max(std::max(bytesCompact, bytesAbove), std::max(bytesTie, bytesSort));
  if (!grow(Temp, TempCap, bytes, error))
  {
    return false;
  }

  // Compaction: candidates in or above the level-1 bin, in index order.
  std::size_t tb = TempCap;
  MCV_CUDA_TRY(cub::DeviceSelect::If(
    Temp, tb, first, ListIdx, Counts, static_cast<long long>(n), compactOp, stream));

  // Levels 2 and 3 on the list -> exact threshold.
  gatherLevel2Kernel<<<gridFor(m, SmCount), kHistThreads, 0, stream>>>(
    scores, ListIdx, m, ListBits, level1.takeAll ? 0 : 1, level1.prefix, hist2);
  MCV_CUDA_TRY(cudaGetLastError());
  if (!level1.takeAll)
  {
    scanLevelKernel<kLevel2Bins><<<1, kScanThreads, 0, stream>>>(hist2, 2, N, State);
    MCV_CUDA_TRY(cudaGetLastError());
    level3Kernel<<<gridFor(m, SmCount), kHistThreads, 0, stream>>>(ListBits, m, State, hist3);
    MCV_CUDA_TRY(cudaGetLastError());
    scanLevelKernel<kLevel3Bins><<<1, kScanThreads, 0, stream>>>(hist3, 3, N, State);
    MCV_CUDA_TRY(cudaGetLastError());
  }

  // Survivors: > T (fewer than N), then the first `need` ties in index order; sorted.
  tb = TempCap;
  MCV_CUDA_TRY(cub::DeviceSelect::If(Temp, tb, first, AbovePos, Counts + 1, m, aboveOp, stream));
  if (!level1.takeAll)
  {
    tb = TempCap;
    MCV_CUDA_TRY(cub::DeviceSelect::If(Temp, tb, first, TiePos, Counts + 2, m, tieOp, stream));
  }
  assembleKernel<<<(N + 255) / 256, 256, 0, stream>>>(
    AbovePos, TiePos, ListBits, ListIdx, State, N, KeysIn, ValsIn);
  MCV_CUDA_TRY(cudaGetLastError());
  tb = TempCap;
  MCV_CUDA_TRY(cub::DeviceRadixSort::SortPairsDescending(
    Temp, tb, KeysIn, KeysOut, ValsIn, ValsOut, N, 0, 32, stream));

  MCV_CUDA_TRY(recordDownload(beforeDownload));
  MCV_CUDA_TRY(cudaMemcpyAsync(HostKeys, KeysOut, uN * sizeof(unsigned), cudaMemcpyDeviceToHost, stream));
  MCV_CUDA_TRY(cudaMemcpyAsync(HostVals, ValsOut, uN * sizeof(long long), cudaMemcpyDeviceToHost, stream));
  MCV_CUDA_TRY(cudaMemcpyAsync(HostState, State, sizeof(SelectState), cudaMemcpyDeviceToHost, stream));
  MCV_CUDA_TRY(cudaMemcpyAsync(HostCounts, Counts, 4 * sizeof(long long), cudaMemcpyDeviceToHost, stream));
  MCV_CUDA_TRY(recordDownload(afterDownload));
  MCV_CUDA_TRY(cudaStreamSynchronize(stream));

  // Consistency of the device-side bookkeeping (a failure here is a bug, reported so the
  // caller falls back to the CPU rather than returning a wrong set).
  const SelectState final = *HostState;
  const unsigned long long count = final.above + final.need;
  if (HostCounts[0] != m || static_cast<unsigned long long>(HostCounts[1]) != final.above ||
    count > static_cast<unsigned long long>(N) ||
    (!level1.takeAll && count != static_cast<unsigned long long>(N)) ||
    (level1.takeAll && count != level1.total))
  {
    return fail(error,
      "GPU top-N selection is inconsistent (list " + std::to_string(HostCounts[0]) + "/" +
        std::to_string(m) + ", above " + std::to_string(HostCounts[1]) + "/" +
        std::to_string(final.above) + ", need " + std::to_string(final.need) + ")");
  }
  out.indices.resize(count);
  out.scores.resize(count);
  for (std::size_t i = 0; i < count; ++i)
  {
    out.indices[i] = HostVals[i];
    unsigned bits = HostKeys[i];
    float s;
    static_assert(sizeof(s) == sizeof(bits), "float is 32 bits");
    std::memcpy(&s, &bits, sizeof(s));
    out.scores[i] = s;
  }
  return true;
}

} // namespace detail
} // namespace cuda
} // namespace mcv
