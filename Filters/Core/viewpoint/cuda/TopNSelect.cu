#include "TopNSelect.cuh"

#include "cuda/CudaCheck.h"
#include "HarrisKernel.cuh" // kLevel1Bins, kHarrisTileX

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

using BlockScanU64 = cub::BlockScan<unsigned long long, kScanThreads>;

// Finds, in a histogram of BINS counters scanned from the top bin down, the bin b with
// count(bins above b) < need <= count(bins >= b). Called by all kScanThreads threads; the
// one thread owning b writes *bin and *aboveBin. `total` receives the histogram's sum.
template <int BINS, typename Count>
__device__ void findBin(const Count* hist, unsigned long long need, BlockScanU64::TempStorage& temp,
  unsigned* bin, unsigned long long* aboveBin, unsigned long long* total)
{
  constexpr int PER = BINS / kScanThreads;
  const int hiBin = BINS - 1 - static_cast<int>(threadIdx.x) * PER; // hiBin, hiBin-1, ...
  unsigned long long h[PER];
  unsigned long long mine = 0;
#pragma unroll
  for (int j = 0; j < PER; ++j)
  {
    h[j] = hist[hiBin - j];
    mine += h[j];
  }
  unsigned long long before = 0, sum = 0;
  BlockScanU64(temp).ExclusiveSum(mine, before, sum);
  *total = sum;
  unsigned long long run = before;
#pragma unroll
  for (int j = 0; j < PER; ++j)
  {
    const unsigned long long above = run;
    run += h[j];
    if (above < need && run >= need)
    {
      *bin = static_cast<unsigned>(hiBin - j);
      *aboveBin = above;
    }
  }
}

// One level of the radix select over a global histogram (single block). Level 1 also
// decides the compaction bound and, with `fastCapacity`, whether the fast path fits.
template <int BINS>
__global__ void __launch_bounds__(kScanThreads) scanLevelKernel(const unsigned long long* __restrict__ hist,
  int level, long long N, long long fastCapacity, SelectState* state)
{
  __shared__ BlockScanU64::TempStorage temp;
  __shared__ unsigned sBin;
  __shared__ unsigned long long sAbove;
  const unsigned long long base = level == 1 ? 0ull : state->above;
  const unsigned prefix = state->prefix;
  const unsigned long long need = static_cast<unsigned long long>(N) - base;
  unsigned long long total = 0;
  findBin<BINS>(hist, need, temp, &sBin, &sAbove, &total); // reads of *state precede: barrier
  __syncthreads();
  if (threadIdx.x != 0)
  {
    return;
  }
  if (level == 1)
  {
    state->total = total;
    state->overflow = 0;
    if (total <= static_cast<unsigned long long>(N))
    {
      state->takeAll = 1;
      state->above = total;
      state->need = 0;
      state->listSize = total;
      state->prefix = 0;
      state->threshold = 0;
      state->low = 1u;
    }
    else
    {
      state->takeAll = 0;
      state->prefix = sBin;
      state->above = sAbove;
      // count of bins >= b1 = count above + the bin itself
      state->listSize = sAbove + hist[sBin];
      state->low = sBin << 21;
    }
    if (static_cast<long long>(state->listSize) > fastCapacity) // -1: always the slow path
    {
      state->overflow = 1;
      state->low = 0xFFFFFFFFu; // the fast compaction selects nothing
    }
  }
  else if (level == 2)
  {
    state->prefix = (prefix << 11) | sBin;
    state->above = base + sAbove;
  }
  else
  {
    state->threshold = (prefix << 10) | sBin;
    state->above = base + sAbove;
    state->need = static_cast<unsigned long long>(N) - (base + sAbove);
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

// ---------------------------------------------------------------------------------------
// Fast path: a bandwidth-bound compaction (list order arbitrary), then one block finds the
// exact threshold, gathers the survivors and sorts them (bitonic, in shared memory).
// ---------------------------------------------------------------------------------------

// The position in the list of the first of this lane's c entries: an inclusive scan of
// the warp's counts and one atomic per warp that holds any. Called by all lanes.
__device__ __forceinline__ unsigned long long warpListPosition(
  unsigned long long* count, unsigned c, int lane)
{
  unsigned incl = c;
#pragma unroll
  for (int o = 1; o < 32; o <<= 1)
  {
    const unsigned y = __shfl_up_sync(0xffffffffu, incl, o);
    if (lane >= o)
    {
      incl += y;
    }
  }
  unsigned long long pos = 0;
  if (lane == 31 && incl > 0)
  {
    pos = atomicAdd(count, static_cast<unsigned long long>(incl));
  }
  return __shfl_sync(0xffffffffu, pos, 31) + (incl - c);
}

constexpr int kCompactThreads = 256;

// Candidates with bits >= state->low into list[0, count) in no particular order: float4
// loads, one atomic per warp that holds any (they are rare: a few times N in the volume).
__global__ void __launch_bounds__(kCompactThreads) compactKernel(const float* __restrict__ scores,
  long long n, const SelectState* __restrict__ state, ListEntry* __restrict__ list, long long cap,
  unsigned long long* __restrict__ count)
{
  const unsigned low = state->low;
  if (low == 0xFFFFFFFFu)
  {
    return; // the list would not fit: the host runs the slow path
  }
  const int lane = threadIdx.x & 31;
  const long long n4 = n / 4;
  const float4* s4 = reinterpret_cast<const float4*>(scores);
  const long long stride = static_cast<long long>(gridDim.x) * blockDim.x;
  for (long long base = static_cast<long long>(blockIdx.x) * blockDim.x; base < n4; base += stride)
  {
    const long long v = base + threadIdx.x; // warps iterate together (collectives below)
    float4 q = make_float4(0.f, 0.f, 0.f, 0.f);
    if (v < n4)
    {
      q = __ldg(s4 + v);
    }
    const unsigned b[4] = { __float_as_uint(q.x), __float_as_uint(q.y), __float_as_uint(q.z),
      __float_as_uint(q.w) };
    bool sel[4];
    unsigned c = 0;
#pragma unroll
    for (int j = 0; j < 4; ++j)
    {
      sel[j] = v < n4 && b[j] >= low && b[j] <= kMaxFiniteBits;
      c += sel[j];
    }
    if (__any_sync(0xffffffffu, c != 0))
    {
      unsigned long long pos = warpListPosition(count, c, lane);
#pragma unroll
      for (int j = 0; j < 4; ++j)
      {
        if (sel[j])
        {
          if (pos < static_cast<unsigned long long>(cap))
          {
            list[pos] = ListEntry{ b[j], 0u, 4 * v + j };
          }
          ++pos;
        }
      }
    }
  }
  if (blockIdx.x == 0 && threadIdx.x < n - 4 * n4) // the last n % 4 scores
  {
    const long long i = 4 * n4 + threadIdx.x;
    const unsigned bits = __float_as_uint(scores[i]);
    if (bits >= low && bits <= kMaxFiniteBits)
    {
      const unsigned long long pos = atomicAdd(count, 1ull);
      if (pos < static_cast<unsigned long long>(cap))
      {
        list[pos] = ListEntry{ bits, 0u, i };
      }
    }
  }
}

// compactKernel from the row maxima: the same list (in another order), reading only the
// segments (two rows of up to 32 scores) whose maximum is >= low. Each lane takes one
// segment; a lane whose segment holds one reads its scores, so a warp's hits are read
// together.
__global__ void __launch_bounds__(kCompactThreads) compactRowsKernel(const float* __restrict__ scores,
  const RowMaxima rows, long long segments, const SelectState* __restrict__ state,
  ListEntry* __restrict__ list, long long cap, unsigned long long* __restrict__ count)
{
  const unsigned low = state->low;
  if (low == 0xFFFFFFFFu)
  {
    return; // the list would not fit: the host runs the slow path
  }
  static_assert(kHarrisTileX == 32, "a segment's row is one score per lane");
  const int lane = threadIdx.x & 31;
  const int nx = rows.nx, ny = rows.ny, tilesX = rows.segmentsPerRow;
  const long long pairsY = (ny + 1) / 2;
  const long long stride = static_cast<long long>(gridDim.x) * blockDim.x;
  for (long long base = static_cast<long long>(blockIdx.x) * blockDim.x; base < segments; base += stride)
  {
    const long long seg = base + threadIdx.x; // warps iterate together (collectives below)
    const bool hit = seg < segments && __ldg(rows.max + seg) >= low;
    if (!__any_sync(0xffffffffu, hit))
    {
      continue;
    }
    long long first = 0; // index of the segment's first score; the second row is nx on
    unsigned b[64];      // row 0 in 0..31, row 1 in 32..63 (0 past the grid)
    unsigned c = 0;
    if (hit)
    {
      const long long zp = seg / tilesX; // slice * pairsY + pair
      const int x0 = static_cast<int>(seg - zp * tilesX) * kHarrisTileX;
      const long long z = zp / pairsY;
      const int y = 2 * static_cast<int>(zp - z * pairsY);
      const int len = min(32, nx - x0);
      const bool second = y + 1 < ny;
      first = (z * ny + y) * nx + x0;
#pragma unroll
      for (int j = 0; j < 32; ++j)
      {
        b[j] = j < len ? __float_as_uint(__ldg(scores + first + j)) : 0u;
        b[32 + j] = second && j < len ? __float_as_uint(__ldg(scores + first + nx + j)) : 0u;
      }
#pragma unroll
      for (int j = 0; j < 64; ++j)
      {
        c += b[j] >= low && b[j] <= kMaxFiniteBits;
      }
    }
    unsigned long long pos = warpListPosition(count, c, lane);
    if (c)
    {
#pragma unroll
      for (int j = 0; j < 64; ++j)
      {
        if (b[j] >= low && b[j] <= kMaxFiniteBits)
        {
          if (pos < static_cast<unsigned long long>(cap))
          {
            list[pos] = ListEntry{ b[j], 0u, first + (j < 32 ? j : nx + j - 32) };
          }
          ++pos;
        }
      }
    }
  }
}

// "a ranks before b": higher score first, then lower index.
__device__ __forceinline__ bool ranksBefore(unsigned ka, long long ia, unsigned kb, long long ib)
{
  return ka > kb || (ka == kb && ia < ib);
}

// In-place bitonic sort of P (a power of two <= 2 * kScanThreads) indices, ascending (the
// ties at the threshold, when more exist than places). Called by the whole block.
__device__ void bitonicSortIndices(long long* idx, int P)
{
  for (int k = 2; k <= P; k <<= 1)
  {
    for (int j = k >> 1; j > 0; j >>= 1)
    {
      for (int i = threadIdx.x; i < P / 2; i += blockDim.x)
      {
        const int lo = 2 * j * (i / j) + (i % j), hi = lo + j;
        const bool up = (lo & k) == 0; // this run ends up ascending
        const long long ilo = idx[lo], ihi = idx[hi];
        if (up ? ihi < ilo : ilo < ihi)
        {
          idx[lo] = ihi;
          idx[hi] = ilo;
        }
      }
      __syncthreads();
    }
  }
}

constexpr int kFastMaxN = 2 * kScanThreads; // survivors gathered in one block
static_assert(kFastMaxN == kTopNFastMaxN, "the header's fast-path limit is this one");
constexpr int kFastMaxTies = 2048;           // ties at the threshold sortable in one block

__global__ void __launch_bounds__(kScanThreads) finishKernel(const ListEntry* __restrict__ list,
  const long long* __restrict__ listCount, SelectState* state, int N,
  unsigned* __restrict__ survivorKeys, long long* __restrict__ survivorVals)
{
  // Phase 1 uses the histograms and the scan, phase 2 the sort buffers (same storage).
  __shared__ union
  {
    struct
    {
      unsigned h2[kLevel2Bins];
      unsigned h3[kLevel3Bins];
      BlockScanU64::TempStorage temp;
    } levels;
    struct
    {
      unsigned keys[kFastMaxN];
      long long vals[kFastMaxN];
      long long ties[kFastMaxTies];
    } sort;
  } sm;
  __shared__ unsigned sBin;
  __shared__ unsigned long long sAbove;
  __shared__ unsigned sCountAbove, sCountTies;
  const int t = threadIdx.x;
  if (state->overflow)
  {
    return; // the list did not fit: the host runs the slow path
  }
  const long long m = *listCount;
  const bool takeAll = state->takeAll != 0;
  unsigned threshold = 0;
  unsigned long long above = 0, need = 0, total = 0;
  if (takeAll)
  {
    above = static_cast<unsigned long long>(m);
  }
  else
  {
    const unsigned bin1 = state->prefix;
    above = state->above;
    for (int i = t; i < kLevel2Bins; i += kScanThreads)
      sm.levels.h2[i] = 0;
    for (int i = t; i < kLevel3Bins; i += kScanThreads)
      sm.levels.h3[i] = 0;
    __syncthreads();
    for (long long i = t; i < m; i += kScanThreads)
    {
      const unsigned bits = list[i].bits;
      if ((bits >> 21) == bin1)
        atomicAdd(&sm.levels.h2[(bits >> 10) & 0x7FFu], 1u);
    }
    __syncthreads();
    findBin<kLevel2Bins>(sm.levels.h2, static_cast<unsigned long long>(N) - above,
      sm.levels.temp, &sBin, &sAbove, &total);
    __syncthreads();
    const unsigned prefix = (bin1 << 11) | sBin;
    above += sAbove;
    __syncthreads(); // sBin/sAbove are read by all before being written again
    for (long long i = t; i < m; i += kScanThreads)
    {
      const unsigned bits = list[i].bits;
      if ((bits >> 10) == prefix)
        atomicAdd(&sm.levels.h3[bits & 0x3FFu], 1u);
    }
    __syncthreads();
    findBin<kLevel3Bins>(sm.levels.h3, static_cast<unsigned long long>(N) - above,
      sm.levels.temp, &sBin, &sAbove, &total);
    __syncthreads();
    threshold = (prefix << 10) | sBin;
    above += sAbove;
    need = static_cast<unsigned long long>(N) - above;
    __syncthreads(); // the histograms are dead from here: their storage becomes the sort buffers
  }

  // Survivors: entries > T (fewer than N, any order) and the ties == T.
  if (t == 0)
  {
    sCountAbove = 0;
    sCountTies = 0;
  }
  __syncthreads();
  for (long long i = t; i < m; i += kScanThreads)
  {
    const ListEntry e = list[i];
    if (e.bits > threshold)
    {
      const unsigned slot = atomicAdd(&sCountAbove, 1u);
      if (slot < static_cast<unsigned>(kFastMaxN))
      {
        sm.sort.keys[slot] = e.bits;
        sm.sort.vals[slot] = e.index;
      }
    }
    else if (!takeAll && e.bits == threshold)
    {
      const unsigned r = atomicAdd(&sCountTies, 1u);
      if (r < static_cast<unsigned>(kFastMaxTies))
      {
        sm.sort.ties[r] = e.index;
      }
    }
  }
  __syncthreads();
  const unsigned nAbove = sCountAbove, nTies = sCountTies;
  if (nAbove != above || nTies < need)
  {
    if (t == 0)
      state->overflow = 2; // bookkeeping mismatch: the host redoes it on the slow path
    return;
  }
  if (nTies > need)
  {
    // More ties than places: the lowest indices win (the CPU's order).
    if (nTies > static_cast<unsigned>(kFastMaxTies))
    {
      if (t == 0)
        state->overflow = 1; // too many ties for one block: the slow path
      return;
    }
    int P = 2;
    while (P < static_cast<int>(nTies))
      P <<= 1;
    for (int i = static_cast<int>(nTies) + t; i < P; i += kScanThreads)
      sm.sort.ties[i] = LLONG_MAX;
    __syncthreads();
    bitonicSortIndices(sm.sort.ties, P);
  }
  const int count = static_cast<int>(above + need);
  for (int s = static_cast<int>(above) + t; s < count; s += kScanThreads)
  {
    sm.sort.keys[s] = threshold;
    sm.sort.vals[s] = sm.sort.ties[s - static_cast<int>(above)];
  }
  __syncthreads();
  for (int s = t; s < count; s += kScanThreads) // unsorted: rankSortKernel orders them
  {
    survivorKeys[s] = sm.sort.keys[s];
    survivorVals[s] = sm.sort.vals[s];
  }
  if (t == 0)
  {
    state->threshold = threshold;
    state->above = above;
    state->need = need;
  }
}

// The survivors of finishKernel (above + need <= N <= kFastMaxN of them, unsorted) in rank
// order: each survivor's place is the number of survivors that rank before it, counted by
// kRankLanes threads over strided parts of the list held in shared memory; the places are
// distinct (indices are). Spread over N / 16 blocks instead of a one-block bitonic sort,
// whose 66 barrier-separated steps ran on a single SM. Slots [count, N) get the padding
// (key 0, index LLONG_MAX).
constexpr int kRankLanes = 16;
constexpr int kRankThreads = 256;

__global__ void __launch_bounds__(kRankThreads) rankSortKernel(const unsigned* __restrict__ keysIn,
  const long long* __restrict__ valsIn, const SelectState* __restrict__ state, int N,
  unsigned* __restrict__ keysOut, long long* __restrict__ valsOut)
{
  __shared__ unsigned sk[kFastMaxN];
  __shared__ long long sv[kFastMaxN];
  if (state->overflow)
  {
    return; // the host runs the slow path
  }
  const int count = static_cast<int>(state->above + state->need);
  for (int i = threadIdx.x; i < count; i += kRankThreads)
  {
    sk[i] = keysIn[i];
    sv[i] = valsIn[i];
  }
  __syncthreads();
  const int e = static_cast<int>((blockIdx.x * kRankThreads + threadIdx.x) / kRankLanes);
  const int part = static_cast<int>(threadIdx.x % kRankLanes);
  unsigned ke = 0u;
  long long ie = LLONG_MAX;
  unsigned rank = 0;
  if (e < count)
  {
    ke = sk[e];
    ie = sv[e];
    for (int j = part; j < count; j += kRankLanes)
    {
      rank += ranksBefore(sk[j], sv[j], ke, ie) ? 1u : 0u;
    }
  }
#pragma unroll
  for (int o = kRankLanes / 2; o > 0; o >>= 1)
  {
    rank += __shfl_xor_sync(0xffffffffu, rank, o);
  }
  if (part == 0)
  {
    if (e < count)
    {
      keysOut[rank] = ke;
      valsOut[rank] = ie;
    }
    else if (e < N)
    {
      keysOut[e] = 0u;
      valsOut[e] = LLONG_MAX;
    }
  }
}

// ---------------------------------------------------------------------------------------
// Slow path kernels (long lists)
// ---------------------------------------------------------------------------------------

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

// ---------------------------------------------------------------------------------------
// CUB functors
// ---------------------------------------------------------------------------------------

struct AtLeastBits // slow compaction: the bound is known on the host
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

std::size_t alignUp(std::size_t x, std::size_t a)
{
  return (x + a - 1) / a * a;
}

} // namespace

TopNSelector::~TopNSelector()
{
  release();
}

void TopNSelector::release()
{
  // Errors on free are ignored: nothing useful can be done with them here.
  for (void* p : { static_cast<void*>(Hist), static_cast<void*>(Result), static_cast<void*>(FastList),
         static_cast<void*>(ListIdx), static_cast<void*>(ListBits), static_cast<void*>(TiePos),
         static_cast<void*>(AbovePos), static_cast<void*>(KeysIn), static_cast<void*>(ValsIn),
         static_cast<void*>(Temp) })
  {
    if (p)
    {
      cudaFree(p);
    }
  }
  if (HostResult)
  {
    cudaFreeHost(HostResult);
  }
  Hist = nullptr;
  Result = HostResult = nullptr;
  ResultBytes = 0;
  ResultN = 0;
  State = nullptr;
  Counts = nullptr;
  FastList = nullptr;
  ListIdx = nullptr;
  ListBits = nullptr;
  TiePos = nullptr;
  AbovePos = nullptr;
  KeysIn = KeysOut = nullptr;
  ValsIn = ValsOut = nullptr;
  Temp = nullptr;
  ListCap = ListBitsCap = TieCap = AboveCap = KeysInCap = ValsInCap = TempCap = 0;
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

bool TopNSelector::reset(int N, cudaStream_t stream, std::string* error)
{
  N = std::max(N, 1);
  // Each piece on its own: after a failure half-way, the next call allocates what is missing.
  if (!Hist)
  {
    MCV_CUDA_TRY(cudaMalloc(reinterpret_cast<void**>(&Hist),
      (kLevel1Bins + kLevel2Bins + kLevel3Bins) * sizeof(unsigned long long)));
  }
  if (!FastList)
  {
    MCV_CUDA_TRY(cudaMalloc(reinterpret_cast<void**>(&FastList), kFastListCapacity * sizeof(ListEntry)));
  }
  if (SmCount <= 0)
  {
    int device = 0;
    MCV_CUDA_TRY(cudaGetDevice(&device));
    MCV_CUDA_TRY(cudaDeviceGetAttribute(&SmCount, cudaDevAttrMultiProcessorCount, device));
  }
  if (N > ResultN)
  {
    if (Result)
    {
      MCV_CUDA_TRY(cudaFree(Result));
      Result = nullptr;
    }
    if (HostResult)
    {
      MCV_CUDA_TRY(cudaFreeHost(HostResult));
      HostResult = nullptr;
    }
    ResultN = 0;
    const std::size_t uN = static_cast<std::size_t>(N);
    ResultBytes = alignUp(uN * sizeof(long long) + uN * sizeof(unsigned), 16) +
      alignUp(sizeof(SelectState), 16) + 4 * sizeof(long long);
    MCV_CUDA_TRY(cudaMalloc(reinterpret_cast<void**>(&Result), ResultBytes));
    MCV_CUDA_TRY(cudaMallocHost(reinterpret_cast<void**>(&HostResult), ResultBytes));
    ValsOut = reinterpret_cast<long long*>(Result);
    KeysOut = reinterpret_cast<unsigned*>(Result + uN * sizeof(long long));
    const std::size_t stateOffset = alignUp(uN * sizeof(long long) + uN * sizeof(unsigned), 16);
    State = reinterpret_cast<SelectState*>(Result + stateOffset);
    Counts = reinterpret_cast<long long*>(Result + stateOffset + alignUp(sizeof(SelectState), 16));
    ResultN = N;
  }
  if (!grow(KeysIn, KeysInCap, static_cast<std::size_t>(N), error) ||
    !grow(ValsIn, ValsInCap, static_cast<std::size_t>(N), error))
  {
    return false;
  }
  MCV_CUDA_TRY(cudaMemsetAsync(
    Hist, 0, (kLevel1Bins + kLevel2Bins + kLevel3Bins) * sizeof(unsigned long long), stream));
  MCV_CUDA_TRY(cudaMemsetAsync(State, 0,
    alignUp(sizeof(SelectState), 16) + 4 * sizeof(long long), stream)); // state + counts
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
  InterestPoints& out, std::string* error, cudaEvent_t beforeDownload, cudaEvent_t afterDownload,
  const RowMaxima* rows)
{
  out.indices.clear();
  out.scores.clear();
  LastListSize = 0;
  LastSlow = false;
  LastNeedsComplete = false;
  if (!Hist || !FastList || !Result || !HostResult || N > ResultN)
  {
    return fail(error, "TopNSelector::select called without reset(N)");
  }
  const auto record = [&](cudaEvent_t e) -> cudaError_t {
    return e ? cudaEventRecord(e, stream) : cudaSuccess;
  };
  if (N <= 0 || n == 0)
  {
    MCV_CUDA_TRY(record(beforeDownload));
    MCV_CUDA_TRY(record(afterDownload));
    MCV_CUDA_TRY(cudaStreamSynchronize(stream));
    return true;
  }
  const long long plane = rows ? static_cast<long long>(rows->nx) * rows->ny : 0;
  const bool byRows = rows && rows->max && plane > 0 && static_cast<long long>(n) % plane == 0;
  if (Partial && (N > kFastMaxN || ForceSlow || !byRows))
  {
    LastNeedsComplete = true; // these read every score
    return false;
  }
  if (N > kFastMaxN || ForceSlow)
  {
    // Too many points for the one-block finish (or a test asking): the slow path alone.
    LastSlow = true;
    if (!selectSlow(scores, n, N, stream, error))
    {
      return false;
    }
    MCV_CUDA_TRY(record(beforeDownload));
    MCV_CUDA_TRY(cudaMemcpyAsync(HostResult, Result, ResultBytes, cudaMemcpyDeviceToHost, stream));
    MCV_CUDA_TRY(record(afterDownload));
    MCV_CUDA_TRY(cudaStreamSynchronize(stream));
    const std::size_t offset = reinterpret_cast<unsigned char*>(State) - Result;
    const SelectState* st = reinterpret_cast<const SelectState*>(HostResult + offset);
    return finish(N, st->takeAll != 0, st->total, out, error);
  }

  // Fast path: level 1 -> compaction into the fixed list -> one block finishes and sorts.
  scanLevelKernel<kLevel1Bins><<<1, kScanThreads, 0, stream>>>(Hist, 1, N, kFastListCapacity, State);
  MCV_CUDA_TRY(cudaGetLastError());
  const long long items = static_cast<long long>(n);
  const int compactBlocks = static_cast<int>(std::max(1ll,
    std::min<long long>((items / 4 + kCompactThreads - 1) / kCompactThreads, 8ll * std::max(SmCount, 1))));
  if (byRows)
  {
    const long long segments = items / plane * ((rows->ny + 1) / 2) * rows->segmentsPerRow;
    const int rowBlocks = static_cast<int>(std::max(1ll, std::min<long long>(
      (segments + kCompactThreads - 1) / kCompactThreads, 8ll * std::max(SmCount, 1))));
    compactRowsKernel<<<rowBlocks, kCompactThreads, 0, stream>>>(scores, *rows, segments, State,
      FastList, kFastListCapacity, reinterpret_cast<unsigned long long*>(Counts));
  }
  else
  {
    compactKernel<<<compactBlocks, kCompactThreads, 0, stream>>>(scores, items, State, FastList,
      kFastListCapacity, reinterpret_cast<unsigned long long*>(Counts));
  }
  MCV_CUDA_TRY(cudaGetLastError());
  finishKernel<<<1, kScanThreads, 0, stream>>>(FastList, Counts, State, N, KeysIn, ValsIn);
  MCV_CUDA_TRY(cudaGetLastError());
  rankSortKernel<<<(N * kRankLanes + kRankThreads - 1) / kRankThreads, kRankThreads, 0, stream>>>(
    KeysIn, ValsIn, State, N, KeysOut, ValsOut);
  MCV_CUDA_TRY(cudaGetLastError());
  MCV_CUDA_TRY(record(beforeDownload));
  MCV_CUDA_TRY(cudaMemcpyAsync(HostResult, Result, ResultBytes, cudaMemcpyDeviceToHost, stream));
  MCV_CUDA_TRY(record(afterDownload));
  MCV_CUDA_TRY(cudaStreamSynchronize(stream));

  const std::size_t stateOffset = reinterpret_cast<unsigned char*>(State) - Result;
  const SelectState* hostState = reinterpret_cast<const SelectState*>(HostResult + stateOffset);
  if (hostState->overflow != 0 && Partial)
  {
    LastNeedsComplete = true; // the slow path would read every score
    return false;
  }
  if (hostState->overflow != 0)
  {
    // 1: the list was longer than the fast capacity, or held more than 2048 ties at the
    // threshold; 2: the fast bookkeeping disagreed (never seen; the slow path is the
    // reference). Either way: size everything on the host and redo.
    LastSlow = true;
    MCV_CUDA_TRY(cudaMemsetAsync(Hist + kLevel1Bins, 0,
      (kLevel2Bins + kLevel3Bins) * sizeof(unsigned long long), stream));
    if (!selectSlow(scores, n, N, stream, error))
    {
      return false;
    }
    MCV_CUDA_TRY(record(beforeDownload));
    MCV_CUDA_TRY(cudaMemcpyAsync(HostResult, Result, ResultBytes, cudaMemcpyDeviceToHost, stream));
    MCV_CUDA_TRY(record(afterDownload));
    MCV_CUDA_TRY(cudaStreamSynchronize(stream));
  }
  return finish(N, hostState->takeAll != 0, hostState->total, out, error);
}

// Reads the copied result block: consistency checks, then the points.
bool TopNSelector::finish(
  int N, bool takeAll, unsigned long long total, InterestPoints& out, std::string* error)
{
  const std::size_t uN = static_cast<std::size_t>(N);
  const std::size_t stateOffset = reinterpret_cast<unsigned char*>(State) - Result;
  const std::size_t countsOffset = reinterpret_cast<unsigned char*>(Counts) - Result;
  const SelectState st = *reinterpret_cast<const SelectState*>(HostResult + stateOffset);
  const long long* counts = reinterpret_cast<const long long*>(HostResult + countsOffset);
  const long long* vals = reinterpret_cast<const long long*>(HostResult);
  const unsigned* keys = reinterpret_cast<const unsigned*>(HostResult + uN * sizeof(long long));
  LastListSize = counts[0];
  const unsigned long long count = st.above + st.need;
  const bool consistent = st.overflow == 0 &&
    static_cast<unsigned long long>(counts[0]) == st.listSize && count <= uN &&
    (takeAll ? count == total : count == uN) && (!LastSlow || static_cast<unsigned long long>(counts[1]) == st.above);
  if (!consistent)
  {
    return fail(error,
      "GPU top-N selection is inconsistent (list " + std::to_string(counts[0]) + "/" +
        std::to_string(st.listSize) + ", above " + std::to_string(st.above) + ", need " +
        std::to_string(st.need) + ", flag " + std::to_string(st.overflow) + ")");
  }
  out.indices.resize(count);
  out.scores.resize(count);
  for (std::size_t i = 0; i < count; ++i)
  {
    out.indices[i] = vals[i];
    float s;
    static_assert(sizeof(s) == sizeof(unsigned), "float is 32 bits");
    std::memcpy(&s, &keys[i], sizeof(s));
    out.scores[i] = s;
  }
  return true;
}

// Slow path: the host learns the list size after level 1 and sizes the CUB calls with it.
bool TopNSelector::selectSlow(
  const float* scores, std::size_t n, int N, cudaStream_t stream, std::string* error)
{
  unsigned long long* hist1 = Hist;
  unsigned long long* hist2 = Hist + kLevel1Bins;
  unsigned long long* hist3 = hist2 + kLevel2Bins;
  scanLevelKernel<kLevel1Bins><<<1, kScanThreads, 0, stream>>>(hist1, 1, N, LLONG_MAX, State);
  MCV_CUDA_TRY(cudaGetLastError());
  MCV_CUDA_TRY(cudaMemcpyAsync(HostResult, Result, ResultBytes, cudaMemcpyDeviceToHost, stream));
  MCV_CUDA_TRY(cudaStreamSynchronize(stream));
  const std::size_t stateOffset = reinterpret_cast<unsigned char*>(State) - Result;
  const SelectState level1 = *reinterpret_cast<const SelectState*>(HostResult + stateOffset);
  const long long m = static_cast<long long>(level1.listSize);
  const std::size_t um = static_cast<std::size_t>(std::max(m, 1ll)), uN = static_cast<std::size_t>(N);
  if (!grow(ListIdx, ListCap, um, error) || !grow(ListBits, ListBitsCap, um, error) ||
    !grow(TiePos, TieCap, um, error) || !grow(AbovePos, AboveCap, uN, error))
  {
    return false;
  }
  const thrust::counting_iterator<long long> first(0);
  const AtLeastBits compactOp{ scores, level1.low };
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
    scanLevelKernel<kLevel2Bins><<<1, kScanThreads, 0, stream>>>(hist2, 2, N, LLONG_MAX, State);
    MCV_CUDA_TRY(cudaGetLastError());
    level3Kernel<<<gridFor(m, SmCount), kHistThreads, 0, stream>>>(ListBits, m, State, hist3);
    MCV_CUDA_TRY(cudaGetLastError());
    scanLevelKernel<kLevel3Bins><<<1, kScanThreads, 0, stream>>>(hist3, 3, N, LLONG_MAX, State);
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
  return true;
}

} // namespace detail
} // namespace cuda
} // namespace mcv
