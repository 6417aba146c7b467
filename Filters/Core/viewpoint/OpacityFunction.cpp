#include "OpacityFunction.h"
#include "TypedChannel.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <type_traits>
#include <vector>

namespace mcv
{

OpacityFunction OpacityFunction::ramp(double lo, double hi)
{
  OpacityFunction f;
  if (!(hi > lo))
  {
    // A constant channel: everything at or above its value is opaque.
    f.x = { lo };
    f.alpha = { 1.0 };
    return f;
  }
  f.x = { lo, hi };
  f.alpha = { 0.0, 1.0 };
  return f;
}

double OpacityFunction::evaluate(double value) const
{
  if (x.empty())
  {
    return 0.0;
  }
  if (value <= x.front())
  {
    // Below a single-node function (constant channel) nothing is opaque.
    return x.size() == 1 && value < x.front() ? 0.0 : alpha.front();
  }
  if (value >= x.back())
  {
    return alpha.back();
  }
  const auto upper = std::upper_bound(x.begin(), x.end(), value);
  const std::size_t i = static_cast<std::size_t>(upper - x.begin());
  const double t = (value - x[i - 1]) / (x[i] - x[i - 1]);
  return alpha[i - 1] + t * (alpha[i] - alpha[i - 1]);
}

namespace
{

template <typename T>
constexpr bool hasSmallRange = std::is_integral<T>::value && sizeof(T) <= 2;

} // namespace

std::pair<double, double> finiteRange(const ChannelView& channel, std::size_t count)
{
  double lo = std::numeric_limits<double>::infinity();
  double hi = -std::numeric_limits<double>::infinity();
  withTypedData(channel, [&](auto data) {
    const std::int64_t n = static_cast<std::int64_t>(count);
    const int stride = channel.numComponents, offset = channel.component;
#pragma omp parallel for reduction(min : lo) reduction(max : hi)
    for (std::int64_t v = 0; v < n; ++v)
    {
      const double value = static_cast<double>(data[v * stride + offset]);
      if (std::isfinite(value))
      {
        lo = std::min(lo, value);
        hi = std::max(hi, value);
      }
    }
  });
  return { lo, hi };
}

std::size_t accumulateOpacity(
  const ChannelView& channel, std::size_t count, const OpacityFunction& f, float* opacity)
{
  std::size_t nonFinite = 0;
  withTypedData(channel, [&](auto data) {
    using T = std::remove_const_t<std::remove_pointer_t<decltype(data)>>;
    const std::int64_t n = static_cast<std::int64_t>(count);
    const int stride = channel.numComponents, offset = channel.component;
    if constexpr (hasSmallRange<T>)
    {
      // 8/16-bit scalars: one table lookup per voxel instead of a search.
      const std::int64_t lowest = std::numeric_limits<T>::lowest();
      std::vector<float> table(static_cast<std::size_t>(std::numeric_limits<T>::max() - lowest + 1));
      for (std::size_t i = 0; i < table.size(); ++i)
      {
        table[i] = static_cast<float>(f.evaluate(static_cast<double>(lowest + std::int64_t(i))));
      }
#pragma omp parallel for
      for (std::int64_t v = 0; v < n; ++v)
      {
        const float a = table[static_cast<std::size_t>(data[v * stride + offset] - lowest)];
        opacity[v] = std::max(opacity[v], a);
      }
    }
    else
    {
      std::size_t bad = 0;
#pragma omp parallel for reduction(+ : bad)
      for (std::int64_t v = 0; v < n; ++v)
      {
        const double value = static_cast<double>(data[v * stride + offset]);
        if (!std::isfinite(value))
        {
          ++bad; // NaN/Inf voxels stay transparent
          continue;
        }
        opacity[v] = std::max(opacity[v], static_cast<float>(f.evaluate(value)));
      }
      nonFinite = bad;
    }
  });
  return nonFinite;
}

namespace
{
// How many voxels the process owns (block indices, x fastest) satisfy `test`.
template <class Test>
std::size_t countOwned(const ImageGrid& block, const GridPiece& piece, Test test)
{
  const std::size_t dx = static_cast<std::size_t>(block.dims[0]);
  const std::size_t dy = static_cast<std::size_t>(block.dims[1]);
  std::size_t total = 0;
#pragma omp parallel for reduction(+ : total) schedule(static)
  for (int k = piece.ownedLo[2]; k <= piece.ownedHi[2]; ++k)
  {
    for (int j = piece.ownedLo[1]; j <= piece.ownedHi[1]; ++j)
    {
      const std::size_t row = (static_cast<std::size_t>(k) * dy + j) * dx;
      for (int i = piece.ownedLo[0]; i <= piece.ownedHi[0]; ++i)
      {
        total += test(row + i) ? 1 : 0;
      }
    }
  }
  return total;
}
} // namespace

std::size_t countNonFiniteVoxels(
  const std::vector<ChannelView>& channels, const ImageGrid& block, const GridPiece& piece)
{
  const std::size_t count = block.voxelCount();
  std::vector<unsigned char> bad;
  for (const ChannelView& channel : channels)
  {
    withTypedData(channel, [&](auto data) {
      using T = std::remove_const_t<std::remove_pointer_t<decltype(data)>>;
      if constexpr (std::is_floating_point<T>::value)
      {
        bad.resize(count, 0);
        const std::int64_t n = static_cast<std::int64_t>(count);
        const int stride = channel.numComponents, offset = channel.component;
#pragma omp parallel for schedule(static)
        for (std::int64_t v = 0; v < n; ++v)
        {
          bad[static_cast<std::size_t>(v)] |= !std::isfinite(data[v * stride + offset]);
        }
      }
    });
  }
  if (bad.empty())
  {
    return 0;
  }
  return countOwned(block, piece, [&](std::size_t v) { return bad[v] != 0; });
}

std::size_t countOwnedAtLeast(
  const float* opacity, const ImageGrid& block, const GridPiece& piece, float threshold)
{
  return countOwned(block, piece, [&](std::size_t v) { return opacity[v] >= threshold; });
}

namespace
{
// The vertices of the 2D convex hull of one slice's row ends (points (i, j, k) of one k,
// in j then i order), in place: Andrew's monotone chain on (j, i), collinear points left
// out. The slice's other ends lie inside that hull, so no direction reaches further there.
void keepSliceHull(std::vector<std::array<int, 3>>& ends)
{
  if (ends.size() < 3)
  {
    return;
  }
  auto turn = [](const std::array<int, 3>& o, const std::array<int, 3>& a, const std::array<int, 3>& b) {
    return static_cast<long long>(a[1] - o[1]) * (b[0] - o[0]) -
      static_cast<long long>(a[0] - o[0]) * (b[1] - o[1]);
  };
  std::vector<std::array<int, 3>> hull(2 * ends.size());
  std::size_t h = 0;
  for (std::size_t p = 0; p < ends.size(); ++p) // lower chain
  {
    while (h >= 2 && turn(hull[h - 2], hull[h - 1], ends[p]) <= 0)
    {
      --h;
    }
    hull[h++] = ends[p];
  }
  for (std::size_t p = ends.size() - 1, lower = h + 1; p-- > 0;) // upper chain
  {
    while (h >= lower && turn(hull[h - 2], hull[h - 1], ends[p]) <= 0)
    {
      --h;
    }
    hull[h++] = ends[p];
  }
  hull.resize(h - 1); // the last point is the first again
  ends.swap(hull);
}
} // namespace

std::vector<std::array<int, 3>> ownedHullCandidatesAtLeast(
  const float* opacity, const ImageGrid& block, const GridPiece& piece, float threshold)
{
  const std::size_t dx = static_cast<std::size_t>(block.dims[0]);
  const std::size_t dy = static_cast<std::size_t>(block.dims[1]);
  const int k0 = piece.ownedLo[2], slices = std::max(0, piece.ownedHi[2] - k0 + 1);
  std::vector<std::vector<std::array<int, 3>>> perSlice(static_cast<std::size_t>(slices));
#pragma omp parallel for schedule(static)
  for (int s = 0; s < slices; ++s)
  {
    const int k = k0 + s;
    for (int j = piece.ownedLo[1]; j <= piece.ownedHi[1]; ++j)
    {
      const float* row = opacity + (static_cast<std::size_t>(k) * dy + j) * dx;
      int first = -1, last = -1;
      for (int i = piece.ownedLo[0]; i <= piece.ownedHi[0]; ++i)
      {
        if (row[i] >= threshold)
        {
          first = first < 0 ? i : first;
          last = i;
        }
      }
      if (first >= 0)
      {
        perSlice[static_cast<std::size_t>(s)].push_back({ first, j, k });
        if (last != first)
        {
          perSlice[static_cast<std::size_t>(s)].push_back({ last, j, k });
        }
      }
    }
    keepSliceHull(perSlice[static_cast<std::size_t>(s)]);
  }
  std::vector<std::array<int, 3>> ends;
  for (const auto& slice : perSlice)
  {
    ends.insert(ends.end(), slice.begin(), slice.end());
  }
  return ends;
}

} // namespace mcv
