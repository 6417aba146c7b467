#include "HarrisBound.cuh"

#include <cub/block/block_scan.cuh>

#include <cstdint>
#include <type_traits>

namespace mcv
{
namespace cuda
{
namespace detail
{
namespace
{

constexpr int kGateThreads = 1024; // one block; two of the 2048 bins per thread

__device__ __forceinline__ int clampi(int v, int lo, int hi)
{
  return min(max(v, lo), hi);
}

// One block per (xy tile, run of slices), the Harris kernel's tile; each thread owns two
// rows of a column, as there. Per input slice: the gradients as the Harris kernel forms
// them (clamped neighbours, the same differences and scales), |g|^2 on the clamped product
// tile, the x and y Gaussian passes, and the tile's largest value X of that slice. The z
// pass is not formed: the trace of an output slice z is a weighted mean (the taps sum to
// 1) of the xy-smoothed values of slices z - R .. z + R, so it is at most their largest X
// (blockBoundsKernel takes the maximum over those slices). The next input slice is loaded
// into registers while the current one is processed.
template <typename T, int R>
__global__ void __launch_bounds__(kHarrisThreads)
  traceBoundKernel(const T* __restrict__ in, const HarrisKernelArgs a, int zChunk, unsigned* sliceMax)
{
  constexpr int TX = kHarrisTileX, TY = kHarrisTileY, W = 2 * R + 1;
  constexpr int IW = TX + 2 * R + 2, IH = TY + 2 * R + 2, IS = IW * IH;
  constexpr int PW = TX + 2 * R, PH = TY + 2 * R;
  constexpr int LOADS = (IS + kHarrisThreads - 1) / kHarrisThreads;
  constexpr int PRODS = (PH * PW + kHarrisThreads - 1) / kHarrisThreads;
  constexpr int XOUTS = (PH * TX + kHarrisThreads - 1) / kHarrisThreads;
  using Raw = std::conditional_t<std::is_same_v<T, float>, float, unsigned>;
  __shared__ float sIn[3][IS];
  __shared__ float sP[PH * PW];
  __shared__ float sX[PH * TX];

  const int tid = threadIdx.x, lane = tid & 31, warp = tid >> 5;
  const int nx = a.nx, ny = a.ny, nz = a.nz;
  const int x0 = blockIdx.x * TX, y0 = blockIdx.y * TY;
  const int zb = blockIdx.z * zChunk, ze = min(zb + zChunk, nz);
  const std::size_t plane = static_cast<std::size_t>(nx) * ny;

  // Per thread, fixed for every slice: its input elements' sources, its product positions'
  // input-tile offsets, its x-pass outputs' product-tile offsets (-1: none).
  int inOff[LOADS], prodAt[PRODS], xFrom[XOUTS];
#pragma unroll
  for (int i = 0; i < LOADS; ++i)
  {
    const int e = tid + i * kHarrisThreads;
    const int ly = e / IW, lx = e - ly * IW;
    inOff[i] = e < IS
      ? clampi(y0 - R - 1 + ly, 0, ny - 1) * nx + clampi(x0 - R - 1 + lx, 0, nx - 1)
      : -1;
  }
#pragma unroll
  for (int i = 0; i < PRODS; ++i)
  {
    const int e = tid + i * kHarrisThreads;
    const int py = e / PW, px = e - py * PW;
    const int bx = clampi(x0 - R + px, 0, nx - 1), by = clampi(y0 - R + py, 0, ny - 1);
    prodAt[i] = e < PH * PW ? (by - (y0 - R - 1)) * IW + (bx - (x0 - R - 1)) : -1;
  }
#pragma unroll
  for (int i = 0; i < XOUTS; ++i)
  {
    const int e = tid + i * kHarrisThreads;
    const int py = e / TX, ox = e - py * TX;
    xFrom[i] = e < PH * TX ? py * PW + ox : -1;
  }
  Raw pre[LOADS];
  auto fetch = [&](int q) {
    const T* src = in + static_cast<std::size_t>(q) * plane;
#pragma unroll
    for (int i = 0; i < LOADS; ++i)
    {
      pre[i] = inOff[i] >= 0 ? static_cast<Raw>(__ldg(src + inOff[i])) : Raw(0);
    }
  };
  auto store = [&](int q) {
    float* dst = sIn[q % 3];
#pragma unroll
    for (int i = 0; i < LOADS; ++i)
    {
      if (inOff[i] >= 0)
      {
        dst[tid + i * kHarrisThreads] = static_cast<float>(pre[i]);
      }
    }
  };

  // Slices zb - 1 .. zb (clamped) stored, zb + 1 fetched; then per slice cz: store cz + 1,
  // fetch cz + 2, barrier, products of cz (reading cz - 1 .. cz + 1), x pass, y pass. The
  // slot cz + 1 takes held cz - 2, last read by the products two barriers before.
  const bool inside0 = x0 + lane < nx && y0 + 2 * warp < ny;
  const bool inside1 = x0 + lane < nx && y0 + 2 * warp + 1 < ny;
  const unsigned tile = blockIdx.y * gridDim.x + blockIdx.x;
  const unsigned tiles = gridDim.x * gridDim.y;
  for (int q = max(zb - 1, 0); q <= zb; ++q)
  {
    fetch(q);
    store(q);
  }
  int next = zb + 1; // the slice in pre (when < nz)
  if (next < nz)
  {
    fetch(next);
  }
  for (int cz = zb; cz < ze; ++cz)
  {
    if (next < nz && next == cz + 1)
    {
      store(next);
      ++next;
      if (next < nz)
      {
        fetch(next);
      }
    }
    __syncthreads();
    const float* sc = sIn[cz % 3];
    const float* sm = sIn[max(cz - 1, 0) % 3];
    const float* sp = sIn[min(cz + 1, nz - 1) % 3];
#pragma unroll
    for (int i = 0; i < PRODS; ++i)
    {
      const int c = prodAt[i];
      if (c >= 0)
      {
        const float gx = (sc[c + 1] - sc[c - 1]) * a.scaleX;
        const float gy = (sc[c + IW] - sc[c - IW]) * a.scaleY;
        const float gz = (sp[c] - sm[c]) * a.scaleZ;
        sP[tid + i * kHarrisThreads] = fmaf(gz, gz, fmaf(gy, gy, gx * gx));
      }
    }
    __syncthreads();
#pragma unroll
    for (int i = 0; i < XOUTS; ++i)
    {
      const int f = xFrom[i];
      if (f >= 0)
      {
        float v = 0.f;
#pragma unroll
        for (int t = 0; t < W; ++t)
        {
          v = fmaf(a.taps[t], sP[f + t], v);
        }
        sX[tid + i * kHarrisThreads] = v;
      }
    }
    __syncthreads();
    float m = 0.f;
#pragma unroll
    for (int r = 0; r < 2; ++r)
    {
      float v = 0.f;
#pragma unroll
      for (int t = 0; t < W; ++t)
      {
        v = fmaf(a.taps[t], sX[(2 * warp + r + t) * TX + lane], v);
      }
      // NaN counts as +Inf (fmaxf would drop it)
      v = v == v ? v : __int_as_float(0x7F800000);
      if (r == 0 ? inside0 : inside1)
      {
        m = fmaxf(m, v);
      }
    }
    unsigned bits = __float_as_uint(m); // m >= 0: its bits order like its value
    for (int o = 16; o > 0; o >>= 1)
    {
      bits = max(bits, __shfl_xor_sync(0xffffffffu, bits, o));
    }
    if (lane == 0 && bits != 0)
    {
      atomicMax(sliceMax + static_cast<std::size_t>(cz) * tiles + tile, bits);
    }
  }
}

// The block's bound: X, the largest xy-smoothed |g|^2 of slices bz zc - R .. (bz + 1) zc +
// R - 1 (clamped), gives R <= tr^3 (1/27 - k) <= X^3 (1/27 - k), with a margin over float
// rounding (relative 1e-3 and 1e-5 X^3: the response's own rounding is ~1e-6 tr^3).
__global__ void blockBoundsKernel(const unsigned* sliceMax, int tilesX, int tilesY, int nz,
  int zChunk, int radius, float k, int blocks, float* blockBound)
{
  const int b = blockIdx.x * blockDim.x + threadIdx.x;
  if (b >= blocks)
  {
    return;
  }
  const int tiles = tilesX * tilesY;
  const int tile = b % tiles, bz = b / tiles;
  unsigned m = 0;
  for (int z = max(bz * zChunk - radius, 0); z < min((bz + 1) * zChunk + radius, nz); ++z)
  {
    m = max(m, sliceMax[static_cast<std::size_t>(z) * tiles + tile]);
  }
  const float x = __uint_as_float(m);
  const float factor = fmaxf(1.0f / 27.0f - k, 0.0f) * 1.001f + 1e-5f;
  blockBound[b] = x * x * x * factor; // +Inf stays +Inf
}

// The bin b of `counts` (kLevel1Bins, in shared memory) such that fewer than `wanted` are
// counted above it and at least `wanted` from it on; -1 if the total is below `wanted`.
// *above gets the count above b. Every thread of the block calls it.
__device__ int crossingBin(const unsigned long long* counts, unsigned long long wanted,
  unsigned long long* above)
{
  using Scan = cub::BlockScan<unsigned long long, kGateThreads>;
  __shared__ typename Scan::TempStorage temp;
  __shared__ int found;
  __shared__ unsigned long long foundAbove;
  const int t = threadIdx.x;
  const int hi = kLevel1Bins - 1 - 2 * t; // this thread: bins hi and hi - 1, from the top
  if (t == 0)
  {
    found = -1;
    foundAbove = 0;
  }
  const unsigned long long mine = counts[hi] + counts[hi - 1];
  unsigned long long before = 0;
  Scan(temp).ExclusiveSum(mine, before);
  __syncthreads();
  if (before < wanted && before + counts[hi] >= wanted)
  {
    found = hi;
    foundAbove = before;
  }
  else if (before + counts[hi] < wanted && before + mine >= wanted)
  {
    found = hi - 1;
    foundAbove = before + counts[hi];
  }
  __syncthreads();
  *above = foundAbove;
  return found;
}

__global__ void __launch_bounds__(kGateThreads)
  phaseGateKernel(const float* blockBound, int blocks, int wanted, float* gateA, float* gateB)
{
  __shared__ unsigned long long counts[kLevel1Bins];
  const int t = threadIdx.x;
  unsigned bits = 0; // theta: 0 takes every block
  unsigned long long above = 0;
  for (int level = 0; level < 2; ++level)
  {
    for (int i = t; i < kLevel1Bins; i += kGateThreads)
    {
      counts[i] = 0;
    }
    __syncthreads();
    // Blocks with equal bounds (many of 0: no gradient) would serialise their shared atomics
    // on one counter: a warp adds each distinct bin once, with its count of lanes.
    for (int base = 0; base < blocks; base += kGateThreads)
    {
      const int b = base + t;
      const unsigned v = b < blocks ? __float_as_uint(blockBound[b]) : 0u;
      const bool counted = b < blocks && (level == 0 || (v >> 21) == (bits >> 21));
      const unsigned bin = level == 0 ? v >> 21 : (v >> 10) & 0x7FFu;
      const unsigned key = counted ? bin : 0xFFFFFFFFu;
      const unsigned same = __match_any_sync(0xffffffffu, key);
      if (counted && (threadIdx.x & 31) == __ffs(same) - 1)
      {
        atomicAdd(&counts[bin], static_cast<unsigned long long>(__popc(same)));
      }
    }
    __syncthreads();
    unsigned long long more = 0;
    const int bin = crossingBin(counts, static_cast<unsigned long long>(wanted) - above, &more);
    if (bin < 0)
    {
      break; // fewer blocks than wanted (level 0): theta 0 takes them all
    }
    bits |= level == 0 ? static_cast<unsigned>(bin) << 21 : static_cast<unsigned>(bin) << 10;
    above += more;
    __syncthreads();
  }
  if (t == 0)
  {
    const float theta = __uint_as_float(bits);
    gateA[0] = theta;
    gateA[1] = __uint_as_float(0x7FC00000u); // NaN: no upper limit
    gateB[1] = theta;
  }
}

__global__ void __launch_bounds__(kGateThreads)
  tauGateKernel(const unsigned long long* hist, int N, float* gateB)
{
  __shared__ unsigned long long counts[kLevel1Bins];
  for (int i = threadIdx.x; i < kLevel1Bins; i += kGateThreads)
  {
    counts[i] = hist[i];
  }
  __syncthreads();
  unsigned long long above = 0;
  const int bin = crossingBin(counts, static_cast<unsigned long long>(N), &above);
  if (threadIdx.x == 0)
  {
    gateB[0] = bin < 0 ? 0.0f : __uint_as_float(static_cast<unsigned>(bin) << 21);
  }
}

template <typename T, int R>
cudaError_t launchBoundRadius(
  const T* input, const HarrisKernelArgs& a, unsigned* sliceMax, cudaStream_t stream)
{
  // Many small blocks: runs of 32 slices (each reads one slice more on either side).
  const int zChunk = min(32, a.nz);
  const dim3 grid((a.nx + kHarrisTileX - 1) / kHarrisTileX,
    (a.ny + kHarrisTileY - 1) / kHarrisTileY, (a.nz + zChunk - 1) / zChunk);
  if (grid.y > 65535u || grid.z > 65535u)
  {
    return cudaErrorInvalidConfiguration;
  }
  traceBoundKernel<T, R><<<grid, kHarrisThreads, 0, stream>>>(input, a, zChunk, sliceMax);
  return cudaGetLastError();
}

} // namespace

template <typename T>
cudaError_t launchTraceBound(
  const T* input, const HarrisKernelArgs& args, int radius, unsigned* sliceMax, cudaStream_t stream)
{
  switch (radius)
  {
    case 0:
      return launchBoundRadius<T, 0>(input, args, sliceMax, stream);
    case 1:
      return launchBoundRadius<T, 1>(input, args, sliceMax, stream);
    case 2:
      return launchBoundRadius<T, 2>(input, args, sliceMax, stream);
    case 3:
      return launchBoundRadius<T, 3>(input, args, sliceMax, stream);
    default:
      return cudaErrorInvalidValue;
  }
}

template cudaError_t launchTraceBound<float>(
  const float*, const HarrisKernelArgs&, int, unsigned*, cudaStream_t);
template cudaError_t launchTraceBound<std::uint8_t>(
  const std::uint8_t*, const HarrisKernelArgs&, int, unsigned*, cudaStream_t);

cudaError_t launchBlockBounds(const unsigned* sliceMax, int tilesX, int tilesY, int nz,
  int zChunk, int radius, float k, float* blockBound, cudaStream_t stream)
{
  const int blocks = tilesX * tilesY * ((nz + zChunk - 1) / zChunk);
  blockBoundsKernel<<<(blocks + 255) / 256, 256, 0, stream>>>(
    sliceMax, tilesX, tilesY, nz, zChunk, radius, k, blocks, blockBound);
  return cudaGetLastError();
}

cudaError_t launchPhaseGate(
  const float* blockBound, int blocks, int wanted, float* gateA, float* gateB, cudaStream_t stream)
{
  phaseGateKernel<<<1, kGateThreads, 0, stream>>>(blockBound, blocks, wanted, gateA, gateB);
  return cudaGetLastError();
}

cudaError_t launchTauGate(const unsigned long long* hist, int N, float* gateB, cudaStream_t stream)
{
  tauGateKernel<<<1, kGateThreads, 0, stream>>>(hist, N, gateB);
  return cudaGetLastError();
}

} // namespace detail
} // namespace cuda
} // namespace mcv
