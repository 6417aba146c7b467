// The real brain (BrainFeatures.h: loadBrain) made larger or smaller for the fused-reduction
// benchmarks, its three channels as float32 in memory:
//   upsampleBrain  trilinear resampling by a factor F along each axis over the input's
//                  bounds, as ParaView's ResampleToImage(UseInputBounds=1,
//                  SamplingDimensions = round(F * dims)) does in benchmark_fused.py and the
//                  main job's --upsample: new content between the old voxels, so runs of
//                  equal voxels grow with F (the placement searches each run once);
//   tileBrain      periodic tiling (voxel (i, j, k) is the brain's (i mod nx, j mod ny,
//                  k mod nz)): the brain's content repeated, its runs as they are.
// Header-only; the loops are OpenMP-parallel where the target links OpenMP.
#pragma once

#include "ChannelView.h"
#include "DimensionReduction.h"
#include "ImageGrid.h"
#include "TestVolumes.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <vector>

namespace mcv
{
namespace testing
{

struct ScaledChannels
{
  ImageGrid grid;
  std::vector<std::vector<float>> channels;
  std::vector<ChannelView> views() const
  {
    std::vector<ChannelView> v;
    for (const auto& c : channels)
    {
      ChannelView cv;
      cv.data = c.data();
      cv.type = ScalarType::Float32;
      v.push_back(cv);
    }
    return v;
  }
};

// ResampleToImage's sampling dimensions for factor F: round(F * dims), at least 1.
inline std::array<int, 3> scaledDims(const ImageGrid& g, double factor)
{
  std::array<int, 3> d{};
  for (int a = 0; a < 3; ++a)
    d[a] = std::max(1, static_cast<int>(std::lround(g.dims[a] * factor)));
  return d;
}

// The channels tiled periodically to `dims` (spacing and origin kept).
inline ScaledChannels tileBrain(const std::vector<Volume>& brain, std::array<int, 3> dims)
{
  const ImageGrid& g = brain[0].grid;
  ScaledChannels t;
  t.grid = g;
  t.grid.dims = dims;
  const std::size_t n = t.grid.voxelCount();
  const int nx = dims[0], ny = dims[1], nz = dims[2];
  for (const Volume& v : brain)
  {
    std::vector<float> c(n);
#pragma omp parallel for schedule(static)
    for (int k = 0; k < nz; ++k)
      for (int j = 0; j < ny; ++j)
      {
        const float* src = v.values.data() + (static_cast<std::size_t>(k % g.dims[2]) * g.dims[1] + j % g.dims[1]) * g.dims[0];
        float* dst = c.data() + (static_cast<std::size_t>(k) * ny + j) * nx;
        for (int i = 0; i < nx; ++i)
          dst[i] = src[i % g.dims[0]];
      }
    t.channels.push_back(std::move(c));
  }
  return t;
}

// Tiled to at least `voxels`: each axis scaled by cbrt(voxels / brain voxels), rounded up.
inline ScaledChannels tileBrain(const std::vector<Volume>& brain, double voxels)
{
  const ImageGrid& g = brain[0].grid;
  const double s = std::cbrt(voxels / static_cast<double>(g.voxelCount()));
  std::array<int, 3> dims{};
  for (int a = 0; a < 3; ++a)
    dims[a] = static_cast<int>(std::ceil(g.dims[a] * s));
  return tileBrain(brain, dims);
}

// Trilinear resampling to round(F * dims) samples spread evenly over the input's bounds
// (first and last samples on the first and last voxel centres, so the spacing becomes
// spacing * (d - 1) / (n - 1)); a single sample along an axis lies on the first voxel.
inline ScaledChannels upsampleBrain(const std::vector<Volume>& brain, double factor)
{
  const ImageGrid& g = brain[0].grid;
  ScaledChannels t;
  t.grid = g;
  t.grid.dims = scaledDims(g, factor);
  // Per axis and output index: the lower input voxel and the weight of the upper one.
  std::array<std::vector<int>, 3> lo;
  std::array<std::vector<double>, 3> w;
  for (int a = 0; a < 3; ++a)
  {
    const int d = g.dims[a], n = t.grid.dims[a];
    const double step = n > 1 ? static_cast<double>(d - 1) / (n - 1) : 0.0;
    t.grid.spacing[a] = n > 1 && d > 1 ? g.spacing[a] * step : g.spacing[a];
    for (int i = 0; i < n; ++i)
    {
      const double x = i * step;
      const int i0 = std::min(static_cast<int>(x), std::max(d - 2, 0));
      lo[a].push_back(i0);
      w[a].push_back(d > 1 ? x - i0 : 0.0);
    }
  }
  const int nx = t.grid.dims[0], ny = t.grid.dims[1], nz = t.grid.dims[2];
  const std::size_t sx = 1, sy = static_cast<std::size_t>(g.dims[0]),
                    sz = static_cast<std::size_t>(g.dims[0]) * static_cast<std::size_t>(g.dims[1]);
  // Neighbour offsets along an axis of one voxel (0 when the input is one voxel thick there).
  const std::size_t ox = g.dims[0] > 1 ? sx : 0, oy = g.dims[1] > 1 ? sy : 0, oz = g.dims[2] > 1 ? sz : 0;
  for (const Volume& v : brain)
  {
    std::vector<float> c(t.grid.voxelCount());
    const float* in = v.values.data();
#pragma omp parallel for schedule(static)
    for (int k = 0; k < nz; ++k)
      for (int j = 0; j < ny; ++j)
      {
        const double wz = w[2][k], wy = w[1][j];
        const std::size_t row = lo[2][k] * sz + lo[1][j] * sy;
        float* dst = c.data() + (static_cast<std::size_t>(k) * ny + j) * nx;
        for (int i = 0; i < nx; ++i)
        {
          const double wx = w[0][i];
          const float* p = in + row + lo[0][i];
          const double y0 = (1 - wx) * p[0] + wx * p[ox];
          const double y1 = (1 - wx) * p[oy] + wx * p[oy + ox];
          const double y2 = (1 - wx) * p[oz] + wx * p[oz + ox];
          const double y3 = (1 - wx) * p[oz + oy] + wx * p[oz + oy + ox];
          const double z0 = (1 - wy) * y0 + wy * y1, z1 = (1 - wy) * y2 + wy * y3;
          dst[i] = static_cast<float>((1 - wz) * z0 + wz * z1);
        }
      }
    t.channels.push_back(std::move(c));
  }
  return t;
}

// The main job's reduction (Examples/transfer_function.py): Isomap, K = 10, L = 500, 3D,
// on a reference sample of `reference` voxels.
inline ReductionOptions mainJobReduction(std::size_t reference, Device device)
{
  ReductionOptions ro;
  ro.method = ReductionMethod::Isomap;
  ro.outputDimension = 3;
  ro.numberOfNeighbors = 10;
  ro.numberOfLandmarks = 500;
  ro.referenceSampleSize = reference;
  ro.device = device;
  return ro;
}

} // namespace testing
} // namespace mcv
