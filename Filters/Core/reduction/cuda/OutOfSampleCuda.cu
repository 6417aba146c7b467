// Out-of-sample placement on the GPU: float candidates by a shared-memory tiled kernel
// (by default skipping the reference tiles that cannot hold a candidate, see "Tile
// pruning"), then the canonical rule (ExactKnn.h) in double, the bound check, an exact scan
// for the rows that fail it, and the barycentric weights, all on the device.
#include "OutOfSampleCuda.h"

#include <math_constants.h>

#include "cuda/CudaCheck.h"
#include "cuda/DeviceBuffer.cuh"
#include "ReferenceTiles.h"

#include <cub/device/device_radix_sort.cuh>
#include <cub/device/device_scan.cuh>
#include <cub/device/device_select.cuh>
#include <thrust/iterator/counting_iterator.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <limits>
#include <utility>
#include <vector>

namespace mcv
{
namespace cuda
{

namespace
{
constexpr int KP = 8;          // float candidates per row
constexpr int kThreads = 128;  // rows per block of the candidate kernel
constexpr int kTile = 128;     // references per shared-memory tile
constexpr unsigned kNone = 0xffffffffu;
constexpr std::size_t kChunkRows = std::size_t(1) << 20; // rows per launch (progress steps)
static_assert(kMaxPlacementNeighbors + 2 <= KP, "keep at least two spare candidates");

__constant__ int cColumns[kMaxPlacementDimension];

struct RowParams
{
  const float* rows;
  std::size_t first; // first row of this chunk
  int count;         // rows in this chunk
  int dim;
  int D;
  int gather; // 1: feature c is rows[..][cColumns[c]]
  int M;
  // Optional: the rows to place are list[0, *listCount) of the chunk (the first of each run
  // of equal rows); null: every row of the chunk.
  const unsigned* list;
  const unsigned* listCount;
};

__device__ __forceinline__ int rowsToPlace(const RowParams& p)
{
  return p.listCount ? static_cast<int>(*p.listCount) : p.count;
}

__device__ __forceinline__ int rowOf(const RowParams& p, int local)
{
  return p.list ? static_cast<int>(p.list[local]) : local;
}

struct PlaceParams
{
  const float* refX; // M x D
  const float* refY; // M x d
  int D, d, k;
  double regularization;
  double margin;
  float* out;            // n x d
  unsigned* neighbors;   // n x k or null
  float* distance;       // n or null: |row - nearest reference| / radius (ModelDistance.h)
  double radius;
};

__device__ __forceinline__ float feature(const float* row, int c, int gather)
{
  return row[gather ? cColumns[c] : c];
}

// Tile pruning (pruneTiles). At upload the references are ordered so that each tile of
// kPruneTile consecutive ones is compact (ReferenceTiles.h); per tile its centroid (to rank
// the tiles) and its bounding box [lo, hi], the exact float minimum and maximum of each
// coordinate over its references. For a query q and any reference r of the tile,
// |q - r|^2 >= box(q)^2 = sum_c max(0, lo_c - q_c, q_c - hi_c)^2. (On the brain's 24D
// features this box prunes far more than the ball |q - c| - R: with the final 8th
// distance known, a row needs 32 % of the 128-reference tiles by the box, 77 % by the ball.)
// The float box(q)^2 is at most (1 + (D + 4) 2^-24) times the exact one, and the float
// distance the kernel computes is acc >= (1 - margin) |q - r|^2 with margin =
// 4 (DP + 4) 2^-24 (floatDistanceMargin of ExactKnn.h). A row "can skip" the tile when
// box(q)^2 > (its current 8th float distance) * (1 + 4 margin): then acc > that 8th
// distance for every r of the tile, and the 8th only decreases, so r is not among the row's
// final 8 by (float distance, index) and skipping it changes nothing. A warp scans the tile
// unless all its rows can skip it; the block loads it unless all its rows can. Candidates
// are kept by (float distance, original index), which does not depend on the order the
// references are visited in: the pruned kernel returns exactly the unpruned kernel's
// candidates (the same indices and float distances in the same slots), so the resolve and
// exact-scan kernels (which see original indices) give the same neighbours and coordinates.
//
// So that the 32 rows of a warp are alike (and skip the same tiles), the rows of a chunk
// are first sorted by their two nearest tile centroids (nearestTileKernel; stable:
// neighbouring voxels stay together); the candidates are still written at each row's own
// position.
//
// The per-row box check costs about a distance per tile (a large share of the kernel's
// instructions when a row checks every tile to scan a few), so with
// warpFilter a warp first checks the box of its rows, [qlo, qhi] per coordinate, against
// the next kWarpBatch tiles at once, one tile per lane: the gap max(0, lo - qhi, qlo - hi)
// is at most every row's max(0, lo - q, q - hi) (float rounding is monotone), summed in the
// same order, so box(warp)^2 <= box(q)^2 for each of its rows; with the largest of the rows'
// thresholds, box(warp)^2 > that threshold means every row of the warp can skip the tile.
// Only the tiles a warp cannot rule out this way get the per-row check; a tile no warp of the
// block needs is passed over without a barrier. The same tiles are skipped or scanned for
// each row's candidates as without it (a skipped tile could not hold any), so the
// candidates are the same.
//
// Dot-product filter (dotFilter). The exact float distance costs a subtraction and an FMA
// per coordinate; |q - r|^2 = |q|^2 + |r|^2 - 2 q.r costs one FMA with |r|^2 known, but
// rounds relative to |q|^2 + |r|^2, not to the distance, so it only decides which references
// need the exact distance: a reference is ruled out when e = fl(|r|^2 - 2 fl(q.r)) exceeds
// limit = 8th distance (1 + 4 margin + 2^-19) + eps - fl(|q|^2). With the FMA chains' error
// bounds (gamma_n = n u / (1 - n u), u = 2^-24), |e - (|r|^2 - 2 q.r)| <= (D + 3) u (|q| + |r|)^2
// and |fl(|q|^2) - |q|^2| <= D u |q|^2, so eps = (2 DP + 24) u (|q| + R)^2, R the tile's
// largest |r| rounded up, covers both with room for the roundings of limit itself (the
// 2^-19 term covers those of the 8th distance). Then e > limit means |q - r|^2 > 8th
// distance (1 + 4 margin), so its float distance exceeds the 8th (as for a skipped tile): not
// a candidate. The others get the exact float distance (in the tile's order), so
// the candidates are those of the full scan. Not finite anywhere: limit or e is not a
// number or infinite, and the comparison keeps the reference.
constexpr int kPruneTile = kReferenceTile;
constexpr int kMaxRankedTiles = 1024; // more tiles: visited in the upload's order
// Fewer tiles: every reference is scanned (on so few tiles the sort and the checks cost
// more than the references they skip).
constexpr int kMinPruneTiles = 32;
constexpr int kWarps = kThreads / 32;
constexpr int kWarpBatch = 32; // tiles per warp check (one per lane)

bool pruneWith(std::size_t M)
{
  return (M + kPruneTile - 1) / kPruneTile >= static_cast<std::size_t>(kMinPruneTiles);
}

struct TileParams
{
  const unsigned* order;      // sorted position -> original reference index; null: no pruning
  const float4* centroids;    // tiles x DP / 4
  const float4* lo;           // tiles x DP / 4, the box
  const float4* hi;
  float margin;               // 4 (DP + 4) 2^-24
  const unsigned* rowOrder;   // thread slot -> row of the chunk (sorted by nearest tile)
  unsigned long long* visits; // [0] += tiles scanned (by a warp) x its rows, [1] += rows
  int warpFilter;             // 1: the warp's box of rows is checked first (see candidatesKernel)
  const float* norms;         // |r|^2 of the references in tile order (float of the double sum)
  const float* radius;        // per tile, max |r| rounded up
  const float* centroidNorms; // per tile, |centroid|^2 (the rows' sort keys)
  int dotFilter;              // 1: the dot-product filter (see "Dot-product filter")
};

template <int V>
__device__ __forceinline__ float squaredDistance(const float* q, const float4* __restrict__ c)
{
  float acc = 0.f;
#pragma unroll
  for (int v = 0; v < V; ++v)
  {
    const float4 r = c[v];
    acc = fmaf(q[4 * v] - r.x, q[4 * v] - r.x, acc);
    acc = fmaf(q[4 * v + 1] - r.y, q[4 * v + 1] - r.y, acc);
    acc = fmaf(q[4 * v + 2] - r.z, q[4 * v + 2] - r.z, acc);
    acc = fmaf(q[4 * v + 3] - r.w, q[4 * v + 3] - r.w, acc);
  }
  return acc;
}

__device__ __forceinline__ float boxGap(float q, float lo, float hi)
{
  return fmaxf(0.f, fmaxf(lo - q, q - hi));
}

// A row can skip a tile whose box(q)^2 exceeds this (its 8th float distance grown by the
// margins, see "Tile pruning"); the warps' box check compares with the largest of its rows'.
// 1e-36: subnormal roundings (absolute, far below any distance that matters).
__device__ __forceinline__ float skipAbove(float eighth, float margin)
{
  return fmaf(eighth, 1.f + 4.f * margin, 1e-36f);
}

// Keeps reference idx at float distance acc among a row's KP best, sorted by (distance,
// original index) whatever order the references come in; an equal distance to a kept +inf is
// not kept (as the scan in index order did).
template <int K>
__device__ __forceinline__ void offerCandidate(float acc, unsigned idx, float (&bf)[K], unsigned (&bi)[K])
{
  if (acc <= bf[K - 1] && (acc < bf[K - 1] || (idx < bi[K - 1] && bi[K - 1] != kNone)))
  {
    bf[K - 1] = acc;
    bi[K - 1] = idx;
#pragma unroll
    for (int s = K - 1; s > 0; --s)
    {
      if (bf[s] < bf[s - 1] || (bf[s] == bf[s - 1] && bi[s] < bi[s - 1]))
      {
        const float tf = bf[s];
        bf[s] = bf[s - 1];
        bf[s - 1] = tf;
        const unsigned ti = bi[s];
        bi[s] = bi[s - 1];
        bi[s - 1] = ti;
      }
    }
  }
}

// The rows' keys for the sort: the nearest tile centroid t1 and the second nearest t2, key
// t1 * tiles + t2 (pairKeys), else t1; rows beyond the chunk's list: the largest key, last.
// Rows that share both tiles are alike, so the 32 rows of a warp skip the same tiles more
// often than rows that share only the nearest (fewer tiles scanned per row). The
// keys only group rows (the candidates do not depend on the order), so the centroids are
// ranked by |c|^2 - 2 q.c, one FMA per coordinate.
template <int DP>
__global__ void nearestTileKernel(RowParams p, TileParams tp, int tiles, bool pairKeys, unsigned* __restrict__ keys,
  unsigned* __restrict__ rows)
{
  constexpr int V = DP / 4;
  const int local = blockIdx.x * blockDim.x + threadIdx.x;
  if (local >= p.count)
  {
    return;
  }
  rows[local] = static_cast<unsigned>(local);
  if (local >= rowsToPlace(p))
  {
    keys[local] = static_cast<unsigned>(pairKeys ? tiles * tiles : tiles);
    return;
  }
  const float* row = p.rows + (p.first + static_cast<std::size_t>(rowOf(p, local))) * p.dim;
  float q[DP];
#pragma unroll
  for (int c = 0; c < DP; ++c)
  {
    q[c] = c < p.D ? feature(row, c, p.gather) : 0.f;
  }
  float best = __int_as_float(0x7f800000), second = best;
  int at = 0, next = 0;
  for (int t = 0; t < tiles; ++t)
  {
    const float4* c = tp.centroids + static_cast<std::size_t>(t) * V;
    float dot = 0.f;
#pragma unroll
    for (int v = 0; v < V; ++v)
    {
      const float4 r = c[v];
      dot = fmaf(q[4 * v], r.x, dot);
      dot = fmaf(q[4 * v + 1], r.y, dot);
      dot = fmaf(q[4 * v + 2], r.z, dot);
      dot = fmaf(q[4 * v + 3], r.w, dot);
    }
    const float d = fmaf(-2.f, dot, tp.centroidNorms[t]);
    if (d < best)
    {
      second = best;
      next = at;
      best = d;
      at = t;
    }
    else if (d < second)
    {
      second = d;
      next = t;
    }
  }
  keys[local] = static_cast<unsigned>(pairKeys ? at * tiles + next : at);
}

// One query per thread; DP = D padded with zeros (queries and references alike) to a
// multiple of 4 so a reference is read from shared memory as float4 broadcasts.
template <int DP, bool Prune>
__global__ void __launch_bounds__(kThreads) candidatesKernel(
  RowParams p, TileParams tp, const float4* __restrict__ refs4, unsigned* __restrict__ cIdx, float* __restrict__ cF)
{
  constexpr int V = DP / 4;
  constexpr int TileN = Prune ? kPruneTile : kTile;
  __shared__ float4 tile[TileN * V];
  __shared__ unsigned tileIdx[Prune ? TileN : 1];
  __shared__ float tileNorm[Prune ? TileN : 1];
  __shared__ unsigned short rankOrder[Prune ? kMaxRankedTiles : 1];
  __shared__ float dist[Prune ? kMaxRankedTiles : 1];
  __shared__ float q0[Prune ? DP : 1];
  __shared__ float4 warpLo[Prune ? kWarps * V : 1], warpHi[Prune ? kWarps * V : 1]; // the warps' boxes of rows
  __shared__ unsigned warpMask[Prune ? kWarps : 1]; // bit b: the warp may need tile step batch + b
  __shared__ unsigned long long blockVisits;
  const int count = rowsToPlace(p);
  if (static_cast<int>(blockIdx.x) * kThreads >= count)
  {
    return; // the whole block (before any barrier): beyond the rows to place
  }
  const int slot = blockIdx.x * kThreads + threadIdx.x;
  const bool active = slot < count;
  const int local = Prune && active ? static_cast<int>(tp.rowOrder[slot]) : slot;
  const float* row = p.rows + (p.first + static_cast<std::size_t>(active ? rowOf(p, local) : 0)) * p.dim;
  float q[DP];
#pragma unroll
  for (int c = 0; c < DP; ++c)
  {
    q[c] = c < p.D ? feature(row, c, p.gather) : 0.f;
  }
  float bf[KP];
  unsigned bi[KP];
#pragma unroll
  for (int s = 0; s < KP; ++s)
  {
    bf[s] = __int_as_float(0x7f800000); // +inf
    bi[s] = kNone;
  }
  // The dot-product filter's |q|^2, |q| and eps / (|q| + R)^2.
  float qq = 0.f;
#pragma unroll
  for (int c = 0; c < DP; ++c)
  {
    qq = fmaf(q[c], q[c], qq);
  }
  const float qNorm = sqrtf(qq);
  constexpr float dotSlack = (2 * DP + 24) * 0x1p-24f;
  const int tiles = (p.M + TileN - 1) / TileN;
  const bool ranked = Prune && tiles <= kMaxRankedTiles;
  if (ranked)
  {
    // The tiles in order of their centroid's distance to thread 0's row (always active):
    // near tiles first lower the 8th distances early, so more far tiles are skipped. A
    // counting rank, ties by tile.
    if (threadIdx.x == 0)
    {
#pragma unroll
      for (int c = 0; c < DP; ++c)
      {
        q0[c] = q[c];
      }
      blockVisits = 0;
    }
    __syncthreads();
    for (int t = threadIdx.x; t < tiles; t += kThreads)
    {
      const float d = squaredDistance<V>(q0, tp.centroids + static_cast<std::size_t>(t) * V);
      dist[t] = d <= 3.4e38f ? d : __int_as_float(0x7f800000); // NaN ranks last too
    }
    __syncthreads();
    for (int t = threadIdx.x; t < tiles; t += kThreads)
    {
      const float dt = dist[t];
      int rank = 0;
      for (int u = 0; u < tiles; ++u)
      {
        const float du = dist[u];
        rank += du < dt || (du == dt && u < t);
      }
      rankOrder[rank] = static_cast<unsigned short>(t);
    }
    __syncthreads(); // rankOrder complete before anyone reads it
  }
  else if (Prune && threadIdx.x == 0)
  {
    blockVisits = 0; // published by the first barrier of the tile loop
  }
  const int warp = threadIdx.x >> 5, lane = threadIdx.x & 31;
  if (Prune && tp.warpFilter)
  {
    // The box of the warp's active rows; a coordinate that is not finite in any of them
    // makes that coordinate's range infinite (gap 0, as the per-row check's gap is >= 0).
    float* wlo = reinterpret_cast<float*>(warpLo + warp * V);
    float* whi = reinterpret_cast<float*>(warpHi + warp * V);
#pragma unroll
    for (int c = 0; c < DP; ++c)
    {
      const bool finite = isfinite(q[c]);
      float l = !active ? __int_as_float(0x7f800000) : finite ? q[c] : __int_as_float(0xff800000);
      float h = !active ? __int_as_float(0xff800000) : finite ? q[c] : __int_as_float(0x7f800000);
#pragma unroll
      for (int offset = 16; offset > 0; offset >>= 1)
      {
        l = fminf(l, __shfl_xor_sync(0xffffffffu, l, offset));
        h = fmaxf(h, __shfl_xor_sync(0xffffffffu, h, offset));
      }
      if (lane == 0)
      {
        wlo[c] = l;
        whi[c] = h;
      }
    }
    __syncwarp();
  }
  unsigned long long visited = 0; // tiles this warp scanned
  int batch = 0, nextCheck = 0;   // the warp masks' first step, the next check's
  for (int step = 0; step < tiles; ++step)
  {
    const int t = ranked ? rankOrder[step] : step;
    const int base = t * TileN;
    const int n = min(TileN, p.M - base);
    bool warpNeeds = true;
    if (Prune)
    {
      bool mine = true; // this warp's rows may need the tile
      if (tp.warpFilter)
      {
        // Step 0 alone (no distance is known before it), then kWarpBatch steps per check.
        if (step == nextCheck)
        {
          batch = step;
          nextCheck = step == 0 ? 1 : step + kWarpBatch;
          float limit = active ? skipAbove(bf[KP - 1], tp.margin) : __int_as_float(0xff800000);
#pragma unroll
          for (int offset = 16; offset > 0; offset >>= 1)
          {
            limit = fmaxf(limit, __shfl_xor_sync(0xffffffffu, limit, offset));
          }
          bool may = false;
          const int mineStep = step + lane;
          if (mineStep < nextCheck && mineStep < tiles)
          {
            const int u = ranked ? rankOrder[mineStep] : mineStep;
            const float4* lo = tp.lo + static_cast<std::size_t>(u) * V;
            const float4* hi = tp.hi + static_cast<std::size_t>(u) * V;
            const float4* ql = warpLo + warp * V;
            const float4* qh = warpHi + warp * V;
            float box = 0.f;
#pragma unroll
            for (int v = 0; v < V; ++v)
            {
              const float4 l = lo[v], h = hi[v], a = ql[v], b = qh[v];
              const float g0 = fmaxf(0.f, fmaxf(l.x - b.x, a.x - h.x));
              const float g1 = fmaxf(0.f, fmaxf(l.y - b.y, a.y - h.y));
              const float g2 = fmaxf(0.f, fmaxf(l.z - b.z, a.z - h.z));
              const float g3 = fmaxf(0.f, fmaxf(l.w - b.w, a.w - h.w));
              box = fmaf(g0, g0, box);
              box = fmaf(g1, g1, box);
              box = fmaf(g2, g2, box);
              box = fmaf(g3, g3, box);
            }
            may = !(box > limit);
          }
          const unsigned mask = __ballot_sync(0xffffffffu, may);
          __syncthreads(); // every warp is done with the previous batch's masks
          if (lane == 0)
          {
            warpMask[warp] = mask;
          }
          __syncthreads();
        }
        const unsigned bit = 1u << (step - batch);
        unsigned any = 0;
#pragma unroll
        for (int w = 0; w < kWarps; ++w)
        {
          any |= warpMask[w];
        }
        if (!(any & bit))
        {
          continue; // no warp of the block needs it (the same decision in every thread)
        }
        mine = (warpMask[warp] & bit) != 0;
      }
      bool need = false;
      if (active && mine)
      {
        const float4* lo = tp.lo + static_cast<std::size_t>(t) * V;
        const float4* hi = tp.hi + static_cast<std::size_t>(t) * V;
        float box = 0.f;
#pragma unroll
        for (int v = 0; v < V; ++v)
        {
          const float4 l = lo[v], h = hi[v];
          const float g0 = boxGap(q[4 * v], l.x, h.x), g1 = boxGap(q[4 * v + 1], l.y, h.y);
          const float g2 = boxGap(q[4 * v + 2], l.z, h.z), g3 = boxGap(q[4 * v + 3], l.w, h.w);
          box = fmaf(g0, g0, box);
          box = fmaf(g1, g1, box);
          box = fmaf(g2, g2, box);
          box = fmaf(g3, g3, box);
        }
        need = !(box > skipAbove(bf[KP - 1], tp.margin));
      }
      warpNeeds = __any_sync(0xffffffffu, need);
      // Also the barrier that keeps the previous tile until every warp has scanned it.
      if (!__syncthreads_or(need))
      {
        continue;
      }
    }
    else
    {
      __syncthreads();
    }
    for (int i = threadIdx.x; i < n * V; i += kThreads)
    {
      tile[i] = refs4[static_cast<std::size_t>(base) * V + i];
    }
    if (Prune && threadIdx.x < n)
    {
      tileIdx[threadIdx.x] = tp.order[base + threadIdx.x];
      if (tp.dotFilter)
      {
        tileNorm[threadIdx.x] = tp.norms[base + threadIdx.x];
      }
    }
    __syncthreads();
    if (!warpNeeds)
    {
      continue; // every row of this warp can skip the tile
    }
    ++visited;
    if (Prune && tp.dotFilter)
    {
      // Only the references the dot-product bound cannot rule out get the exact float
      // distance (see "Dot-product filter"); their bits, then those in index order.
      const float reach = qNorm + tp.radius[t];
      const float eps = dotSlack * reach * reach;
      const float limit = fmaf(bf[KP - 1], 1.f + 4.f * tp.margin + 0x1p-19f, eps - qq);
      unsigned pass = 0;
#pragma unroll 4
      for (int j = 0; j < n; ++j)
      {
        float dot = 0.f;
#pragma unroll
        for (int v = 0; v < V; ++v)
        {
          const float4 r = tile[j * V + v];
          dot = fmaf(q[4 * v], r.x, dot);
          dot = fmaf(q[4 * v + 1], r.y, dot);
          dot = fmaf(q[4 * v + 2], r.z, dot);
          dot = fmaf(q[4 * v + 3], r.w, dot);
        }
        pass |= static_cast<unsigned>(!(fmaf(-2.f, dot, tileNorm[j]) > limit)) << j;
      }
      while (pass)
      {
        const int j = __ffs(pass) - 1;
        pass &= pass - 1;
        offerCandidate<KP>(squaredDistance<V>(q, tile + j * V), tileIdx[j], bf, bi);
      }
      continue;
    }
#pragma unroll 2
    for (int j = 0; j < n; ++j)
    {
      offerCandidate<KP>(squaredDistance<V>(q, tile + j * V), Prune ? tileIdx[j] : static_cast<unsigned>(base + j), bf, bi);
    }
  }
  if (Prune && tp.visits)
  {
    const unsigned rows = __popc(__ballot_sync(0xffffffffu, active));
    if ((threadIdx.x & 31) == 0)
    {
      atomicAdd(&blockVisits, visited * rows);
    }
    __syncthreads();
    if (threadIdx.x == 0)
    {
      atomicAdd(tp.visits, blockVisits);
      atomicAdd(tp.visits + 1, static_cast<unsigned long long>(min(kThreads, count - static_cast<int>(blockIdx.x) * kThreads)));
    }
  }
  if (active)
  {
#pragma unroll
    for (int s = 0; s < KP; ++s)
    {
      cIdx[static_cast<std::size_t>(local) * KP + s] = bi[s];
      cF[static_cast<std::size_t>(local) * KP + s] = bf[s];
    }
  }
}

// The canonical distance, rounded step by step exactly like the CPU's (no FMA contraction).
__device__ double canonicalD2(const float* q, const float* r, int D)
{
  double s = 0.0;
  for (int c = 0; c < D; ++c)
  {
    const double t = __dsub_rn(static_cast<double>(q[c]), static_cast<double>(r[c]));
    s = __dadd_rn(s, __dmul_rn(t, t));
  }
  return s;
}

__device__ void loadRow(const RowParams& p, int row, float* q)
{
  const float* at = p.rows + (p.first + static_cast<std::size_t>(row)) * p.dim;
  for (int c = 0; c < p.D; ++c)
  {
    q[c] = feature(at, c, p.gather);
  }
}

// Barycentric weights of the k neighbours (Cholesky of G + ridge) and the coordinates;
// an exact match takes the reference's embedding exactly. Same rules as the CPU path.
__device__ void place(const PlaceParams& pp, std::size_t row, const float* q, const unsigned* nb, const double* d2)
{
  const int k = pp.k;
  float* y = pp.out + row * pp.d;
  if (pp.neighbors)
  {
    for (int j = 0; j < k; ++j)
    {
      pp.neighbors[row * k + j] = nb[j];
    }
  }
  if (pp.distance)
  {
    // As ModelDistance.cpp: the double square root and quotient, rounded once to float.
    const double distance = sqrt(d2[0]);
    pp.distance[row] = static_cast<float>(
      pp.radius > 0 ? distance / pp.radius : (distance == 0.0 ? 0.0 : CUDART_INF));
  }
  if (k == 1 || d2[0] == 0.0)
  {
    for (int c = 0; c < pp.d; ++c)
    {
      y[c] = pp.refY[static_cast<std::size_t>(nb[0]) * pp.d + c];
    }
    return;
  }
  double G[kMaxPlacementNeighbors][kMaxPlacementNeighbors];
  for (int a = 0; a < k; ++a)
  {
    const float* ra = pp.refX + static_cast<std::size_t>(nb[a]) * pp.D;
    for (int b = 0; b <= a; ++b)
    {
      const float* rb = pp.refX + static_cast<std::size_t>(nb[b]) * pp.D;
      double s = 0.0;
      for (int c = 0; c < pp.D; ++c)
      {
        const double q64 = static_cast<double>(q[c]);
        s += (static_cast<double>(ra[c]) - q64) * (static_cast<double>(rb[c]) - q64);
      }
      G[a][b] = s;
      G[b][a] = s;
    }
  }
  double tr = 0.0;
  for (int a = 0; a < k; ++a)
  {
    tr += G[a][a];
  }
  const double ridge = tr > 0 ? pp.regularization * tr : pp.regularization;
  for (int a = 0; a < k; ++a)
  {
    G[a][a] += ridge;
  }
  // Cholesky G = L L^T (in place, lower triangle), then L L^T w = 1.
  bool ok = true;
  for (int i = 0; i < k; ++i)
  {
    for (int j = 0; j <= i; ++j)
    {
      double s = G[i][j];
      for (int m = 0; m < j; ++m)
      {
        s -= G[i][m] * G[j][m];
      }
      if (i == j)
      {
        ok = ok && s > 0.0;
        G[i][i] = sqrt(s > 0.0 ? s : 1.0);
      }
      else
      {
        G[i][j] = s / G[j][j];
      }
    }
  }
  double w[kMaxPlacementNeighbors];
  for (int i = 0; i < k; ++i)
  {
    double s = 1.0;
    for (int m = 0; m < i; ++m)
    {
      s -= G[i][m] * w[m];
    }
    w[i] = s / G[i][i];
  }
  for (int i = k - 1; i >= 0; --i)
  {
    double s = w[i];
    for (int m = i + 1; m < k; ++m)
    {
      s -= G[m][i] * w[m];
    }
    w[i] = s / G[i][i];
  }
  double sum = 0.0;
  for (int i = 0; i < k; ++i)
  {
    sum += w[i];
  }
  if (!ok || !isfinite(sum) || sum == 0.0)
  {
    for (int i = 0; i < k; ++i)
    {
      w[i] = 1.0;
    }
    sum = k;
  }
  for (int c = 0; c < pp.d; ++c)
  {
    double v = 0.0;
    for (int j = 0; j < k; ++j)
    {
      v += w[j] * static_cast<double>(pp.refY[static_cast<std::size_t>(nb[j]) * pp.d + c]);
    }
    y[c] = static_cast<float>(v / sum);
  }
}

// Canonical rule on the candidates, the bound check, placement; failing rows are listed.
__global__ void resolveKernel(RowParams p, PlaceParams pp, const unsigned* __restrict__ cIdx,
  const float* __restrict__ cF, unsigned* __restrict__ scanRows, unsigned* __restrict__ scanCount)
{
  const int local = blockIdx.x * blockDim.x + threadIdx.x;
  if (local >= rowsToPlace(p))
  {
    return;
  }
  const int row = rowOf(p, local);
  float q[kMaxPlacementDimension];
  loadRow(p, row, q);
  double cd[KP];
  unsigned ci[KP];
  int valid = 0;
  for (int s = 0; s < KP; ++s)
  {
    const unsigned idx = cIdx[static_cast<std::size_t>(local) * KP + s];
    if (idx == kNone)
    {
      break;
    }
    const double d = canonicalD2(q, pp.refX + static_cast<std::size_t>(idx) * pp.D, pp.D);
    int at = valid++;
    while (at > 0 && (cd[at - 1] > d || (cd[at - 1] == d && ci[at - 1] > idx)))
    {
      cd[at] = cd[at - 1];
      ci[at] = ci[at - 1];
      --at;
    }
    cd[at] = d;
    ci[at] = idx;
  }
  const double grow = (1.0 + pp.margin) * (1.0 + pp.margin);
  const bool exact = valid >= pp.k &&
    (valid == p.M || static_cast<double>(cF[static_cast<std::size_t>(local) * KP + valid - 1]) > cd[pp.k - 1] * grow);
  if (!exact)
  {
    scanRows[atomicAdd(scanCount, 1u)] = static_cast<unsigned>(local);
    return;
  }
  place(pp, p.first + row, q, ci, cd);
}

// The rows the bound could not settle: every reference in canonical double, best k kept
// by (distance, index).
// Launched over every row of the chunk (so nothing waits for the host to read the count);
// thread 0 adds the count to the running total.
__global__ void scanKernel(RowParams p, PlaceParams pp, const unsigned* __restrict__ scanRows,
  const unsigned* __restrict__ scanCount, unsigned long long* __restrict__ scanTotal)
{
  const unsigned t = blockIdx.x * blockDim.x + threadIdx.x;
  const unsigned count = *scanCount;
  if (t == 0 && count > 0)
  {
    atomicAdd(scanTotal, static_cast<unsigned long long>(count));
  }
  if (t >= count)
  {
    return;
  }
  const int row = rowOf(p, static_cast<int>(scanRows[t]));
  float q[kMaxPlacementDimension];
  loadRow(p, row, q);
  double bd[kMaxPlacementNeighbors];
  unsigned bi[kMaxPlacementNeighbors];
  for (int j = 0; j < pp.k; ++j)
  {
    bd[j] = __longlong_as_double(0x7ff0000000000000ll); // +inf
    bi[j] = kNone;
  }
  for (int r = 0; r < p.M; ++r)
  {
    const double d = canonicalD2(q, pp.refX + static_cast<std::size_t>(r) * pp.D, pp.D);
    if (d < bd[pp.k - 1])
    {
      int at = pp.k - 1;
      while (at > 0 && bd[at - 1] > d)
      {
        bd[at] = bd[at - 1];
        bi[at] = bi[at - 1];
        --at;
      }
      bd[at] = d;
      bi[at] = static_cast<unsigned>(r);
    }
  }
  place(pp, p.first + row, q, bi, bd);
}

// Runs of equal rows (the CPU's mergeEqualRows, OutOfSample.cpp): equal used features give
// equal neighbours and coordinates, so only the first row of a run is placed and the others
// copy its coordinates. headIdx[r] = r for the first row of a run, 0 otherwise (row 0 always
// starts one).
__global__ void runHeadsKernel(RowParams p, unsigned* __restrict__ headIdx)
{
  const int r = blockIdx.x * blockDim.x + threadIdx.x;
  if (r >= p.count)
  {
    return;
  }
  bool head = r == 0;
  if (!head)
  {
    const float* a = p.rows + (p.first + static_cast<std::size_t>(r)) * p.dim;
    const float* b = a - p.dim;
    for (int c = 0; c < p.D && !head; ++c)
    {
      head = feature(a, c, p.gather) != feature(b, c, p.gather);
    }
  }
  headIdx[r] = head ? static_cast<unsigned>(r) : 0u;
}

struct IsRunHead
{
  const unsigned* headIdx;
  __device__ bool operator()(int r) const { return r == 0 || headIdx[r] != 0u; }
};

struct MaxOp
{
  __device__ unsigned operator()(unsigned a, unsigned b) const { return a > b ? a : b; }
};

// Every row that is not the first of its run takes the coordinates (and neighbours) of the
// run's first row, headOf[r] (the running maximum of headIdx).
__global__ void copyRunsKernel(int count, std::size_t first, const unsigned* __restrict__ headOf, float* out, int d,
  unsigned* neighbors, int k, float* distance)
{
  const int r = blockIdx.x * blockDim.x + threadIdx.x;
  if (r >= count)
  {
    return;
  }
  const unsigned h = headOf[r];
  if (h == static_cast<unsigned>(r))
  {
    return;
  }
  for (int c = 0; c < d; ++c)
  {
    out[(first + r) * d + c] = out[(first + h) * d + c];
  }
  if (neighbors)
  {
    for (int j = 0; j < k; ++j)
    {
      neighbors[(first + r) * k + j] = neighbors[(first + h) * k + j];
    }
  }
  if (distance)
  {
    distance[first + r] = distance[first + h];
  }
}

// The rows' nearest-tile keys and their sort (pruning only), then the candidates.
struct SortScratch
{
  unsigned *keys, *keysOut, *rows, *rowsOut;
  void* temp;
  std::size_t tempBytes;
  int tiles, keyBits;
  bool pairKeys;
};

template <int DP>
cudaError_t launchCandidates(const RowParams& p, TileParams tp, const SortScratch& ss, const float* refsPadded,
  unsigned* cIdx, float* cF, cudaStream_t stream)
{
  const int blocks = (p.count + kThreads - 1) / kThreads;
  const float4* refs4 = reinterpret_cast<const float4*>(refsPadded);
  if (tp.order)
  {
    nearestTileKernel<DP><<<blocks, kThreads, 0, stream>>>(p, tp, ss.tiles, ss.pairKeys, ss.keys, ss.rows);
    cudaError_t e = cudaGetLastError();
    if (e != cudaSuccess)
    {
      return e;
    }
    // Double buffers: no copy of the keys in the temporary storage; the sorted rows end in
    // whichever buffer the passes leave them (known on the host).
    std::size_t bytes = ss.tempBytes;
    cub::DoubleBuffer<unsigned> keys(ss.keys, ss.keysOut), rows(ss.rows, ss.rowsOut);
    e = cub::DeviceRadixSort::SortPairs(ss.temp, bytes, keys, rows, p.count, 0, ss.keyBits, stream);
    if (e != cudaSuccess)
    {
      return e;
    }
    tp.rowOrder = rows.Current();
    candidatesKernel<DP, true><<<blocks, kThreads, 0, stream>>>(p, tp, refs4, cIdx, cF);
  }
  else
  {
    candidatesKernel<DP, false><<<blocks, kThreads, 0, stream>>>(p, tp, refs4, cIdx, cF);
  }
  return cudaGetLastError();
}

int paddedDimension(int D)
{
  return D <= 8 ? 8 : D <= 16 ? 16 : D <= 24 ? 24 : D <= 32 ? 32 : D <= 48 ? 48 : 64;
}

using Clock = std::chrono::steady_clock;
double msSince(Clock::time_point t)
{
  return std::chrono::duration<double, std::milli>(Clock::now() - t).count();
}
} // namespace

struct PlacementOnDevice::Impl
{
  struct Slot
  {
    DeviceBuffer cIdx, cF, scanRows, scanCount;
    DeviceBuffer headIdx, headOf, list, listCount, temp; // runs of equal rows
    DeviceBuffer keys, keysOut, rowOrder, rowOrderOut;    // rows sorted by nearest tile
    std::size_t tempBytes = 0;
  };
  DeviceBuffer refs, refX, refY, scanTotal;
  // Tile pruning: refs in tile order, order[sorted] = original index, per-tile centroids
  // and boxes, the visit counters (TileParams::visits). Empty: refs in original order.
  DeviceBuffer order, centroids, lo, hi, visits, norms, radius, centroidNorms;
  std::vector<Slot> slots;
  std::size_t M = 0, bytes = 0, chunk = 0;
  int D = 0, d = 0, k = 0, dim = 0, DP = 0, tiles = 0, keyBits = 0; // tiles: pruning's, 0 without
  bool pairKeys = false;
  bool gather = false, warpFilter = true, dotFilter = true;
  double regularization = 0, margin = 0;
};

PlacementOnDevice::PlacementOnDevice()
  : P(new Impl)
{
}

PlacementOnDevice::~PlacementOnDevice() = default;

void PlacementOnDevice::release()
{
  P.reset(new Impl);
}

std::size_t PlacementOnDevice::deviceBytes() const
{
  return P->bytes;
}

std::size_t PlacementOnDevice::scratchBytesPerSlot(std::size_t maxRows)
{
  // Candidates and scan list, run heads, run owners, placed list, the sort's keys and rows
  // (twice); CUB's temporary storage (a few KiB per million rows) is bounded by 2 MiB here.
  return std::min(kChunkRows, std::max<std::size_t>(1, maxRows)) * (2 * KP + 8) * sizeof(unsigned) +
    2 * sizeof(unsigned) + (std::size_t(2) << 20);
}

std::size_t PlacementOnDevice::referenceBytes(std::size_t M, int D, int d)
{
  // Padded, original and embedding rows, the scan total; with pruning the order and norms,
  // the tiles' centroids, their norms, boxes and radii and two visit counters.
  const std::size_t DP = static_cast<std::size_t>(paddedDimension(D)), tiles = (M + kPruneTile - 1) / kPruneTile;
  return M * (DP + D + d) * sizeof(float) + sizeof(unsigned long long) +
    (pruneWith(M) ? M * (sizeof(unsigned) + sizeof(float)) + tiles * (3 * DP + 2) * sizeof(float) +
        2 * sizeof(unsigned long long)
                  : 0);
}

bool PlacementOnDevice::upload(const PlacementInput& in, int slots, std::size_t maxRows, std::string* error)
{
  release();
  if (in.D < 1 || in.D > kMaxPlacementDimension)
  {
    return detail::fail(error, "the GPU placement handles 1.." + std::to_string(kMaxPlacementDimension) +
        " features (got " + std::to_string(in.D) + ")");
  }
  const int k = static_cast<int>(std::min<std::size_t>(static_cast<std::size_t>(std::max(1, in.neighbors)), in.M));
  if (k > kMaxPlacementNeighbors)
  {
    return detail::fail(error, "the GPU placement handles up to " + std::to_string(kMaxPlacementNeighbors) +
        " neighbours (got " + std::to_string(k) + ")");
  }
  if (in.M == 0 || in.M >= 0x7fffffffu || (in.columns == nullptr && in.dim != in.D) || in.d < 1 || slots < 1)
  {
    return detail::fail(error, "invalid GPU placement arguments");
  }
  Impl& I = *P;
  I.M = in.M;
  I.D = in.D;
  I.d = in.d;
  I.k = k;
  I.dim = in.dim;
  I.DP = paddedDimension(in.D);
  I.gather = in.columns != nullptr;
  I.warpFilter = in.warpBoxFilter;
  I.dotFilter = in.dotProductFilter;
  I.regularization = in.regularization;
  I.margin = in.distanceMargin;
  I.chunk = std::min(kChunkRows, std::max<std::size_t>(1, maxRows));
  // The padded copy the candidate kernel reads: in tile order when pruning.
  ReferenceTiles rt; // empty: no pruning
  if (in.pruneTiles && pruneWith(in.M))
  {
    rt = buildReferenceTiles(in.refX, in.M, in.D, I.DP);
    I.tiles = static_cast<int>(rt.tiles());
    // The sort's keys: tile pairs (0 .. tiles^2 - 1, and tiles^2 for no row) up to 4096 tiles
    // (24 bits), else tiles (0 .. tiles - 1, and tiles).
    I.pairKeys = I.tiles <= 4096;
    const unsigned largestKey = static_cast<unsigned>(I.pairKeys ? I.tiles * I.tiles : I.tiles);
    I.keyBits = 1;
    while (I.keyBits < 32 && (1u << I.keyBits) <= largestKey)
    {
      ++I.keyBits;
    }
  }
  std::vector<float> padded(in.M * static_cast<std::size_t>(I.DP), 0.f);
  for (std::size_t i = 0; i < in.M; ++i)
  {
    const std::size_t from = rt.order.empty() ? i : rt.order[i];
    std::copy(in.refX + from * in.D, in.refX + (from + 1) * in.D, padded.begin() + static_cast<std::ptrdiff_t>(i * I.DP));
  }
  if (!rt.order.empty())
  {
    MCV_CUDA_TRY(cudaMalloc(&I.order.ptr, rt.order.size() * sizeof(unsigned)));
    MCV_CUDA_TRY(cudaMalloc(&I.centroids.ptr, rt.centroids.size() * sizeof(float)));
    MCV_CUDA_TRY(cudaMalloc(&I.centroidNorms.ptr, rt.centroidNorms.size() * sizeof(float)));
    MCV_CUDA_TRY(cudaMalloc(&I.lo.ptr, rt.lo.size() * sizeof(float)));
    MCV_CUDA_TRY(cudaMalloc(&I.hi.ptr, rt.hi.size() * sizeof(float)));
    MCV_CUDA_TRY(cudaMalloc(&I.norms.ptr, rt.norms.size() * sizeof(float)));
    MCV_CUDA_TRY(cudaMalloc(&I.radius.ptr, rt.radius.size() * sizeof(float)));
    MCV_CUDA_TRY(cudaMemcpy(I.order.ptr, rt.order.data(), rt.order.size() * sizeof(unsigned), cudaMemcpyHostToDevice));
    MCV_CUDA_TRY(cudaMemcpy(I.centroids.ptr, rt.centroids.data(), rt.centroids.size() * sizeof(float), cudaMemcpyHostToDevice));
    MCV_CUDA_TRY(cudaMemcpy(I.centroidNorms.ptr, rt.centroidNorms.data(), rt.centroidNorms.size() * sizeof(float), cudaMemcpyHostToDevice));
    MCV_CUDA_TRY(cudaMemcpy(I.lo.ptr, rt.lo.data(), rt.lo.size() * sizeof(float), cudaMemcpyHostToDevice));
    MCV_CUDA_TRY(cudaMemcpy(I.hi.ptr, rt.hi.data(), rt.hi.size() * sizeof(float), cudaMemcpyHostToDevice));
    MCV_CUDA_TRY(cudaMemcpy(I.norms.ptr, rt.norms.data(), rt.norms.size() * sizeof(float), cudaMemcpyHostToDevice));
    MCV_CUDA_TRY(cudaMemcpy(I.radius.ptr, rt.radius.data(), rt.radius.size() * sizeof(float), cudaMemcpyHostToDevice));
    MCV_CUDA_TRY(cudaMalloc(&I.visits.ptr, 2 * sizeof(unsigned long long)));
    MCV_CUDA_TRY(cudaMemset(I.visits.ptr, 0, 2 * sizeof(unsigned long long)));
  }
  MCV_CUDA_TRY(cudaMalloc(&I.refs.ptr, padded.size() * sizeof(float)));
  MCV_CUDA_TRY(cudaMalloc(&I.refX.ptr, in.M * in.D * sizeof(float)));
  MCV_CUDA_TRY(cudaMalloc(&I.refY.ptr, in.M * in.d * sizeof(float)));
  MCV_CUDA_TRY(cudaMalloc(&I.scanTotal.ptr, sizeof(unsigned long long)));
  I.bytes = referenceBytes(in.M, in.D, in.d);
  I.slots.resize(static_cast<std::size_t>(slots));
  for (Impl::Slot& slot : I.slots)
  {
    MCV_CUDA_TRY(cudaMalloc(&slot.cIdx.ptr, I.chunk * KP * sizeof(unsigned)));
    MCV_CUDA_TRY(cudaMalloc(&slot.cF.ptr, I.chunk * KP * sizeof(float)));
    MCV_CUDA_TRY(cudaMalloc(&slot.scanRows.ptr, I.chunk * sizeof(unsigned)));
    MCV_CUDA_TRY(cudaMalloc(&slot.scanCount.ptr, sizeof(unsigned)));
    MCV_CUDA_TRY(cudaMalloc(&slot.headIdx.ptr, I.chunk * sizeof(unsigned)));
    MCV_CUDA_TRY(cudaMalloc(&slot.headOf.ptr, I.chunk * sizeof(unsigned)));
    MCV_CUDA_TRY(cudaMalloc(&slot.list.ptr, I.chunk * sizeof(unsigned)));
    MCV_CUDA_TRY(cudaMalloc(&slot.listCount.ptr, sizeof(unsigned)));
    std::size_t selectBytes = 0, scanBytes = 0;
    const thrust::counting_iterator<int> rows(0);
    MCV_CUDA_TRY(cub::DeviceSelect::If(nullptr, selectBytes, rows, slot.list.as<int>(), slot.listCount.as<int>(),
      static_cast<int>(I.chunk), IsRunHead{ slot.headIdx.as<unsigned>() }));
    MCV_CUDA_TRY(cub::DeviceScan::InclusiveScan(nullptr, scanBytes, slot.headIdx.as<unsigned>(),
      slot.headOf.as<unsigned>(), MaxOp{}, static_cast<int>(I.chunk)));
    slot.tempBytes = std::max<std::size_t>(1, std::max(selectBytes, scanBytes));
    if (I.tiles > 0)
    {
      MCV_CUDA_TRY(cudaMalloc(&slot.keys.ptr, I.chunk * sizeof(unsigned)));
      MCV_CUDA_TRY(cudaMalloc(&slot.keysOut.ptr, I.chunk * sizeof(unsigned)));
      MCV_CUDA_TRY(cudaMalloc(&slot.rowOrder.ptr, I.chunk * sizeof(unsigned)));
      MCV_CUDA_TRY(cudaMalloc(&slot.rowOrderOut.ptr, I.chunk * sizeof(unsigned)));
      std::size_t sortBytes = 0;
      cub::DoubleBuffer<unsigned> keys(slot.keys.as<unsigned>(), slot.keysOut.as<unsigned>());
      cub::DoubleBuffer<unsigned> rowOrder(slot.rowOrder.as<unsigned>(), slot.rowOrderOut.as<unsigned>());
      MCV_CUDA_TRY(
        cub::DeviceRadixSort::SortPairs(nullptr, sortBytes, keys, rowOrder, static_cast<int>(I.chunk), 0, I.keyBits));
      slot.tempBytes = std::max(slot.tempBytes, sortBytes);
    }
    MCV_CUDA_TRY(cudaMalloc(&slot.temp.ptr, slot.tempBytes));
    I.bytes += scratchBytesPerSlot(I.chunk);
  }
  if (in.columns)
  {
    MCV_CUDA_TRY(cudaMemcpyToSymbol(cColumns, in.columns, in.D * sizeof(int)));
  }
  MCV_CUDA_TRY(cudaMemcpy(I.refs.ptr, padded.data(), padded.size() * sizeof(float), cudaMemcpyHostToDevice));
  MCV_CUDA_TRY(cudaMemcpy(I.refX.ptr, in.refX, in.M * in.D * sizeof(float), cudaMemcpyHostToDevice));
  MCV_CUDA_TRY(cudaMemcpy(I.refY.ptr, in.refY, in.M * in.d * sizeof(float), cudaMemcpyHostToDevice));
  MCV_CUDA_TRY(cudaMemset(I.scanTotal.ptr, 0, sizeof(unsigned long long)));
  return true;
}

bool PlacementOnDevice::place(const float* deviceRows, std::size_t n, float* deviceOut, unsigned* deviceNeighbors,
  int slot, void* streamHandle, bool mergeEqualRows, std::string* error, float* deviceDistance, double radius)
{
  Impl& I = *P;
  if (I.M == 0 || slot < 0 || slot >= static_cast<int>(I.slots.size()))
  {
    return detail::fail(error, "the GPU placement has no references (upload first)");
  }
  const cudaStream_t stream = static_cast<cudaStream_t>(streamHandle);
  Impl::Slot& s = I.slots[static_cast<std::size_t>(slot)];
  RowParams p{ deviceRows, 0, 0, I.dim, I.D, I.gather ? 1 : 0, static_cast<int>(I.M) };
  PlaceParams pp{ I.refX.as<float>(), I.refY.as<float>(), I.D, I.d, I.k, I.regularization, I.margin, deviceOut,
    deviceNeighbors, deviceDistance, radius };
  const TileParams tp{ I.order.as<unsigned>(), I.centroids.as<float4>(), I.lo.as<float4>(), I.hi.as<float4>(),
    static_cast<float>(4.0 * (I.DP + 4) * std::ldexp(1.0, -24)), nullptr, I.visits.as<unsigned long long>(),
    I.warpFilter ? 1 : 0, I.norms.as<float>(), I.radius.as<float>(), I.centroidNorms.as<float>(),
    I.dotFilter ? 1 : 0 };
  const SortScratch ss{ s.keys.as<unsigned>(), s.keysOut.as<unsigned>(), s.rowOrder.as<unsigned>(),
    s.rowOrderOut.as<unsigned>(), s.temp.ptr, s.tempBytes, I.tiles, I.keyBits, I.pairKeys };
  for (std::size_t first = 0; first < n; first += I.chunk)
  {
    p.first = first;
    p.count = static_cast<int>(std::min(I.chunk, n - first));
    if (mergeEqualRows)
    {
      // The first row of each run is placed (list), the others copy it afterwards.
      runHeadsKernel<<<(p.count + 255) / 256, 256, 0, stream>>>(p, s.headIdx.as<unsigned>());
      MCV_CUDA_TRY(cudaGetLastError());
      std::size_t bytes = s.tempBytes;
      const thrust::counting_iterator<int> rows(0);
      MCV_CUDA_TRY(cub::DeviceSelect::If(s.temp.ptr, bytes, rows, s.list.as<int>(), s.listCount.as<int>(), p.count,
        IsRunHead{ s.headIdx.as<unsigned>() }, stream));
      bytes = s.tempBytes;
      MCV_CUDA_TRY(cub::DeviceScan::InclusiveScan(s.temp.ptr, bytes, s.headIdx.as<unsigned>(), s.headOf.as<unsigned>(),
        MaxOp{}, p.count, stream));
      p.list = s.list.as<unsigned>();
      p.listCount = s.listCount.as<unsigned>();
    }
    MCV_CUDA_TRY(cudaMemsetAsync(s.scanCount.ptr, 0, sizeof(unsigned), stream));
    switch (I.DP)
    {
      case 8:
        MCV_CUDA_TRY(launchCandidates<8>(p, tp, ss, I.refs.as<float>(), s.cIdx.as<unsigned>(), s.cF.as<float>(), stream));
        break;
      case 16:
        MCV_CUDA_TRY(launchCandidates<16>(p, tp, ss, I.refs.as<float>(), s.cIdx.as<unsigned>(), s.cF.as<float>(), stream));
        break;
      case 24:
        MCV_CUDA_TRY(launchCandidates<24>(p, tp, ss, I.refs.as<float>(), s.cIdx.as<unsigned>(), s.cF.as<float>(), stream));
        break;
      case 32:
        MCV_CUDA_TRY(launchCandidates<32>(p, tp, ss, I.refs.as<float>(), s.cIdx.as<unsigned>(), s.cF.as<float>(), stream));
        break;
      case 48:
        MCV_CUDA_TRY(launchCandidates<48>(p, tp, ss, I.refs.as<float>(), s.cIdx.as<unsigned>(), s.cF.as<float>(), stream));
        break;
      default:
        MCV_CUDA_TRY(launchCandidates<64>(p, tp, ss, I.refs.as<float>(), s.cIdx.as<unsigned>(), s.cF.as<float>(), stream));
        break;
    }
    MCV_CUDA_TRY(cudaGetLastError());
    const int blocks = (p.count + 127) / 128;
    resolveKernel<<<blocks, 128, 0, stream>>>(p, pp, s.cIdx.as<unsigned>(), s.cF.as<float>(), s.scanRows.as<unsigned>(),
      s.scanCount.as<unsigned>());
    MCV_CUDA_TRY(cudaGetLastError());
    scanKernel<<<(p.count + 63) / 64, 64, 0, stream>>>(p, pp, s.scanRows.as<unsigned>(), s.scanCount.as<unsigned>(),
      I.scanTotal.as<unsigned long long>());
    MCV_CUDA_TRY(cudaGetLastError());
    if (mergeEqualRows)
    {
      copyRunsKernel<<<(p.count + 255) / 256, 256, 0, stream>>>(p.count, first, s.headOf.as<unsigned>(), deviceOut, I.d,
        deviceNeighbors, I.k, deviceDistance);
      MCV_CUDA_TRY(cudaGetLastError());
    }
  }
  return true;
}

bool PlacementOnDevice::radiusScans(std::size_t* count, std::string* error)
{
  unsigned long long total = 0;
  if (P->scanTotal.ptr)
  {
    MCV_CUDA_TRY(cudaMemcpy(&total, P->scanTotal.ptr, sizeof total, cudaMemcpyDeviceToHost));
  }
  *count = static_cast<std::size_t>(total);
  return true;
}

bool PlacementOnDevice::tileVisits(int* tiles, double* perRow, std::string* error)
{
  const Impl& I = *P;
  *tiles = static_cast<int>((I.M + kPruneTile - 1) / kPruneTile);
  *perRow = *tiles;
  if (I.visits.ptr)
  {
    unsigned long long v[2] = { 0, 0 };
    MCV_CUDA_TRY(cudaMemcpy(v, I.visits.ptr, sizeof v, cudaMemcpyDeviceToHost));
    *perRow = v[1] ? static_cast<double>(v[0]) / static_cast<double>(v[1]) : 0.0;
  }
  return true;
}

bool placeOutOfSample(const PlacementInput& in, float* out, std::uint32_t* neighbors,
  const std::function<void(double)>& progress, PlacementStats* stats, std::string* error)
{
  FaultStage stage("outofsample");
  PlacementStats local;
  PlacementStats& st = stats ? *stats : local;
  st = PlacementStats{};
  auto start = Clock::now();
  PlacementOnDevice device;
  if (!device.upload(in, 1, in.n, error))
  {
    return false;
  }
  if (in.n == 0)
  {
    return true;
  }
  const int k = static_cast<int>(std::min<std::size_t>(static_cast<std::size_t>(std::max(1, in.neighbors)), in.M));
  DeviceBuffer dRows, dOut, dNb;
  MCV_CUDA_TRY(cudaMalloc(&dRows.ptr, in.n * in.dim * sizeof(float)));
  MCV_CUDA_TRY(cudaMalloc(&dOut.ptr, in.n * in.d * sizeof(float)));
  if (neighbors)
  {
    MCV_CUDA_TRY(cudaMalloc(&dNb.ptr, in.n * k * sizeof(unsigned)));
  }
  MCV_CUDA_TRY(cudaMemcpy(dRows.ptr, in.rows, in.n * in.dim * sizeof(float), cudaMemcpyHostToDevice));
  st.uploadMs = msSince(start);

  start = Clock::now();
  // One chunk per step, so that progress can be reported between them.
  for (std::size_t first = 0; first < in.n; first += kChunkRows)
  {
    const std::size_t count = std::min(kChunkRows, in.n - first);
    if (!device.place(dRows.as<float>() + first * in.dim, count, dOut.as<float>() + first * in.d,
          neighbors ? dNb.as<unsigned>() + first * k : nullptr, 0, nullptr, false, error))
    {
      return false;
    }
    if (progress)
    {
      MCV_CUDA_TRY(cudaDeviceSynchronize());
      progress(static_cast<double>(first + count) / static_cast<double>(in.n));
    }
  }
  MCV_CUDA_TRY(cudaDeviceSynchronize());
  if (!device.radiusScans(&st.radiusScans, error) || !device.tileVisits(&st.tiles, &st.tilesPerRow, error))
  {
    return false;
  }
  st.computeMs = msSince(start);

  start = Clock::now();
  MCV_CUDA_TRY(cudaMemcpy(out, dOut.ptr, in.n * in.d * sizeof(float), cudaMemcpyDeviceToHost));
  if (neighbors)
  {
    MCV_CUDA_TRY(cudaMemcpy(neighbors, dNb.ptr, in.n * k * sizeof(unsigned), cudaMemcpyDeviceToHost));
  }
  st.downloadMs = msSince(start);
  return true;
}

} // namespace cuda
} // namespace mcv
