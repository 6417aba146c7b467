// The per-voxel feature kernel shared by the whole-volume GPU path (FeaturesCuda.cu) and the
// fused slab path (FusedPlacementCuda.cu): one thread per voxel, the same float expressions
// as the CPU path (Filters/Core/features/FeatureVectors.cpp, channelFeaturesImpl), rounded
// step by step (__f*_rn: no FMA contraction) so both give the same bits.
#pragma once

#include "../Filters/Core/features/FeatureVectors.h"

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

template <bool Guard>
__global__ void channelFeaturesKernel(const float* __restrict__ f, float* __restrict__ out,
  ChannelParams p)
{
  const std::int64_t nxy = static_cast<std::int64_t>(p.nx) * p.ny;
  for (std::int64_t v = p.vBegin + blockIdx.x * static_cast<std::int64_t>(blockDim.x) + threadIdx.x; v < p.vEnd;
       v += static_cast<std::int64_t>(gridDim.x) * blockDim.x)
  {
    const int k = static_cast<int>(v / nxy);
    const std::int64_t rest = v - k * nxy;
    const int j = static_cast<int>(rest / p.nx);
    const int i = static_cast<int>(rest - static_cast<std::int64_t>(j) * p.nx);
    float* o = out + (v - p.vBegin) * p.cols + p.firstColumn;
    const float c = f[v];
    if (Guard && !isfinite(c))
    {
      for (int t = 0; t < p.perChannel; ++t)
      {
        o[t] = 0.0f;
      }
      continue;
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
