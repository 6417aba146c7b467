// Out-of-sample placement on the GPU: float candidates by a shared-memory tiled kernel,
// then the canonical rule (ExactKnn.h) in double, the bound check, an exact scan for the
// rows that fail it, and the barycentric weights, all on the device.
#include "OutOfSampleCuda.h"

#include "CudaCheck.h"
#include "DeviceBuffer.cuh"

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
};

__device__ __forceinline__ float feature(const float* row, int c, int gather)
{
  return row[gather ? cColumns[c] : c];
}

// Tile pruning (pruneTiles): the references are ordered at upload so that each tile of
// kTile is compact (orderReferences) and each tile has a float centroid c and a radius R
// (the largest distance of its references to c, computed in double and rounded up). For a
// query q and any reference r of the tile, |q - r| >= |q - c| - R. The kernel computes that
// bound in float with a relative allowance for rounding, margin = 4 (DP + 4) 2^-24 (the
// bound of floatDistanceMargin in ExactKnn.h: a float squared distance is within that
// relative margin of the exact one), and a row "can skip" the tile when
// lb^2 > (its current 8th float distance) * (1 + 4 margin). Then every reference r of the
// tile has the float distance the kernel would compute, acc(q, r) >= (1 - margin)^2 |q - r|^2,
// larger than the current 8th, which only decreases: r is not among the row's final 8 by
// (float distance, index), so skipping it changes nothing. The block skips a tile only when
// every active row can (__syncthreads_or of "needs it"). Candidates are inserted by
// (float distance, original index), which does not depend on the order references are
// visited in, so the pruned kernel returns exactly the unpruned kernel's candidates (the
// same indices and float distances in the same slots).
struct TileParams
{
  const unsigned* order;      // sorted position -> original reference index
  const float4* centroids;    // tiles x DP / 4
  const float* radii;         // tiles, rounded up
  float margin;               // 4 (DP + 4) 2^-24
  unsigned long long* visits; // [0] += tiles scanned x rows of the block, [1] += rows
};
constexpr int kMaxRankedTiles = 1024; // more tiles: visited in the upload's order

// One query per thread; DP = D padded with zeros (queries and references alike) to a
// multiple of 4 so a reference is read from shared memory as float4 broadcasts.
template <int DP, bool Prune>
__global__ void __launch_bounds__(kThreads) candidatesKernel(
  RowParams p, TileParams tp, const float4* __restrict__ refs4, unsigned* __restrict__ cIdx, float* __restrict__ cF)
{
  constexpr int V = DP / 4;
  static_assert(kTile * V * sizeof(float4) >= kMaxRankedTiles * sizeof(float), "tile distances alias the tile");
  __shared__ float4 tile[kTile * V];
  __shared__ unsigned tileIdx[Prune ? kTile : 1];
  __shared__ unsigned short rankOrder[Prune ? kMaxRankedTiles : 1];
  __shared__ float q0[Prune ? DP : 1];
  const int count = rowsToPlace(p);
  if (static_cast<int>(blockIdx.x) * kThreads >= count)
  {
    return; // the whole block (before any barrier): beyond the rows to place
  }
  const int local = blockIdx.x * kThreads + threadIdx.x;
  const bool active = local < count;
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
  const int tiles = (p.M + kTile - 1) / kTile;
  const bool ranked = Prune && tiles <= kMaxRankedTiles;
  if (ranked)
  {
    // The tiles in order of their centroid's distance to thread 0's row (always active):
    // the block's rows are neighbouring voxels, so near tiles first lower the 8th distances
    // early and more of the far tiles are skipped. A counting rank, ties by tile.
    if (threadIdx.x == 0)
    {
#pragma unroll
      for (int c = 0; c < DP; ++c)
      {
        q0[c] = q[c];
      }
    }
    __syncthreads();
    float* dist = reinterpret_cast<float*>(tile);
    for (int t = threadIdx.x; t < tiles; t += kThreads)
    {
      float acc = 0.f;
#pragma unroll
      for (int v = 0; v < V; ++v)
      {
        const float4 c = tp.centroids[t * V + v];
        acc = fmaf(q0[4 * v] - c.x, q0[4 * v] - c.x, acc);
        acc = fmaf(q0[4 * v + 1] - c.y, q0[4 * v + 1] - c.y, acc);
        acc = fmaf(q0[4 * v + 2] - c.z, q0[4 * v + 2] - c.z, acc);
        acc = fmaf(q0[4 * v + 3] - c.w, q0[4 * v + 3] - c.w, acc);
      }
      dist[t] = acc <= 3.4e38f ? acc : __int_as_float(0x7f800000); // NaN ranks last too
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
    __syncthreads(); // rankOrder complete; dist (the tile's memory) read by everyone
  }
  unsigned long long visited = 0;
  for (int step = 0; step < tiles; ++step)
  {
    const int t = ranked ? rankOrder[step] : step;
    const int base = t * kTile;
    const int n = min(kTile, p.M - base);
    if (Prune)
    {
      bool need = false;
      if (active)
      {
        float acc = 0.f;
#pragma unroll
        for (int v = 0; v < V; ++v)
        {
          const float4 c = tp.centroids[t * V + v];
          acc = fmaf(q[4 * v] - c.x, q[4 * v] - c.x, acc);
          acc = fmaf(q[4 * v + 1] - c.y, q[4 * v + 1] - c.y, acc);
          acc = fmaf(q[4 * v + 2] - c.z, q[4 * v + 2] - c.z, acc);
          acc = fmaf(q[4 * v + 3] - c.w, q[4 * v + 3] - c.w, acc);
        }
        // |q - c| from below (its float value less 4 margins), less the radius; the
        // comparison allows 4 margins more (see TileParams). 1e-36: subnormal rounding.
        const float lb = sqrtf(acc) * (1.f - 4.f * tp.margin) - tp.radii[t];
        need = !(lb > 0.f && lb * lb > fmaf(bf[KP - 1], 1.f + 4.f * tp.margin, 1e-36f));
      }
      // Also the barrier that keeps the previous tile until everyone has scanned it.
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
    }
    __syncthreads();
    ++visited;
#pragma unroll 2
    for (int j = 0; j < n; ++j)
    {
      float acc = 0.f;
#pragma unroll
      for (int v = 0; v < V; ++v)
      {
        const float4 r = tile[j * V + v];
        const float t0 = q[4 * v] - r.x;
        const float t1 = q[4 * v + 1] - r.y;
        const float t2 = q[4 * v + 2] - r.z;
        const float t3 = q[4 * v + 3] - r.w;
        acc = fmaf(t0, t0, acc);
        acc = fmaf(t1, t1, acc);
        acc = fmaf(t2, t2, acc);
        acc = fmaf(t3, t3, acc);
      }
      if (acc <= bf[KP - 1])
      {
        // Kept by (distance, original index) whatever order the references come in; an
        // equal distance to a kept +inf is not kept (as the scan in index order did).
        const unsigned idx = Prune ? tileIdx[j] : static_cast<unsigned>(base + j);
        if (acc < bf[KP - 1] || (idx < bi[KP - 1] && bi[KP - 1] != kNone))
        {
          bf[KP - 1] = acc;
          bi[KP - 1] = idx;
#pragma unroll
          for (int s = KP - 1; s > 0; --s)
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
    }
  }
  if (Prune && threadIdx.x == 0 && tp.visits)
  {
    const unsigned long long rows = static_cast<unsigned long long>(min(kThreads, count - static_cast<int>(blockIdx.x) * kThreads));
    atomicAdd(tp.visits, visited * rows);
    atomicAdd(tp.visits + 1, rows);
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
  unsigned* neighbors, int k)
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
}

template <int DP>
void launchCandidates(
  const RowParams& p, const TileParams& tp, const float* refsPadded, unsigned* cIdx, float* cF, cudaStream_t stream)
{
  const int blocks = (p.count + kThreads - 1) / kThreads;
  const float4* refs4 = reinterpret_cast<const float4*>(refsPadded);
  if (tp.order)
  {
    candidatesKernel<DP, true><<<blocks, kThreads, 0, stream>>>(p, tp, refs4, cIdx, cF);
  }
  else
  {
    candidatesKernel<DP, false><<<blocks, kThreads, 0, stream>>>(p, tp, refs4, cIdx, cF);
  }
}

int paddedDimension(int D)
{
  return D <= 8 ? 8 : D <= 16 ? 16 : D <= 24 ? 24 : D <= 32 ? 32 : D <= 48 ? 48 : 64;
}

// The references reordered so that each tile of kTile consecutive ones is compact: a node
// of the recursion is split across its principal axis (a few power iterations on its
// covariance, in double) at a multiple of kTile, by rank along the axis (ties by index),
// until it is one tile. order[sorted position] = original index; deterministic.
std::vector<unsigned> orderReferences(const float* X, std::size_t M, int D)
{
  std::vector<unsigned> order(M);
  for (std::size_t i = 0; i < M; ++i)
  {
    order[i] = static_cast<unsigned>(i);
  }
  std::vector<double> mean(D), axis(D), next(D), x(D);
  std::vector<std::pair<double, unsigned>> keyed;
  struct Node
  {
    std::size_t lo, hi;
  };
  std::vector<Node> todo{ { 0, M } };
  while (!todo.empty())
  {
    const Node node = todo.back();
    todo.pop_back();
    const std::size_t n = node.hi - node.lo;
    if (n <= static_cast<std::size_t>(kTile))
    {
      continue;
    }
    std::fill(mean.begin(), mean.end(), 0.0);
    for (std::size_t i = node.lo; i < node.hi; ++i)
    {
      for (int c = 0; c < D; ++c)
      {
        mean[c] += X[static_cast<std::size_t>(order[i]) * D + c];
      }
    }
    for (int c = 0; c < D; ++c)
    {
      mean[c] /= static_cast<double>(n);
    }
    // Start from the widest coordinate (by variance) and iterate axis <- C axis.
    std::fill(axis.begin(), axis.end(), 0.0);
    for (std::size_t i = node.lo; i < node.hi; ++i)
    {
      for (int c = 0; c < D; ++c)
      {
        const double t = X[static_cast<std::size_t>(order[i]) * D + c] - mean[c];
        axis[c] += t * t;
      }
    }
    const int widest = static_cast<int>(std::max_element(axis.begin(), axis.end()) - axis.begin());
    std::fill(axis.begin(), axis.end(), 0.0);
    axis[widest] = 1.0;
    for (int iteration = 0; iteration < 8; ++iteration)
    {
      std::fill(next.begin(), next.end(), 0.0);
      for (std::size_t i = node.lo; i < node.hi; ++i)
      {
        double dot = 0.0;
        for (int c = 0; c < D; ++c)
        {
          x[c] = X[static_cast<std::size_t>(order[i]) * D + c] - mean[c];
          dot += x[c] * axis[c];
        }
        for (int c = 0; c < D; ++c)
        {
          next[c] += dot * x[c];
        }
      }
      double norm = 0.0;
      for (double v : next)
      {
        norm += v * v;
      }
      if (!(norm > 0.0) || !std::isfinite(norm))
      {
        break; // all equal (or not finite): keep the last axis
      }
      norm = std::sqrt(norm);
      for (int c = 0; c < D; ++c)
      {
        axis[c] = next[c] / norm;
      }
    }
    keyed.clear();
    for (std::size_t i = node.lo; i < node.hi; ++i)
    {
      double dot = 0.0;
      for (int c = 0; c < D; ++c)
      {
        dot += (X[static_cast<std::size_t>(order[i]) * D + c] - mean[c]) * axis[c];
      }
      keyed.emplace_back(std::isnan(dot) ? std::numeric_limits<double>::infinity() : dot, order[i]);
    }
    const std::size_t left = (n + kTile - 1) / kTile / 2 * kTile;
    std::nth_element(keyed.begin(), keyed.begin() + static_cast<std::ptrdiff_t>(left), keyed.end());
    for (std::size_t i = 0; i < n; ++i)
    {
      order[node.lo + i] = keyed[i].second;
    }
    todo.push_back({ node.lo, node.lo + left });
    todo.push_back({ node.lo + left, node.hi });
  }
  return order;
}

// Per tile of the ordered references: the centroid (float, padded to DP) and the radius,
// the largest distance of its references to that float centroid, in double, rounded up to
// a float; +inf for a tile with a value that is not finite (never skipped).
void tileBounds(const float* X, std::size_t M, int D, int DP, const std::vector<unsigned>& order,
  std::vector<float>& centroids, std::vector<float>& radii)
{
  const std::size_t tiles = (M + kTile - 1) / kTile;
  centroids.assign(tiles * static_cast<std::size_t>(DP), 0.f);
  radii.assign(tiles, 0.f);
  std::vector<double> mean(D);
  for (std::size_t t = 0; t < tiles; ++t)
  {
    const std::size_t lo = t * kTile, hi = std::min(M, lo + kTile);
    std::fill(mean.begin(), mean.end(), 0.0);
    bool finite = true;
    for (std::size_t i = lo; i < hi; ++i)
    {
      for (int c = 0; c < D; ++c)
      {
        const float v = X[static_cast<std::size_t>(order[i]) * D + c];
        finite = finite && std::isfinite(v);
        mean[c] += v;
      }
    }
    float* centroid = centroids.data() + t * DP;
    if (!finite)
    {
      radii[t] = std::numeric_limits<float>::infinity();
      continue;
    }
    for (int c = 0; c < D; ++c)
    {
      centroid[c] = static_cast<float>(mean[c] / static_cast<double>(hi - lo));
    }
    double r2 = 0.0;
    for (std::size_t i = lo; i < hi; ++i)
    {
      double s = 0.0;
      for (int c = 0; c < D; ++c)
      {
        const double t0 = static_cast<double>(X[static_cast<std::size_t>(order[i]) * D + c]) - centroid[c];
        s += t0 * t0;
      }
      r2 = std::max(r2, s);
    }
    // 1e-9: more than the double rounding of the sum; nextafter: up past the float rounding.
    radii[t] = std::nextafter(static_cast<float>(std::sqrt(r2) * (1.0 + 1e-9)), std::numeric_limits<float>::infinity());
  }
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
    std::size_t tempBytes = 0;
  };
  DeviceBuffer refs, refX, refY, scanTotal;
  // Tile pruning: refs in tile order, order[sorted] = original index, per-tile centroids
  // and radii, the visit counters (TileParams::visits). Empty: refs in original order.
  DeviceBuffer order, centroids, radii, visits;
  std::vector<Slot> slots;
  std::size_t M = 0, bytes = 0, chunk = 0;
  int D = 0, d = 0, k = 0, dim = 0, DP = 0;
  bool gather = false;
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
  // Candidates and scan list, run heads, run owners, placed list; CUB's temporary storage
  // (a few KiB per million rows) is bounded by 1 MiB here.
  return std::min(kChunkRows, std::max<std::size_t>(1, maxRows)) * (2 * KP + 4) * sizeof(unsigned) +
    2 * sizeof(unsigned) + (std::size_t(1) << 20);
}

std::size_t PlacementOnDevice::referenceBytes(std::size_t M, int D, int d)
{
  // Padded, original and embedding rows, the scan total; with pruning the order, the tiles'
  // centroids and radii and two visit counters.
  const std::size_t DP = static_cast<std::size_t>(paddedDimension(D)), tiles = (M + kTile - 1) / kTile;
  return M * (DP + D + d) * sizeof(float) + sizeof(unsigned long long) + M * sizeof(unsigned) +
    tiles * (DP + 1) * sizeof(float) + 2 * sizeof(unsigned long long);
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
  I.regularization = in.regularization;
  I.margin = in.distanceMargin;
  I.chunk = std::min(kChunkRows, std::max<std::size_t>(1, maxRows));
  // The padded copy the candidate kernel reads: in tile order when pruning.
  std::vector<unsigned> order;
  std::vector<float> centroids, radii;
  if (in.pruneTiles)
  {
    order = orderReferences(in.refX, in.M, in.D);
    tileBounds(in.refX, in.M, in.D, I.DP, order, centroids, radii);
  }
  std::vector<float> padded(in.M * static_cast<std::size_t>(I.DP), 0.f);
  for (std::size_t i = 0; i < in.M; ++i)
  {
    const std::size_t from = order.empty() ? i : order[i];
    std::copy(in.refX + from * in.D, in.refX + (from + 1) * in.D, padded.begin() + static_cast<std::ptrdiff_t>(i * I.DP));
  }
  if (!order.empty())
  {
    MCV_CUDA_TRY(cudaMalloc(&I.order.ptr, order.size() * sizeof(unsigned)));
    MCV_CUDA_TRY(cudaMalloc(&I.centroids.ptr, centroids.size() * sizeof(float)));
    MCV_CUDA_TRY(cudaMalloc(&I.radii.ptr, radii.size() * sizeof(float)));
    MCV_CUDA_TRY(cudaMalloc(&I.visits.ptr, 2 * sizeof(unsigned long long)));
    MCV_CUDA_TRY(cudaMemcpy(I.order.ptr, order.data(), order.size() * sizeof(unsigned), cudaMemcpyHostToDevice));
    MCV_CUDA_TRY(
      cudaMemcpy(I.centroids.ptr, centroids.data(), centroids.size() * sizeof(float), cudaMemcpyHostToDevice));
    MCV_CUDA_TRY(cudaMemcpy(I.radii.ptr, radii.data(), radii.size() * sizeof(float), cudaMemcpyHostToDevice));
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
  int slot, void* streamHandle, bool mergeEqualRows, std::string* error)
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
    deviceNeighbors };
  const TileParams tp{ I.order.as<unsigned>(), I.centroids.as<float4>(), I.radii.as<float>(),
    static_cast<float>(4.0 * (I.DP + 4) * std::ldexp(1.0, -24)), I.visits.as<unsigned long long>() };
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
        launchCandidates<8>(p, tp, I.refs.as<float>(), s.cIdx.as<unsigned>(), s.cF.as<float>(), stream);
        break;
      case 16:
        launchCandidates<16>(p, tp, I.refs.as<float>(), s.cIdx.as<unsigned>(), s.cF.as<float>(), stream);
        break;
      case 24:
        launchCandidates<24>(p, tp, I.refs.as<float>(), s.cIdx.as<unsigned>(), s.cF.as<float>(), stream);
        break;
      case 32:
        launchCandidates<32>(p, tp, I.refs.as<float>(), s.cIdx.as<unsigned>(), s.cF.as<float>(), stream);
        break;
      case 48:
        launchCandidates<48>(p, tp, I.refs.as<float>(), s.cIdx.as<unsigned>(), s.cF.as<float>(), stream);
        break;
      default:
        launchCandidates<64>(p, tp, I.refs.as<float>(), s.cIdx.as<unsigned>(), s.cF.as<float>(), stream);
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
        deviceNeighbors, I.k);
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
  *tiles = static_cast<int>((I.M + kTile - 1) / kTile);
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
