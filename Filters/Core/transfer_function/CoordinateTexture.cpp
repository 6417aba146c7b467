#include "CoordinateTexture.h"

#include <algorithm>
#include <cmath>

namespace mcv
{

namespace
{
bool drawn(const float* x, int components, const std::uint8_t* mask, std::size_t i)
{
  if (mask && mask[i] == 0)
  {
    return false;
  }
  for (int c = 0; c < components; ++c)
  {
    if (!std::isfinite(x[c]))
    {
      return false;
    }
  }
  return true;
}
} // namespace

void CoordinateRange::Add(
  const float* coordinates, std::size_t count, int components, const std::uint8_t* mask)
{
  // Serial: one pass at data change, never per widget edit; a min/max reduction over a
  // few million voxels is memory-bound either way.
  for (std::size_t i = 0; i < count; ++i)
  {
    const float* x = coordinates + i * components;
    if (!drawn(x, components, mask, i))
    {
      continue;
    }
    for (int c = 0; c < components; ++c)
    {
      if (this->empty || x[c] < this->min[c])
      {
        this->min[c] = x[c];
      }
      if (this->empty || x[c] > this->max[c])
      {
        this->max[c] = x[c];
      }
    }
    this->empty = false;
  }
}

std::size_t quantizeCoordinates(const float* coordinates, std::size_t count, int components,
  const std::uint8_t* mask, const CoordinateRange& range, std::uint16_t* texels)
{
  double scale[3] = { 0, 0, 0 };
  for (int c = 0; c < components; ++c)
  {
    const double extent = range.Extent(c);
    scale[c] = extent > 0 ? 65535.0 / extent : 0.0;
  }
  std::size_t drawnCount = 0;
#pragma omp parallel for schedule(static) reduction(+ : drawnCount)
  for (long long i = 0; i < static_cast<long long>(count); ++i)
  {
    const float* x = coordinates + i * components;
    std::uint16_t* t = texels + 4 * i;
    t[0] = t[1] = t[2] = t[3] = 0;
    if (!drawn(x, components, mask, static_cast<std::size_t>(i)))
    {
      continue;
    }
    for (int c = 0; c < components; ++c)
    {
      const double q = std::round((x[c] - range.min[c]) * scale[c]);
      t[c] = static_cast<std::uint16_t>(std::min(65535.0, std::max(0.0, q)));
    }
    t[3] = 65535;
    ++drawnCount;
  }
  return drawnCount;
}

} // namespace mcv
