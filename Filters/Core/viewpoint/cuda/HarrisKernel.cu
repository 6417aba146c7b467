#include "HarrisKernel.cuh"

#include <algorithm>
#include <cfloat>
#include <cstdint>
#include <type_traits>
#include <utility>

namespace mcv
{
namespace cuda
{
namespace detail
{
namespace
{

__device__ __forceinline__ int clampi(int v, int lo, int hi)
{
  return min(max(v, lo), hi);
}

// An input value as loaded, kept in a register until it is stored to shared memory: the
// conversion to float waits for the load, so it is done at the store, a slice later, not
// right after the load (where it would stall the warp for the load's whole latency).
template <typename T>
using RawInput = std::conditional_t<std::is_same_v<T, float>, float, unsigned>;

// Input value as float. uint8: exact via the float bit pattern of 2^23 + v (an OR and a
// full-rate add instead of the quarter-rate integer-to-float conversion).
__device__ __forceinline__ float toFloat(float v)
{
  return v;
}
__device__ __forceinline__ float toFloat(unsigned v)
{
  return __uint_as_float(0x4B000000u | v) - 8388608.0f;
}

// Shared-memory layout of one block for radius R (all sizes in floats).
template <int R>
struct TileShape
{
  static constexpr int W = 2 * R + 1;                   // taps
  static constexpr int IW = kHarrisTileX + 2 * R + 2;   // input tile (gradient + blur halo)
  static constexpr int IH = kHarrisTileY + 2 * R + 2;
  static constexpr int IS = IW * IH;
  static constexpr int PWa = kHarrisTileX + 2 * R;      // product tile (blur halo)
  static constexpr int PW = (PWa + 3) & ~3;             // row stride, float4-aligned
  static constexpr int PH = kHarrisTileY + 2 * R;
  static constexpr int LOADS = (IS + kHarrisThreads - 1) / kHarrisThreads;
  static constexpr int ProdFloats = 6 * PH * PW;         // [6][PH][PW]
  static constexpr int XbFloats = 6 * PH * kHarrisTileX; // [6][PH][TX] x-smoothed
  static constexpr int InFloats = 3 * IS;                // ring of 3 input slices
  static constexpr int Positions = PH * PWa;              // product positions of a slice
  static std::size_t smemBytes(bool hist, bool table)
  {
    return static_cast<std::size_t>(ProdFloats + XbFloats + InFloats) * sizeof(float) +
      (table ? Positions * sizeof(unsigned) : 0) + (hist ? kLevel1Bins * sizeof(unsigned) : 0);
  }
  // harrisKernelPairs: two product and two x-smoothed slices, a ring of four input slices.
  static std::size_t smemBytesPairs(bool hist)
  {
    return static_cast<std::size_t>(2 * ProdFloats + 2 * XbFloats + 4 * IS) * sizeof(float) +
      Positions * sizeof(unsigned) + (hist ? kLevel1Bins * sizeof(unsigned) : 0);
  }
};

// Phases 0..W-1 of the unrolled z loop, each with its compile-time window slot.
template <int P, int W, typename F>
__device__ __forceinline__ void forPhases(F& f, int sv, int svEnd)
{
  if constexpr (P < W)
  {
    if (sv + P < svEnd)
    {
      f(std::integral_constant<int, P>{}, sv + P);
      forPhases<P + 1, W>(f, sv, svEnd);
    }
  }
}

// The block's level-1 histogram (kLevel1Bins counts in shared memory), cleared.
__device__ __forceinline__ void clearHistogram(unsigned* sHist, int tid)
{
  for (int i = tid; i < kLevel1Bins; i += kHarrisThreads)
  {
    sHist[i] = 0;
  }
}

// In-plane source offsets of this thread's input-tile elements (clamped: replicated border);
// -1 for an element past the tile.
template <int R>
__device__ __forceinline__ void inputOffsets(
  int (&inOff)[TileShape<R>::LOADS], int tid, int x0, int y0, int nx, int ny)
{
  using S = TileShape<R>;
#pragma unroll
  for (int i = 0; i < S::LOADS; ++i)
  {
    const int e = tid + i * kHarrisThreads;
    if (e < S::IS)
    {
      const int ly = e / S::IW, lx = e - ly * S::IW;
      inOff[i] = clampi(y0 - R - 1 + ly, 0, ny - 1) * nx + clampi(x0 - R - 1 + lx, 0, nx - 1);
    }
    else
    {
      inOff[i] = -1;
    }
  }
}

// This thread's elements of input slice q into registers (the next slice, loaded ahead of
// its use).
template <int R, typename T>
__device__ __forceinline__ void loadSlice(RawInput<T> (&pre)[TileShape<R>::LOADS], const T* in, int q,
  std::size_t plane, const int (&inOff)[TileShape<R>::LOADS])
{
  const T* src = in + static_cast<std::size_t>(q) * plane;
#pragma unroll
  for (int i = 0; i < TileShape<R>::LOADS; ++i)
  {
    // Only the last round can run past the tile (inOff -1); the others need no test.
    const bool whole = (i + 1) * kHarrisThreads <= TileShape<R>::IS;
    pre[i] = whole || inOff[i] >= 0 ? static_cast<RawInput<T>>(__ldg(src + inOff[i])) : 0;
  }
}

// The loaded slice q, as floats, into its slot of the ring of RING input slices.
template <int R, typename Raw, int RING = 3>
__device__ __forceinline__ void storeSlice(
  float* sIn, int q, const Raw (&pre)[TileShape<R>::LOADS], int tid)
{
  using S = TileShape<R>;
  float* dst = sIn + (q % RING) * S::IS;
#pragma unroll
  for (int i = 0; i < S::LOADS; ++i)
  {
    const int e = tid + i * kHarrisThreads;
    if ((i + 1) * kHarrisThreads <= S::IS || e < S::IS)
    {
      dst[e] = toFloat(pre[i]);
    }
  }
}

// Whether any of this thread's loaded elements of an input slice is non-zero (a NaN
// counts as non-zero). Each element is a plain value, so -0 and +0 are both zero here: a
// tile of zeros of either sign gives +0 gradients' products (x - y of two zeros is a zero,
// and every sum below starts from +0), the same as a skipped slice's.
template <int R, typename Raw>
__device__ __forceinline__ bool anyNonZero(const Raw (&pre)[TileShape<R>::LOADS])
{
  // elements past the tile were loaded as 0
  if constexpr (std::is_same_v<Raw, unsigned>)
  {
    unsigned any = 0;
#pragma unroll
    for (int i = 0; i < TileShape<R>::LOADS; ++i)
    {
      any |= pre[i];
    }
    return any != 0;
  }
  else
  {
    bool any = false;
#pragma unroll
    for (int i = 0; i < TileShape<R>::LOADS; ++i)
    {
      any |= pre[i] != 0;
    }
    return any;
  }
}

// The six gradient products of input-tile element c of slice sc (neighbour slices sm, sp)
// into d[0], d[CS], ..., d[5 CS].
template <int R>
__device__ __forceinline__ void productsAt(float* d, const float* sc, const float* sm,
  const float* sp, int c, float scaleX, float scaleY, float scaleZ)
{
  constexpr int IW = TileShape<R>::IW, CS = TileShape<R>::PH * TileShape<R>::PW;
  const float gx = (sc[c + 1] - sc[c - 1]) * scaleX;
  const float gy = (sc[c + IW] - sc[c - IW]) * scaleY;
  const float gz = (sp[c] - sm[c]) * scaleZ;
  d[0] = gx * gx;
  d[CS] = gx * gy;
  d[2 * CS] = gx * gz;
  d[3 * CS] = gy * gy;
  d[4 * CS] = gy * gz;
  d[5 * CS] = gz * gz;
}

// Six gradient products of slice cz on the product tile. A product position outside the
// grid takes the products of the clamped (border) voxel; gradients read clamped neighbours.
// Interior blocks (the whole product tile inside the grid) skip the clamping.
template <int R>
__device__ __forceinline__ void gradientProducts(float* sProd, const float* sIn, int cz,
  bool interior, int x0, int y0, const HarrisKernelArgs& a, int tid)
{
  using S = TileShape<R>;
  constexpr int IW = S::IW, IS = S::IS, PWa = S::PWa, PW = S::PW, PH = S::PH;
  const int nx = a.nx, ny = a.ny, nz = a.nz;
  const float* sc = sIn + (cz % 3) * IS;
  const float* sm = sIn + (max(cz - 1, 0) % 3) * IS;
  const float* sp = sIn + (min(cz + 1, nz - 1) % 3) * IS;
  auto at = [&](int c, int py, int px) {
    productsAt<R>(sProd + py * PW + px, sc, sm, sp, c, a.scaleX, a.scaleY, a.scaleZ);
  };
  if (interior)
  {
    for (int p = tid; p < PH * PWa; p += kHarrisThreads)
    {
      const int py = p / PWa, px = p - py * PWa;
      at((py + 1) * IW + px + 1, py, px);
    }
  }
  else
  {
    for (int p = tid; p < PH * PWa; p += kHarrisThreads)
    {
      const int py = p / PWa, px = p - py * PWa;
      const int cx = clampi(x0 - R + px, 0, nx - 1) - (x0 - R - 1);
      const int cy = clampi(y0 - R + py, 0, ny - 1) - (y0 - R - 1);
      at(cy * IW + cx, py, px);
    }
  }
}

// The product positions of a slice as a table built once per block: entry p (position
// py = p / PWa, px = p % PWa) holds the input-tile offset of the voxel it reads (clamped at
// the grid's border, so interior and border blocks share one loop) in its low 16 bits and
// the product-tile offset py * PW + px in its high 16 bits.
template <int R>
__device__ __forceinline__ void buildPositionTable(
  unsigned* sPos, int x0, int y0, int nx, int ny, int tid)
{
  using S = TileShape<R>;
  static_assert(S::IS < 65536 && S::PH * S::PW < 65536, "offsets fit in 16 bits");
  for (int p = tid; p < S::Positions; p += kHarrisThreads)
  {
    const int py = p / S::PWa, px = p - py * S::PWa;
    const int cx = clampi(x0 - R + px, 0, nx - 1) - (x0 - R - 1);
    const int cy = clampi(y0 - R + py, 0, ny - 1) - (y0 - R - 1);
    sPos[p] = static_cast<unsigned>(cy * S::IW + cx) |
      (static_cast<unsigned>(py * S::PW + px) << 16);
  }
}

// gradientProducts from the position table: the same values, one table read instead of
// the position's index arithmetic, rounds unrolled (only the last one tests its bound).
// Input slices sit in a ring of RING slots. PAIR: when `two`, slice cz + 1 (< nz) too,
// into the product tile after cz's, from the same table reads.
template <int R, int RING = 3, bool PAIR = false>
__device__ __forceinline__ void gradientProductsTable(float* sProd, const float* sIn,
  const unsigned* sPos, int cz, const HarrisKernelArgs& a, int tid, bool two = false)
{
  using S = TileShape<R>;
  constexpr int IS = S::IS, N = S::Positions;
  constexpr int ROUNDS = (N + kHarrisThreads - 1) / kHarrisThreads;
  const int nz = a.nz;
  const float* sc = sIn + (cz % RING) * IS;
  const float* sm = sIn + (max(cz - 1, 0) % RING) * IS;
  const float* sp = sIn + (min(cz + 1, nz - 1) % RING) * IS;
  [[maybe_unused]] const float* spp = PAIR ? sIn + (min(cz + 2, nz - 1) % RING) * IS : nullptr;
  const float scaleX = a.scaleX, scaleY = a.scaleY, scaleZ = a.scaleZ;
#pragma unroll
  for (int k = 0; k < ROUNDS; ++k)
  {
    const int p = tid + k * kHarrisThreads;
    if ((k + 1) * kHarrisThreads <= N || p < N)
    {
      const unsigned e = sPos[p];
      if constexpr (PAIR)
      {
        const int c = static_cast<int>(e & 0xffffu);
        float* d = sProd + (e >> 16);
        productsAt<R>(d, sc, sm, sp, c, scaleX, scaleY, scaleZ);
        if (two)
        {
          // slice cz + 1: its lower neighbour is cz, its upper one cz + 2 (clamped)
          productsAt<R>(d + S::ProdFloats, sp, sc, spp, c, scaleX, scaleY, scaleZ);
        }
      }
      else
      {
        productsAt<R>(sProd + (e >> 16), sc, sm, sp, static_cast<int>(e & 0xffffu), scaleX,
          scaleY, scaleZ);
      }
    }
  }
}

// x pass: each task smooths 4 consecutive outputs of one row of one channel (float4), over
// SLICES consecutive product slices (their tiles follow each other, as do the outputs').
template <int R, int SLICES = 1>
__device__ __forceinline__ void xPass(float* sXb, const float* sProd, const HarrisKernelArgs& a, int tid)
{
  using S = TileShape<R>;
  constexpr int W = S::W, PW = S::PW, PH = S::PH, TX = kHarrisTileX;
  constexpr int XG = TX / 4, NV = (4 + 2 * R + 3) / 4, TASKS = SLICES * 6 * PH * XG;
  constexpr int ROUNDS = (TASKS + kHarrisThreads - 1) / kHarrisThreads;
#pragma unroll
  for (int k = 0; k < ROUNDS; ++k)
  {
    const int t = tid + k * kHarrisThreads;
    if ((k + 1) * kHarrisThreads > TASKS && t >= TASKS)
    {
      break; // only the last round can run past the tasks
    }
    const int row = t / XG; // channel * PH + row
    const int g = t - row * XG;
    const float4* src = reinterpret_cast<const float4*>(sProd + row * PW) + g;
    float v[4 * NV];
#pragma unroll
    for (int j = 0; j < NV; ++j)
    {
      const float4 q = src[j];
      v[4 * j] = q.x;
      v[4 * j + 1] = q.y;
      v[4 * j + 2] = q.z;
      v[4 * j + 3] = q.w;
    }
    float o[4];
#pragma unroll
    for (int u = 0; u < 4; ++u)
    {
      float s = 0.f;
#pragma unroll
      for (int tt = 0; tt < W; ++tt)
      {
        s = fmaf(a.taps[tt], v[u + tt], s);
      }
      o[u] = s;
    }
    reinterpret_cast<float4*>(sXb + row * TX)[g] = make_float4(o[0], o[1], o[2], o[3]);
  }
}

// The z window of xy-smoothed tensors for the two voxels (rows 2*warp, 2*warp+1) of a
// thread: win[row][t][channel], t = 0 the oldest slice (or, unrolled, a ring of N slots,
// N = W, or W + 1 when two slices enter per round).
template <int N>
using ZWindow = float[2][N][6];

template <int N>
__device__ __forceinline__ void clearWindow(ZWindow<N>& win)
{
#pragma unroll
  for (int r = 0; r < 2; ++r)
#pragma unroll
    for (int t = 0; t < N; ++t)
#pragma unroll
      for (int c = 0; c < 6; ++c)
        win[r][t][c] = 0.f;
}

// y pass for the two voxels of this thread -> the newest z-window slot (slot P of the ring
// when unrolled, else the window shifts by one).
template <int R, bool UNROLL, int P, int N = 2 * R + 1>
__device__ __forceinline__ void yPassStore(
  ZWindow<N>& win, const float* sXb, const HarrisKernelArgs& a, int warp, int lane)
{
  using S = TileShape<R>;
  constexpr int W = S::W, PH = S::PH, TX = kHarrisTileX;
  const int r0 = 2 * warp;
#pragma unroll
  for (int c = 0; c < 6; ++c)
  {
    float col[W + 1];
#pragma unroll
    for (int j = 0; j < W + 1; ++j)
    {
      col[j] = sXb[(c * PH + r0 + j) * TX + lane];
    }
    float s0 = 0.f, s1 = 0.f;
#pragma unroll
    for (int t = 0; t < W; ++t)
    {
      s0 = fmaf(a.taps[t], col[t], s0);
      s1 = fmaf(a.taps[t], col[t + 1], s1);
    }
    if constexpr (UNROLL)
    {
      win[0][P][c] = s0;
      win[1][P][c] = s1;
    }
    else
    {
#pragma unroll
      for (int t = 0; t + 1 < W; ++t)
      {
        win[0][t][c] = win[0][t + 1][c];
        win[1][t][c] = win[1][t + 1][c];
      }
      win[0][W - 1][c] = s0;
      win[1][W - 1][c] = s1;
    }
  }
}

// The clamped slice repeats (z border): the newest slice enters the window again.
template <int W, bool UNROLL, int P, int N = W>
__device__ __forceinline__ void repeatStore(ZWindow<N>& win)
{
#pragma unroll
  for (int c = 0; c < 6; ++c)
  {
    if constexpr (UNROLL)
    {
      win[0][P][c] = win[0][(P + N - 1) % N][c];
      win[1][P][c] = win[1][(P + N - 1) % N][c];
    }
    else
    {
#pragma unroll
      for (int t = 0; t + 1 < W; ++t)
      {
        win[0][t][c] = win[0][t + 1][c];
        win[1][t][c] = win[1][t + 1][c];
      }
    }
  }
}

// A slice whose products are all zero enters the z window as zeros (what the y pass of a
// zero product tile gives: every tap times +0 summed from +0).
template <int W, bool UNROLL, int P, int N = W>
__device__ __forceinline__ void zeroStore(ZWindow<N>& win)
{
#pragma unroll
  for (int c = 0; c < 6; ++c)
  {
    if constexpr (UNROLL)
    {
      win[0][P][c] = 0.f;
      win[1][P][c] = 0.f;
    }
    else
    {
#pragma unroll
      for (int t = 0; t + 1 < W; ++t)
      {
        win[0][t][c] = win[0][t + 1][c];
        win[1][t][c] = win[1][t + 1][c];
      }
      win[0][W - 1][c] = 0.f;
      win[1][W - 1][c] = 0.f;
    }
  }
}

// z pass of voxel rr of this thread after phase P: the smoothed structure tensor
// m = (xx, xy, xz, yy, yz, zz).
template <int W, bool UNROLL, int P, int N = W>
__device__ __forceinline__ void zSmooth(
  float (&m)[6], const ZWindow<N>& win, int rr, const HarrisKernelArgs& a)
{
#pragma unroll
  for (int c = 0; c < 6; ++c)
  {
    float s = 0.f;
#pragma unroll
    for (int t = 0; t < W; ++t)
    {
      // slot of the t-th oldest slice: a ring whose newest slot is P, else the shifted window
      s = fmaf(a.taps[t], win[rr][UNROLL ? (P + N - W + 1 + t) % N : t][c], s);
    }
    m[c] = s;
  }
}

// The Harris response of a smoothed tensor: det - k tr^3, or det2 - k tr2^2 on the x,y
// block (planar).
__device__ __forceinline__ float harrisResponse(const float (&m)[6], const HarrisKernelArgs& a)
{
  const float xx = m[0], xy = m[1], xz = m[2], yy = m[3], yz = m[4], zz = m[5];
  float response;
  if (a.planar)
  {
    const float tr = xx + yy;
    response = (xx * yy - xy * xy) - a.k * tr * tr;
  }
  else
  {
    const float det =
      xx * (yy * zz - yz * yz) - xy * (xy * zz - yz * xz) + xz * (xy * yz - yy * xz);
    const float tr = xx + yy + zz;
    response = det - a.k * tr * tr * tr;
  }
  return response;
}

// Candidates (R > 0, finite) counted by their top 11 bits in the block's histogram.
__device__ __forceinline__ void countCandidate(
  unsigned* sHist, float response, bool inside, int histMode, int lane)
{
  const bool cand = inside && response > 0.f && response <= FLT_MAX;
  const unsigned bin = __float_as_uint(response) >> 21;
  if (histMode == 0)
  {
    // one atomic per group of lanes that share a bin
    const unsigned active = __ballot_sync(0xffffffffu, cand);
    if (cand)
    {
      const unsigned peers = __match_any_sync(active, bin);
      if (lane == __ffs(peers) - 1)
      {
        atomicAdd(&sHist[bin], static_cast<unsigned>(__popc(peers)));
      }
    }
  }
  else if (cand)
  {
    atomicAdd(&sHist[bin], 1u);
  }
}

// The row maxima (HarrisKernelArgs::rowMax) of a warp's two rows 2 warp, 2 warp + 1 of the
// tile (a row pair): lane 0 stores, per output slice, the largest candidate's bit pattern
// over the pair's two 32-wide row segments (positive floats order like their bits), 0
// without one. The place is computed once per thread; offer() is called for row 0, then
// row 1, by all lanes of the warp.
struct RowMaxOut
{
  unsigned* base = nullptr; // this warp's pair, output slice zOutBegin
  std::size_t plane = 0;    // entries per output slice
  bool writer = false;
  unsigned key = 0;         // row 0's candidate, until row 1 is offered

  __device__ __forceinline__ RowMaxOut(const HarrisKernelArgs& a, int y0, int warp, int lane)
  {
    if (a.rowMax)
    {
      const int pair = y0 / 2 + warp;
      plane = static_cast<std::size_t>((a.ny + 1) / 2) * gridDim.x;
      base = a.rowMax + static_cast<std::size_t>(pair) * gridDim.x + blockIdx.x;
      writer = lane == 0 && 2 * pair < a.ny;
    }
  }

  // Row rr of output slice zOut (counted from zOutBegin).
  __device__ __forceinline__ void offer(int zOut, int rr, float response, bool inside)
  {
    const bool cand = inside && response > 0.f && response <= FLT_MAX;
    const unsigned k = cand ? __float_as_uint(response) : 0u;
    if (rr == 0)
    {
      key = k;
      return;
    }
    const unsigned both = max(key, k);
#if __CUDA_ARCH__ >= 800
    const unsigned m = __reduce_max_sync(0xffffffffu, both);
#else
    unsigned m = both;
    for (int o = 16; o > 0; o >>= 1)
    {
      m = max(m, __shfl_xor_sync(0xffffffffu, m, o));
    }
#endif
    if (writer)
    {
      base[static_cast<std::size_t>(zOut) * plane] = m;
    }
  }
};

// The block's histogram added to the global one.
__device__ __forceinline__ void flushHistogram(unsigned long long* hist, const unsigned* sHist, int tid)
{
  for (int i = tid; i < kLevel1Bins; i += kHarrisThreads)
  {
    const unsigned c = sHist[i];
    if (c)
    {
      atomicAdd(&hist[i], static_cast<unsigned long long>(c));
    }
  }
}

// A block's place in the grid and its thread's: the xy tile's origin and the output slices
// [zb, ze). Clears the block's histogram when there is one.
struct BlockPlace
{
  int tid, lane, warp;
  int x0, y0; // tile origin
  int zb, ze; // output slices
  std::size_t plane;
  bool withHist; // the level-1 histogram is counted

  __device__ __forceinline__ BlockPlace(const HarrisKernelArgs& a, unsigned* sHist)
  {
    tid = threadIdx.x;
    lane = tid & 31;
    warp = tid >> 5;
    x0 = blockIdx.x * kHarrisTileX;
    y0 = blockIdx.y * kHarrisTileY;
    zb = a.zOutBegin + blockIdx.z * a.zChunk;
    ze = min(zb + a.zChunk, a.zOutEnd);
    plane = static_cast<std::size_t>(a.nx) * a.ny;
    withHist = a.hist != nullptr;
    if (withHist)
    {
      clearHistogram(sHist, tid);
    }
  }
};

// The thread's two voxels: the in-plane offset of the first (the second is one row on) and
// which of the two are inside the grid.
struct OwnVoxels
{
  int offset;
  bool inside[2];

  __device__ __forceinline__ OwnVoxels(const BlockPlace& bp, int nx, int ny)
  {
    const int gx = bp.x0 + bp.lane, gy = bp.y0 + 2 * bp.warp;
    offset = gx < nx && gy < ny ? gx + gy * nx : 0;
    inside[0] = gx < nx && gy < ny;
    inside[1] = gx < nx && gy + 1 < ny;
  }
};

// V (variant) bit 0: z loop unrolled by the kernel width, the z window a register ring with
// compile-time slots (no shifts); bit 1: 3 blocks per SM (register cap 85) instead of 2;
// bit 2: the product positions from a table built once per block (buildPositionTable), the
// output offsets of the thread's two voxels computed once, and two barriers per slice
// instead of three (the next input slice stored between the products and the y pass); and
// empty space skipped exactly: a slice whose input slices (itself and its two neighbours,
// the whole input tile with its halo) are all zero has all-zero products, so its products,
// x pass and y pass are not computed and it enters the z window as zeros; an output slice
// whose whole z window is such slices has the response +0 everywhere (det - k tr^3 of the
// zero tensor), stored without the z pass. Whether a loaded input slice is all zero is
// decided by the barrier that publishes it (__syncthreads_or), so every decision is the
// same for the whole block and the results are bit for bit those of the full arithmetic.
template <typename T, int R, int V>
__global__ void __launch_bounds__(kHarrisThreads, (V & 2) ? 3 : 2)
  harrisKernel(const T* __restrict__ in, const HarrisKernelArgs a)
{
  constexpr bool UNROLL = (V & 1) != 0;
  constexpr bool TABLE = (V & 4) != 0;
  using S = TileShape<R>;
  constexpr int W = S::W;
  constexpr int TX = kHarrisTileX;
  if (a.blockBound)
  {
    // Pruned (HarrisBound.cuh): the whole block returns at once, before any barrier.
    const float bound = a.blockBound[(blockIdx.z * gridDim.y + blockIdx.y) * gridDim.x + blockIdx.x];
    if (!(bound >= a.gate[0]) || bound >= a.gate[1])
    {
      return;
    }
  }

  extern __shared__ float4 smem4[];
  float* sProd = reinterpret_cast<float*>(smem4);
  float* sXb = sProd + S::ProdFloats;
  float* sIn = sXb + S::XbFloats;
  unsigned* sPos = reinterpret_cast<unsigned*>(sIn + S::InFloats);
  unsigned* sHist = sPos + (TABLE ? S::Positions : 0);

  const BlockPlace bp(a, sHist);
  const int tid = bp.tid, lane = bp.lane, warp = bp.warp;
  const int nx = a.nx, ny = a.ny, nz = a.nz;
  const int x0 = bp.x0, y0 = bp.y0, zb = bp.zb, ze = bp.ze;
  const std::size_t plane = bp.plane;
  const bool withHist = bp.withHist;
  if constexpr (TABLE)
  {
    buildPositionTable<R>(sPos, x0, y0, nx, ny, tid); // read after the first barrier
  }

  int inOff[S::LOADS];
  inputOffsets<R>(inOff, tid, x0, y0, nx, ny);
  RawInput<T> pre[S::LOADS]; // the next input slice, loaded ahead of its use
  const bool interior = x0 - R >= 0 && x0 + TX + R <= nx && y0 - R >= 0 &&
    y0 + kHarrisTileY + R <= ny;
  float win[2][W][6];
  clearWindow<W>(win);
  const OwnVoxels own(bp, nx, ny);
  RowMaxOut rowMaxOut(a, y0, warp, lane);

  // Empty-space skipping (TABLE): bit i of nzBits tells whether input slice nextLoad - 1 - i
  // (the newest stored one, and older) has a non-zero element in the block's input tile;
  // slices before the first one stored count as zero, and none of them is ever needed.
  [[maybe_unused]] unsigned nzBits = 0;

  // The z pass, the response and its output for the two voxels of this thread at slice z.
  auto emit = [&](auto phase, int z) {
    constexpr int P = decltype(phase)::value;
    [[maybe_unused]] float* outSlice = nullptr;
    if constexpr (TABLE)
    {
      outSlice = a.response + static_cast<std::size_t>(z - a.zOutBegin) * plane;
    }
    // The response of slice z reads input slices z - R - 1 .. z + R + 1 (clamped). When it
    // is emitted, the newest stored slice is at most z + R + 2 (and at least z + R + 1 or
    // the last one), so the 2 R + 4 newest flags cover them (and one more, which only makes
    // the test stricter). All zero: the window holds only zeros, the z pass gives zeros.
    [[maybe_unused]] const bool zeroWindow = TABLE && (nzBits & ((1u << (2 * R + 4)) - 1u)) == 0u;
#pragma unroll
    for (int rr = 0; rr < 2; ++rr)
    {
      float m[6] = {};
      if (!zeroWindow)
      {
        zSmooth<W, UNROLL, P>(m, win, rr, a);
      }
      const float response = harrisResponse(m, a);
      bool inside;
      if constexpr (TABLE)
      {
        inside = own.inside[rr];
        if (inside)
        {
          outSlice[own.offset + rr * nx] = response;
        }
      }
      else
      {
        const int gx = x0 + lane, gy = y0 + 2 * warp + rr;
        inside = gx < nx && gy < ny;
        if (inside)
        {
          a.response[static_cast<std::size_t>(z - a.zOutBegin) * plane +
            static_cast<std::size_t>(gy) * nx + gx] =
            response;
        }
      }
      if (withHist)
      {
        countCandidate(sHist, response, inside, a.histMode, lane);
      }
      if (a.rowMax)
      {
        rowMaxOut.offer(z - a.zOutBegin, rr, response, inside);
      }
    }
  };

  // Virtual slices sv = zb-R .. ze+R-1 feed the z window; sv outside the grid repeats the
  // border slice. Each distinct clamped slice is computed once.
  const int svBegin = zb - R, svEnd = ze + R;
  const int czFirst = clampi(svBegin, 0, nz - 1);
  const int czLast = clampi(svEnd - 1, 0, nz - 1);
  const int qLast = min(czLast + 1, nz - 1); // last input slice this block reads
  for (int q = max(czFirst - 1, 0); q <= min(czFirst + 1, nz - 1); ++q)
  {
    loadSlice<R>(pre, in, q, plane, inOff);
    storeSlice<R>(sIn, q, pre, tid);
    if constexpr (TABLE)
    {
      // the barrier that publishes slice q (and, the first time, the position table)
      nzBits = (nzBits << 1) | (__syncthreads_or(anyNonZero<R>(pre)) ? 1u : 0u);
    }
  }
  int nextLoad = min(czFirst + 1, nz - 1) + 1;
  if (nextLoad <= qLast)
  {
    loadSlice<R>(pre, in, nextLoad, plane, inOff);
  }
  int lastCz = -1;
  auto step = [&](auto phase, int sv) {
    constexpr int P = decltype(phase)::value;
    const int cz = clampi(sv, 0, nz - 1);
    if (cz != lastCz)
    {
      if constexpr (TABLE)
      {
        // Two barriers per slice: the next input slice (nextLoad == cz + 2) is stored after
        // the products of cz, into the slot of cz - 1 that they were the last to read, and
        // is visible from the barrier before the y pass on, ahead of the products of cz + 1.
        // The products of cz read input slices cz - 1 .. cz + 1 (clamped); the newest stored
        // slice is cz + 1, or cz when cz is the last one (then the three newest flags are
        // those of cz - 2 .. cz, a stricter test).
        const bool empty = (nzBits & 7u) == 0u;
        if (!empty)
        {
          gradientProductsTable<R>(sProd, sIn, sPos, cz, a, tid);
          __syncthreads();
        }
        // An empty slice reads no input slice, so the slot of cz - 1 is free without the
        // barrier; sProd and sXb are not touched until the next computed slice's barrier.
        bool stored = false, storedNonZero = false;
        if (nextLoad <= qLast)
        {
          storeSlice<R>(sIn, nextLoad, pre, tid);
          storedNonZero = anyNonZero<R>(pre);
          stored = true; // the same for the whole block
          ++nextLoad;
          if (nextLoad <= qLast)
          {
            loadSlice<R>(pre, in, nextLoad, plane, inOff);
          }
        }
        if (!empty)
        {
          xPass<R>(sXb, sProd, a, tid);
        }
        const bool anyStored = __syncthreads_or(storedNonZero) != 0;
        if (stored)
        {
          nzBits = (nzBits << 1) | (anyStored ? 1u : 0u);
        }
        if (empty)
        {
          zeroStore<W, UNROLL, P>(win);
        }
        else
        {
          yPassStore<R, UNROLL, P>(win, sXb, a, warp, lane);
        }
      }
      else
      {
        if (lastCz >= 0 && nextLoad <= qLast)
        {
          // nextLoad == cz + 1: its slot held cz - 2, last read before two barriers ago.
          storeSlice<R>(sIn, nextLoad, pre, tid);
          ++nextLoad;
          if (nextLoad <= qLast)
          {
            loadSlice<R>(pre, in, nextLoad, plane, inOff);
          }
        }
        __syncthreads();
        gradientProducts<R>(sProd, sIn, cz, interior, x0, y0, a, tid);
        __syncthreads();
        xPass<R>(sXb, sProd, a, tid);
        __syncthreads();
        yPassStore<R, UNROLL, P>(win, sXb, a, warp, lane);
      }
      lastCz = cz;
    }
    else
    {
      repeatStore<W, UNROLL, P>(win);
    }
    if (sv >= zb + R)
    {
      emit(phase, sv - R);
    }
  };
  if constexpr (UNROLL)
  {
    for (int sv = svBegin; sv < svEnd; sv += W)
    {
      forPhases<0, W>(step, sv, svEnd);
    }
  }
  else
  {
    for (int sv = svBegin; sv < svEnd; ++sv)
    {
      step(std::integral_constant<int, W - 1>{}, sv);
    }
  }

  if (withHist)
  {
    __syncthreads();
    flushHistogram(a.hist, sHist, tid);
  }
}

// The next two input slices of harrisKernelPairs as loaded (slices q and q + 1 of the
// thread's input-tile elements). uint8: both bytes of an element in one register (q in
// bits 0-7, q + 1 in bits 8-15), which keeps the kernel within the 128 registers of two
// blocks per SM without spills; float: two registers.
template <typename T, int R>
struct NextSlices
{
  static constexpr int L = TileShape<R>::LOADS;
  static constexpr bool PACKED = !std::is_same_v<T, float>;
  RawInput<T> a[L];
  RawInput<T> b[PACKED ? 1 : L];

  // Slice q as the first (the second is cleared when packed).
  __device__ __forceinline__ void loadFirst(const T* in, int q, std::size_t plane, const int (&inOff)[L])
  {
    loadSlice<R>(a, in, q, plane, inOff);
  }
  __device__ __forceinline__ void loadSecond(const T* in, int q, std::size_t plane, const int (&inOff)[L])
  {
    if constexpr (PACKED)
    {
      RawInput<T> t[L];
      loadSlice<R>(t, in, q, plane, inOff);
#pragma unroll
      for (int i = 0; i < L; ++i)
      {
        a[i] = (a[i] & 0xffu) | (t[i] << 8);
      }
    }
    else
    {
      loadSlice<R>(b, in, q, plane, inOff);
    }
  }
  // The first (second) slice into its slot q of the ring of four input slices.
  __device__ __forceinline__ void storeFirst(float* sIn, int q, int tid) const
  {
    if constexpr (PACKED)
    {
      RawInput<T> t[L];
#pragma unroll
      for (int i = 0; i < L; ++i)
      {
        t[i] = a[i] & 0xffu;
      }
      storeSlice<R, RawInput<T>, 4>(sIn, q, t, tid);
    }
    else
    {
      storeSlice<R, RawInput<T>, 4>(sIn, q, a, tid);
    }
  }
  __device__ __forceinline__ void storeSecond(float* sIn, int q, int tid) const
  {
    if constexpr (PACKED)
    {
      RawInput<T> t[L];
#pragma unroll
      for (int i = 0; i < L; ++i)
      {
        t[i] = a[i] >> 8;
      }
      storeSlice<R, RawInput<T>, 4>(sIn, q, t, tid);
    }
    else
    {
      storeSlice<R, RawInput<T>, 4>(sIn, q, b, tid);
    }
  }
  // The second slice becomes the first.
  __device__ __forceinline__ void shift()
  {
#pragma unroll
    for (int i = 0; i < L; ++i)
    {
      if constexpr (PACKED)
      {
        a[i] >>= 8;
      }
      else
      {
        a[i] = b[i];
      }
    }
  }
};

// Rounds of two virtual slices (sv, sv + 1), phases 0..N/2-1 of the unrolled z loop.
template <int P, int N, typename F>
__device__ __forceinline__ void forPairs(F& f, int sv, int svEnd)
{
  if constexpr (2 * P < N)
  {
    if (sv + 2 * P < svEnd)
    {
      f(std::integral_constant<int, P>{}, sv + 2 * P);
      forPairs<P + 1, N>(f, sv, svEnd);
    }
  }
}

// The two-slice form of harrisKernel's table variant (variant 8): each round of two barriers
// forms the products, x pass and y pass of two input slices (where both are new), so the
// barriers, the table reads and the per-slice index work are paid once per two slices. The
// shared tiles hold two product and two x-smoothed slices and a ring of four input slices
// (89 KB at width 5, still two blocks per SM); the z window is a register ring of W + 1
// slots, two slots per round. Same operations in the same order as harrisKernel. Slower
// than variant 5 on an H200 (docs/benchmarks.md, section 2), so not the default.
template <typename T, int R>
__global__ void __launch_bounds__(kHarrisThreads, 2)
  harrisKernelPairs(const T* __restrict__ in, const HarrisKernelArgs a)
{
  using S = TileShape<R>;
  constexpr int W = S::W, NS = W + 1; // window slots: W + 1 is even, two per round

  extern __shared__ float4 smem4[];
  float* sProd = reinterpret_cast<float*>(smem4);
  float* sXb = sProd + 2 * S::ProdFloats;
  float* sIn = sXb + 2 * S::XbFloats;
  unsigned* sPos = reinterpret_cast<unsigned*>(sIn + 4 * S::IS);
  unsigned* sHist = sPos + S::Positions;

  const BlockPlace bp(a, sHist);
  const int tid = bp.tid, nz = a.nz, zb = bp.zb;
  const std::size_t plane = bp.plane;
  buildPositionTable<R>(sPos, bp.x0, bp.y0, a.nx, a.ny, tid); // read after the first barrier

  int inOff[S::LOADS];
  inputOffsets<R>(inOff, tid, bp.x0, bp.y0, a.nx, a.ny);
  float win[2][NS][6];
  clearWindow<NS>(win);
  const OwnVoxels own(bp, a.nx, a.ny);
  RowMaxOut rowMaxOut(a, bp.y0, bp.warp, bp.lane);

  // The z pass, the response and its output for the two voxels of this thread at slice z,
  // the window's newest slot being P.
  auto emit = [&](auto slot, int z) {
    constexpr int P = decltype(slot)::value;
    float* outSlice = a.response + static_cast<std::size_t>(z - a.zOutBegin) * plane;
#pragma unroll
    for (int rr = 0; rr < 2; ++rr)
    {
      float m[6];
      zSmooth<W, true, P, NS>(m, win, rr, a);
      const float response = harrisResponse(m, a);
      if (own.inside[rr])
      {
        outSlice[own.offset + rr * a.nx] = response;
      }
      if (bp.withHist)
      {
        countCandidate(sHist, response, own.inside[rr], a.histMode, bp.lane);
      }
      if (a.rowMax)
      {
        rowMaxOut.offer(z - a.zOutBegin, rr, response, own.inside[rr]);
      }
    }
  };

  // Virtual slices sv = zb-R .. ze+R-1 as in harrisKernel. The input ring holds slices
  // q % 4; before the products of new slices up to c it holds c - 1 .. c + 1 (clamped) and,
  // when c is the second of a pair, c - 2 too; the products' last reads of it are behind
  // the first barrier, so slices up to c + 3 are stored then (at most two per round).
  const int svBegin = zb - R, svEnd = bp.ze + R;
  const int czFirst = clampi(svBegin, 0, nz - 1);
  const int czLast = clampi(svEnd - 1, 0, nz - 1);
  const int qLast = min(czLast + 1, nz - 1); // last input slice this block reads
  const int qFill = min(czFirst + 2, qLast);
  for (int q = max(czFirst - 1, 0); q <= qFill; ++q)
  {
    RawInput<T> raw[S::LOADS];
    loadSlice<R>(raw, in, q, plane, inOff);
    storeSlice<R, RawInput<T>, 4>(sIn, q, raw, tid);
  }
  NextSlices<T, R> pre; // input slices nextLoad and nextLoad + 1
  int nextLoad = qFill + 1;
  if (nextLoad <= qLast)
  {
    pre.loadFirst(in, nextLoad, plane, inOff);
  }
  if (nextLoad + 1 <= qLast)
  {
    pre.loadSecond(in, nextLoad + 1, plane, inOff);
  }
  int lastCz = -1;
  __syncthreads(); // the first input slices, the position table

  auto round = [&](auto phase, int sv) {
    constexpr int P = decltype(phase)::value;
    const bool has1 = sv + 1 < svEnd;
    const int cz0 = clampi(sv, 0, nz - 1), cz1 = clampi(sv + 1, 0, nz - 1);
    const bool fresh0 = cz0 != lastCz, fresh1 = has1 && cz1 != cz0;
    if (fresh0 || fresh1)
    {
      const int first = fresh0 ? cz0 : cz1;
      const bool two = fresh0 && fresh1;
      const int last = two ? cz1 : first;
      gradientProductsTable<R, 4, true>(sProd, sIn, sPos, first, a, tid, two);
      __syncthreads();
      const int stores = max(min(last + 3, qLast) - nextLoad + 1, 0); // 0, 1 or 2
      if (stores > 0)
      {
        pre.storeFirst(sIn, nextLoad, tid);
        if (stores > 1)
        {
          pre.storeSecond(sIn, nextLoad + 1, tid);
          nextLoad += 2;
          if (nextLoad <= qLast)
          {
            pre.loadFirst(in, nextLoad, plane, inOff);
          }
        }
        else
        {
          ++nextLoad;
          pre.shift();
        }
        if (nextLoad + 1 <= qLast)
        {
          pre.loadSecond(in, nextLoad + 1, plane, inOff);
        }
      }
      if (two)
      {
        xPass<R, 2>(sXb, sProd, a, tid);
      }
      else
      {
        xPass<R, 1>(sXb, sProd, a, tid);
      }
      __syncthreads();
      lastCz = last;
    }
    // the x-smoothed slices: the first new one in sXb, the second after it
    if (fresh0)
    {
      yPassStore<R, true, 2 * P, NS>(win, sXb, a, bp.warp, bp.lane);
    }
    else
    {
      repeatStore<W, true, 2 * P, NS>(win);
    }
    if (sv >= zb + R)
    {
      emit(std::integral_constant<int, 2 * P>{}, sv - R);
    }
    if (has1)
    {
      if (fresh1)
      {
        yPassStore<R, true, 2 * P + 1, NS>(win, sXb + (fresh0 ? S::XbFloats : 0), a, bp.warp, bp.lane);
      }
      else
      {
        repeatStore<W, true, 2 * P + 1, NS>(win);
      }
      if (sv + 1 >= zb + R)
      {
        emit(std::integral_constant<int, 2 * P + 1>{}, sv + 1 - R);
      }
    }
  };
  for (int sv = svBegin; sv < svEnd; sv += NS)
  {
    forPairs<0, NS>(round, sv, svEnd);
  }

  if (bp.withHist)
  {
    __syncthreads();
    flushHistogram(a.hist, sHist, tid);
  }
}

// Model: time ~ waves * (slices per block + 2 radius halo slices) for a volume without
// empty space; the largest chunk wins ties (less halo work). `balance` (a kernel that skips
// empty space): the smallest chunk within 5 % of that cost. Blocks then take very
// different times (an empty one is cheap), and with more blocks than resident places the
// ones that finish early take over the remaining ones, where one wave of long blocks would
// last as long as its fullest block.
int chooseZChunk(int tiles, int nz, int resident, int radius, bool balance)
{
  if (resident < 1)
  {
    resident = 1;
  }
  auto cost = [&](int zc) {
    const long long blocks = static_cast<long long>(tiles) * ((nz + zc - 1) / zc);
    const long long waves = (blocks + resident - 1) / resident;
    return static_cast<double>(waves) * (zc + 2 * radius);
  };
  double best = 1e300;
  int bestChunk = nz;
  for (int chunks = 1; chunks <= nz; ++chunks)
  {
    const int zc = (nz + chunks - 1) / chunks;
    if (cost(zc) < best)
    {
      best = cost(zc);
      bestChunk = zc;
    }
  }
  if (balance)
  {
    for (int chunks = 1; chunks <= nz; ++chunks)
    {
      const int zc = (nz + chunks - 1) / chunks;
      if (cost(zc) <= 1.05 * best)
      {
        bestChunk = std::min(bestChunk, zc);
      }
    }
  }
  return bestChunk;
}

template <typename T, int R, int V>
cudaError_t launchRadius(
  const T* input, const HarrisKernelArgs& args, int zChunk, cudaStream_t stream, int* used)
{
  using S = TileShape<R>;
  constexpr bool PAIRS = V == kHarrisPairsVariant;
  const bool hist = args.hist != nullptr;
  const std::size_t smem = PAIRS ? S::smemBytesPairs(hist) : S::smemBytes(hist, (V & 4) != 0);
  void (*kernel)(const T*, HarrisKernelArgs) = nullptr;
  if constexpr (PAIRS)
  {
    kernel = harrisKernelPairs<T, R>;
  }
  else
  {
    kernel = harrisKernel<T, R, V>;
  }
  cudaError_t err =
    cudaFuncSetAttribute(kernel, cudaFuncAttributeMaxDynamicSharedMemorySize, static_cast<int>(smem));
  if (err != cudaSuccess)
  {
    return err;
  }
  const int tilesX = (args.nx + kHarrisTileX - 1) / kHarrisTileX;
  const int tilesY = (args.ny + kHarrisTileY - 1) / kHarrisTileY;
  HarrisKernelArgs a = args;
  if (a.zOutEnd <= 0)
  {
    a.zOutBegin = 0;
    a.zOutEnd = a.nz;
  }
  if (a.zOutBegin < 0 || a.zOutEnd > a.nz || a.zOutBegin >= a.zOutEnd)
  {
    return cudaErrorInvalidValue;
  }
  const int outSlices = a.zOutEnd - a.zOutBegin;
  if (zChunk <= 0)
  {
    int device = 0, sms = 1, perSM = 1;
    if ((err = cudaGetDevice(&device)) != cudaSuccess ||
      (err = cudaDeviceGetAttribute(&sms, cudaDevAttrMultiProcessorCount, device)) != cudaSuccess ||
      (err = cudaOccupancyMaxActiveBlocksPerMultiprocessor(&perSM, kernel, kHarrisThreads, smem)) !=
        cudaSuccess)
    {
      return err;
    }
    zChunk = chooseZChunk(tilesX * tilesY, outSlices, sms * perSM, R, !PAIRS && (V & 4) != 0);
  }
  zChunk = min(max(zChunk, 1), outSlices);
  a.zChunk = zChunk;
  if (used)
  {
    *used = zChunk;
  }
  const dim3 grid(tilesX, tilesY, (outSlices + zChunk - 1) / zChunk);
  if (grid.y > 65535u || grid.z > 65535u)
  {
    return cudaErrorInvalidConfiguration;
  }
  kernel<<<grid, kHarrisThreads, smem, stream>>>(input, a);
  return cudaGetLastError();
}

// Width 5 with kernel variant `variant` (one of V...).
template <typename T, int... V>
cudaError_t launchVariant(int variant, const T* input, const HarrisKernelArgs& args, int zChunk,
  cudaStream_t stream, int* used, std::integer_sequence<int, V...>)
{
  cudaError_t err = cudaErrorInvalidValue;
  (void)((variant == V && ((err = launchRadius<T, 2, V>(input, args, zChunk, stream, used)), true)) ||
    ...);
  return err;
}

} // namespace

template <typename T>
cudaError_t launchHarris(const T* input, HarrisKernelArgs args, int radius, int zChunk,
  cudaStream_t stream, int* usedZChunk, int variant)
{
  constexpr int D = kHarrisDefaultVariant;
  switch (radius)
  {
    case 0:
      return launchRadius<T, 0, D>(input, args, zChunk, stream, usedZChunk);
    case 1:
      return launchRadius<T, 1, D>(input, args, zChunk, stream, usedZChunk);
    case 2:
      // The default width: every variant is built (the benchmark compares them).
      return launchVariant<T>(variant < 0 ? D : variant, input, args, zChunk, stream,
        usedZChunk, std::make_integer_sequence<int, kHarrisVariants>());
    case 3:
      return launchRadius<T, 3, D>(input, args, zChunk, stream, usedZChunk);
    default:
      return cudaErrorInvalidValue;
  }
}

template cudaError_t launchHarris<float>(
  const float*, HarrisKernelArgs, int, int, cudaStream_t, int*, int);
template cudaError_t launchHarris<std::uint8_t>(
  const std::uint8_t*, HarrisKernelArgs, int, int, cudaStream_t, int*, int);

} // namespace detail
} // namespace cuda
} // namespace mcv
