#include "ReferenceHarrisCPU.h"

#include <omp.h>

#include <queue>
#include <utility>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <vector>

// The former computeHarrisResponseCPU and selectTopResponsesCPU, unchanged but for their
// names (see the header).

namespace mcv
{
namespace benchmark
{
namespace
{

constexpr int Channels = 6; // xx, xy, xz, yy, yz, zz

inline int clampIndex(int i, int n)
{
  return i < 0 ? 0 : (i >= n ? n - 1 : i);
}

// Response from the smoothed structure tensor. `plane` < 0: 3D form; otherwise the axis of
// size 1 whose two complementary axes span the slice (2D form det - k tr^2).
inline float harrisFromTensor(const float m[Channels], float k, int plane)
{
  const float xx = m[0], xy = m[1], xz = m[2], yy = m[3], yz = m[4], zz = m[5];
  if (plane < 0)
  {
    const float det = xx * (yy * zz - yz * yz) - xy * (xy * zz - yz * xz) + xz * (xy * yz - yy * xz);
    const float tr = xx + yy + zz;
    return det - k * tr * tr * tr;
  }
  float a, b, c; // the in-plane 2x2 block [a b; b c]
  if (plane == 2)
  {
    a = xx, b = xy, c = yy;
  }
  else if (plane == 1)
  {
    a = xx, b = xz, c = zz;
  }
  else
  {
    a = yy, b = yz, c = zz;
  }
  const float tr = a + c;
  return (a * c - b * b) - k * tr * tr;
}

class SliceSmoother
{
public:
  SliceSmoother(const float* opacity, const ImageGrid& grid, const std::vector<float>& taps)
    : Opacity(opacity)
    , Nx(grid.dims[0])
    , Ny(grid.dims[1])
    , Nz(grid.dims[2])
    , Taps(taps)
    , Radius(static_cast<int>(taps.size()) / 2)
    , Scale{ static_cast<float>(0.5 / grid.spacing[0]), static_cast<float>(0.5 / grid.spacing[1]),
      static_cast<float>(0.5 / grid.spacing[2]) }
    , Products(static_cast<std::size_t>(Channels) * Nx * Ny)
    , PaddedRow(static_cast<std::size_t>(Nx + 2 * Radius))
    , RowSmoothed(static_cast<std::size_t>(Channels) * Nx * Ny)
  {
  }

  // Six gradient products of slice z, smoothed along x then y, into `out`
  // (channel-major: out[c * Nx * Ny + j * Nx + i]).
  void smoothSlice(int z, float* out)
  {
    computeProducts(z);
    const std::size_t sliceSize = static_cast<std::size_t>(Nx) * Ny;
    const int width = static_cast<int>(Taps.size());
    for (int c = 0; c < Channels; ++c)
    {
      const float* in = Products.data() + c * sliceSize;
      float* rows = RowSmoothed.data() + c * sliceSize;
      for (int j = 0; j < Ny; ++j)
      {
        const float* row = in + static_cast<std::size_t>(j) * Nx;
        float* pad = PaddedRow.data();
        std::fill(pad, pad + Radius, row[0]);
        std::copy(row, row + Nx, pad + Radius);
        std::fill(pad + Radius + Nx, pad + 2 * Radius + Nx, row[Nx - 1]);
        float* dst = rows + static_cast<std::size_t>(j) * Nx;
        for (int i = 0; i < Nx; ++i)
        {
          float s = 0.f;
          for (int t = 0; t < width; ++t)
          {
            s += Taps[t] * pad[i + t];
          }
          dst[i] = s;
        }
      }
      float* cols = out + c * sliceSize;
      for (int j = 0; j < Ny; ++j)
      {
        float* dst = cols + static_cast<std::size_t>(j) * Nx;
        std::fill(dst, dst + Nx, 0.f);
        for (int t = 0; t < width; ++t)
        {
          const float* src = rows + static_cast<std::size_t>(clampIndex(j - Radius + t, Ny)) * Nx;
          const float w = Taps[t];
          for (int i = 0; i < Nx; ++i)
          {
            dst[i] += w * src[i];
          }
        }
      }
    }
  }

private:
  void computeProducts(int z)
  {
    const std::size_t sliceSize = static_cast<std::size_t>(Nx) * Ny;
    const float* cur = Opacity + static_cast<std::size_t>(z) * sliceSize;
    const float* below = Opacity + static_cast<std::size_t>(clampIndex(z - 1, Nz)) * sliceSize;
    const float* above = Opacity + static_cast<std::size_t>(clampIndex(z + 1, Nz)) * sliceSize;
    float* p = Products.data();
    for (int j = 0; j < Ny; ++j)
    {
      const std::size_t row = static_cast<std::size_t>(j) * Nx;
      const float* prevRow = cur + static_cast<std::size_t>(clampIndex(j - 1, Ny)) * Nx;
      const float* nextRow = cur + static_cast<std::size_t>(clampIndex(j + 1, Ny)) * Nx;
      for (int i = 0; i < Nx; ++i)
      {
        const int im = i > 0 ? i - 1 : 0, ip = i + 1 < Nx ? i + 1 : Nx - 1;
        const float gx = (cur[row + ip] - cur[row + im]) * Scale[0];
        const float gy = (nextRow[i] - prevRow[i]) * Scale[1];
        const float gz = (above[row + i] - below[row + i]) * Scale[2];
        const std::size_t v = row + i;
        p[0 * sliceSize + v] = gx * gx;
        p[1 * sliceSize + v] = gx * gy;
        p[2 * sliceSize + v] = gx * gz;
        p[3 * sliceSize + v] = gy * gy;
        p[4 * sliceSize + v] = gy * gz;
        p[5 * sliceSize + v] = gz * gz;
      }
    }
  }

  const float* Opacity;
  const int Nx, Ny, Nz;
  const std::vector<float>& Taps;
  const int Radius;
  const float Scale[3];
  std::vector<float> Products;
  std::vector<float> PaddedRow;
  std::vector<float> RowSmoothed;
};

} // namespace

void referenceHarrisResponseCPU(
  const float* opacity, const ImageGrid& grid, const HarrisParameters& params, float* response)
{
  const int nx = grid.dims[0], ny = grid.dims[1], nz = grid.dims[2];
  std::vector<float> taps(static_cast<std::size_t>(params.kernelWidth));
  gaussianTaps(params, taps.data());
  const int width = params.kernelWidth, radius = width / 2;
  const float k = static_cast<float>(params.k);
  int plane = -1;
  if (grid.extendedAxes() == 2)
  {
    plane = nx == 1 ? 0 : (ny == 1 ? 1 : 2);
  }
  const std::size_t sliceSize = static_cast<std::size_t>(nx) * ny;

#pragma omp parallel
  {
    // Each thread owns a contiguous run of output slices and the ring of smoothed slices
    // it needs; the 2*radius halo slices at the ends of a run are computed twice.
    const int threads = omp_get_num_threads(), id = omp_get_thread_num();
    const int z0 = static_cast<int>(static_cast<std::int64_t>(nz) * id / threads);
    const int z1 = static_cast<int>(static_cast<std::int64_t>(nz) * (id + 1) / threads);
    if (z0 < z1)
    {
      SliceSmoother smoother(opacity, grid, taps);
      std::vector<float> ring(static_cast<std::size_t>(width) * Channels * sliceSize);
      std::vector<int> ringSlice(static_cast<std::size_t>(width), -1);
      std::vector<float> tensorRow(static_cast<std::size_t>(Channels) * nx);
      auto smoothed = [&](int zClamped) -> const float* {
        const int slot = zClamped % width;
        float* data = ring.data() + static_cast<std::size_t>(slot) * Channels * sliceSize;
        if (ringSlice[slot] != zClamped)
        {
          smoother.smoothSlice(zClamped, data);
          ringSlice[slot] = zClamped;
        }
        return data;
      };
      std::vector<const float*> window(static_cast<std::size_t>(width));
      for (int z = z0; z < z1; ++z)
      {
        for (int t = 0; t < width; ++t)
        {
          window[t] = smoothed(clampIndex(z - radius + t, nz));
        }
        for (int j = 0; j < ny; ++j)
        {
          const std::size_t row = static_cast<std::size_t>(j) * nx;
          for (int c = 0; c < Channels; ++c)
          {
            float* dst = tensorRow.data() + static_cast<std::size_t>(c) * nx;
            std::fill(dst, dst + nx, 0.f);
            for (int t = 0; t < width; ++t)
            {
              const float* src = window[t] + c * sliceSize + row;
              const float w = taps[t];
              for (int i = 0; i < nx; ++i)
              {
                dst[i] += w * src[i];
              }
            }
          }
          float* out = response + static_cast<std::size_t>(z) * sliceSize + row;
          for (int i = 0; i < nx; ++i)
          {
            const float m[Channels] = { tensorRow[i], tensorRow[nx + i], tensorRow[2 * nx + i],
              tensorRow[3 * nx + i], tensorRow[4 * nx + i], tensorRow[5 * nx + i] };
            out[i] = harrisFromTensor(m, k, plane);
          }
        }
      }
    }
  }
}

// The former selection: one bounded std::priority_queue per thread, every voxel tested.
namespace
{

using Candidate = std::pair<float, std::int64_t>; // (response, linear index)

// Strict "ranks before": higher response first, then lower index (unique order under ties).
struct RanksBefore
{
  bool operator()(const Candidate& a, const Candidate& b) const
  {
    return a.first > b.first || (a.first == b.first && a.second < b.second);
  }
};

// The `keep` candidates that rank first, in rank order.
InterestPoints strongest(std::vector<Candidate>& merged, std::size_t keep)
{
  InterestPoints result;
  const std::size_t taken = std::min(keep, merged.size());
  std::partial_sort(merged.begin(), merged.begin() + static_cast<std::ptrdiff_t>(taken),
    merged.end(), RanksBefore());
  result.indices.reserve(taken);
  result.scores.reserve(taken);
  for (std::size_t i = 0; i < taken; ++i)
  {
    result.scores.push_back(merged[i].first);
    result.indices.push_back(merged[i].second);
  }
  return result;
}

} // namespace

InterestPoints referenceSelectTopResponsesCPU(const float* response, std::size_t count, int N)
{
  if (N <= 0 || count == 0)
  {
    return InterestPoints();
  }
  const std::size_t keep = static_cast<std::size_t>(N);
  std::vector<std::vector<Candidate>> perThread;

#pragma omp parallel
  {
#pragma omp single
    perThread.resize(static_cast<std::size_t>(omp_get_num_threads()));

    // A bounded heap per thread whose top is the weakest kept candidate (as in the
    // dissertation's filtering step); once full, most voxels are rejected by one compare.
    std::priority_queue<Candidate, std::vector<Candidate>, RanksBefore> heap;
    const std::int64_t n = static_cast<std::int64_t>(count);
#pragma omp for schedule(static) nowait
    for (std::int64_t v = 0; v < n; ++v)
    {
      const float r = response[v];
      if (!(r > 0.f) || !std::isfinite(r))
      {
        continue;
      }
      if (heap.size() < keep)
      {
        heap.emplace(r, v);
      }
      else if (RanksBefore()(Candidate(r, v), heap.top()))
      {
        heap.pop();
        heap.emplace(r, v);
      }
    }
    std::vector<Candidate>& mine = perThread[static_cast<std::size_t>(omp_get_thread_num())];
    mine.reserve(heap.size());
    while (!heap.empty())
    {
      mine.push_back(heap.top());
      heap.pop();
    }
  }

  std::vector<Candidate> merged;
  for (const auto& part : perThread)
  {
    merged.insert(merged.end(), part.begin(), part.end());
  }
  return strongest(merged, keep);
}

} // namespace benchmark
} // namespace mcv
