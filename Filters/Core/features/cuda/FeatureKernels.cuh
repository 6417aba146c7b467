// The per-voxel feature kernel shared by the whole-volume GPU path (FeaturesCuda.cu) and the
// fused slab path (FusedPlacementCuda.cu): one thread per voxel, the same float expressions
// as the CPU path (Filters/Core/features/FeatureVectors.cpp, channelFeaturesImpl), rounded
// step by step (__f*_rn: no FMA contraction) so both give the same bits.
#pragma once

#include "FeatureVectors.h"

#include <cstdint>

namespace mcv
{
namespace cuda
{
// Internal to each .cu that includes it (whole-program compilation: every translation unit
// registers its own kernels).
namespace
{

struct ChannelParams
{
  int nx, ny, nz;
  float sx, sy, sz; // 0.5 / spacing
  int intensity, gradient, gradientMagnitude, laplacian, localMean, localVariance;
  int perChannel;
  int cols;
  int firstColumn;
  // Voxels [vBegin, vEnd) of the grid are computed, voxel v into row v - vBegin of out
  // (the whole grid for the whole-volume path; a slab without its ghost slices for the
  // fused path, whose grid is the slab with them).
  std::int64_t vBegin, vEnd;
};

__device__ __forceinline__ int clampIndex(int i, int n)
{
  return i < 0 ? 0 : (i >= n ? n - 1 : i);
}

// One voxel's features of one channel into o[0, perChannel): the same float expressions as
// the CPU path, rounded step by step.
template <bool Guard>
__device__ __forceinline__ void channelFeaturesOf(
  const float* __restrict__ f, const ChannelParams& p, std::int64_t nxy, std::int64_t v, int i, int j, int k, float* o)
{
  const float c = f[v];
  if (Guard && !isfinite(c))
  {
    for (int t = 0; t < p.perChannel; ++t)
    {
      o[t] = 0.0f;
    }
    return;
  }
  auto at = [&](int ii, int jj, int kk) {
    const float x = f[static_cast<std::int64_t>(kk) * nxy + static_cast<std::int64_t>(jj) * p.nx + ii];
    return (!Guard || isfinite(x)) ? x : c;
  };
  const int im = clampIndex(i - 1, p.nx), ip = clampIndex(i + 1, p.nx);
  const int jm = clampIndex(j - 1, p.ny), jp = clampIndex(j + 1, p.ny);
  const int km = clampIndex(k - 1, p.nz), kp = clampIndex(k + 1, p.nz);
  const float xm = at(im, j, k), xp = at(ip, j, k);
  const float ym = at(i, jm, k), yp = at(i, jp, k);
  const float zm = at(i, j, km), zp = at(i, j, kp);
  int col = 0;
  if (p.intensity)
  {
    o[col++] = c;
  }
  if (p.gradient || p.gradientMagnitude)
  {
    const float gx = __fmul_rn(__fsub_rn(xp, xm), p.sx);
    const float gy = __fmul_rn(__fsub_rn(yp, ym), p.sy);
    const float gz = __fmul_rn(__fsub_rn(zp, zm), p.sz);
    if (p.gradient)
    {
      o[col++] = gx;
      o[col++] = gy;
      o[col++] = gz;
    }
    if (p.gradientMagnitude)
    {
      o[col++] = sqrtf(__fadd_rn(__fadd_rn(__fmul_rn(gx, gx), __fmul_rn(gy, gy)), __fmul_rn(gz, gz)));
    }
  }
  if (p.laplacian)
  {
    o[col++] = __fsub_rn(
      __fdiv_rn(__fadd_rn(__fadd_rn(__fadd_rn(xm, xp), __fadd_rn(ym, yp)), __fadd_rn(zm, zp)), 6.0f), c);
  }
  if (p.localMean || p.localVariance)
  {
    const int is[3] = { im, i, ip }, js[3] = { jm, j, jp }, ks[3] = { km, k, kp };
    float vals[27];
    float s = 0.0f;
    int t = 0;
    for (int a = 0; a < 3; ++a)
    {
      for (int b = 0; b < 3; ++b)
      {
        for (int d = 0; d < 3; ++d, ++t)
        {
          vals[t] = at(is[d], js[b], ks[a]);
          s = __fadd_rn(s, vals[t]);
        }
      }
    }
    const float mean = __fdiv_rn(s, 27.0f);
    if (p.localMean)
    {
      o[col++] = mean;
    }
    if (p.localVariance)
    {
      float s2 = 0.0f;
      for (t = 0; t < 27; ++t)
      {
        const float dv = __fsub_rn(vals[t], mean);
        s2 = __fadd_rn(s2, __fmul_rn(dv, dv));
      }
      o[col++] = __fdiv_rn(s2, 27.0f);
    }
  }
}

// Threads per block of channelFeaturesKernel (its launches use this), and the most features
// one channel gives (FeatureSelection::perChannel: intensity, gradient x3, its magnitude,
// Laplacian, local mean and variance).
constexpr int kFeatureThreads = 256;
constexpr int kMaxFeaturesPerChannel = 8;

// A voxel's features are staged in shared memory and the block writes its rows' columns
// together: written straight from each thread, the stores of a warp hit 32 rows (32 sectors
// per store, one float used in each); staged, each store covers whole 32-byte column runs of
// 4 rows. The grid index arithmetic is 32-bit when the grid allows (64-bit division costs
// several times more).
template <bool Guard>
__global__ void __launch_bounds__(kFeatureThreads) channelFeaturesKernel(
  const float* __restrict__ f, float* __restrict__ out, ChannelParams p)
{
  constexpr int kStride = kMaxFeaturesPerChannel + 1; // odd: no bank conflicts
  __shared__ float stage[kFeatureThreads * kStride];
  const std::int64_t nxy = static_cast<std::int64_t>(p.nx) * p.ny;
  const bool small = nxy * p.nz < (std::int64_t(1) << 31);
  const std::int64_t step = static_cast<std::int64_t>(gridDim.x) * kFeatureThreads;
  for (std::int64_t first = p.vBegin + static_cast<std::int64_t>(blockIdx.x) * kFeatureThreads; first < p.vEnd;
       first += step) // the same trips for every thread of the block (barriers inside)
  {
    const std::int64_t v = first + threadIdx.x;
    float* o = stage + threadIdx.x * kStride;
    if (v < p.vEnd)
    {
      int i, j, k;
      if (small)
      {
        const unsigned u = static_cast<unsigned>(v), plane = static_cast<unsigned>(nxy);
        k = static_cast<int>(u / plane);
        const unsigned rest = u - static_cast<unsigned>(k) * plane;
        j = static_cast<int>(rest / static_cast<unsigned>(p.nx));
        i = static_cast<int>(rest - static_cast<unsigned>(j) * static_cast<unsigned>(p.nx));
      }
      else
      {
        k = static_cast<int>(v / nxy);
        const std::int64_t rest = v - k * nxy;
        j = static_cast<int>(rest / p.nx);
        i = static_cast<int>(rest - static_cast<std::int64_t>(j) * p.nx);
      }
      channelFeaturesOf<Guard>(f, p, nxy, v, i, j, k, o);
    }
    __syncthreads();
    // Row r of this block's voxels, column t: consecutive threads, consecutive columns.
    const int rows = static_cast<int>(min(static_cast<std::int64_t>(kFeatureThreads), p.vEnd - first));
    for (int e = threadIdx.x; e < rows * p.perChannel; e += kFeatureThreads)
    {
      const int r = e / p.perChannel, t = e - r * p.perChannel;
      out[(first + r - p.vBegin) * p.cols + p.firstColumn + t] = stage[r * kStride + t];
    }
    __syncthreads(); // the stage is refilled next trip
  }
}

inline ChannelParams channelParams(const ImageGrid& grid, const FeatureSelection& sel, int cols, int firstColumn)
{
  ChannelParams p;
  p.nx = grid.dims[0];
  p.ny = grid.dims[1];
  p.nz = grid.dims[2];
  p.sx = static_cast<float>(0.5 / grid.spacing[0]);
  p.sy = static_cast<float>(0.5 / grid.spacing[1]);
  p.sz = static_cast<float>(0.5 / grid.spacing[2]);
  p.intensity = sel.intensity;
  p.gradient = sel.gradient;
  p.gradientMagnitude = sel.gradientMagnitude;
  p.laplacian = sel.laplacian;
  p.localMean = sel.localMean;
  p.localVariance = sel.localVariance;
  p.perChannel = sel.perChannel();
  p.cols = cols;
  p.firstColumn = firstColumn;
  p.vBegin = 0;
  p.vEnd = static_cast<std::int64_t>(grid.voxelCount());
  return p;
}

} // namespace
} // namespace cuda
} // namespace mcv
