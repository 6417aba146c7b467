#include "CoordinateTexture.h"

#include "HalfCoordinates.h"

#include <algorithm>
#include <cmath>
#include <vector>

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

// Voxel i's texel from its coordinates x (float).
bool quantizeVoxel(const float* x, int components, const std::uint8_t* mask, std::size_t i, const CoordinateRange& range,
  const double* scale, std::uint16_t* t)
{
  t[0] = t[1] = t[2] = t[3] = 0;
  if (!drawn(x, components, mask, i))
  {
    return false;
  }
  for (int c = 0; c < components; ++c)
  {
    const double q = std::round((x[c] - range.min[c]) * scale[c]);
    t[c] = static_cast<std::uint16_t>(std::min(65535.0, std::max(0.0, q)));
  }
  t[3] = 65535;
  return true;
}

void scales(const CoordinateRange& range, int components, double* scale)
{
  for (int c = 0; c < components; ++c)
  {
    const double extent = range.Extent(c);
    scale[c] = extent > 0 ? 65535.0 / extent : 0.0;
  }
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

void CoordinateRange::AddHalf(
  const std::uint16_t* coordinates, std::size_t count, int components, const std::uint8_t* mask)
{
  std::vector<float> x(kHalfChunkVoxels * static_cast<std::size_t>(components));
  for (std::size_t first = 0; first < count; first += kHalfChunkVoxels)
  {
    const std::size_t n = std::min(kHalfChunkVoxels, count - first);
    halvesToFloats(coordinates + first * components, n * components, x.data());
    this->Add(x.data(), n, components, mask ? mask + first : nullptr);
  }
}

std::size_t quantizeCoordinates(const float* coordinates, std::size_t count, int components,
  const std::uint8_t* mask, const CoordinateRange& range, std::uint16_t* texels)
{
  double scale[3] = { 0, 0, 0 };
  scales(range, components, scale);
  std::size_t drawnCount = 0;
#pragma omp parallel for schedule(static) reduction(+ : drawnCount)
  for (long long i = 0; i < static_cast<long long>(count); ++i)
  {
    drawnCount += quantizeVoxel(coordinates + i * components, components, mask, static_cast<std::size_t>(i), range,
      scale, texels + 4 * i) ? 1 : 0;
  }
  return drawnCount;
}

std::size_t quantizeHalfCoordinates(const std::uint16_t* coordinates, std::size_t count, int components,
  const std::uint8_t* mask, const CoordinateRange& range, std::uint16_t* texels)
{
  double scale[3] = { 0, 0, 0 };
  scales(range, components, scale);
  // Chunks of voxels per thread, each decoded into the thread's own float scratch.
  constexpr std::size_t chunk = 4096;
  const long long chunks = static_cast<long long>((count + chunk - 1) / chunk);
  std::size_t drawnCount = 0;
#pragma omp parallel reduction(+ : drawnCount)
  {
    std::vector<float> x(chunk * static_cast<std::size_t>(components));
#pragma omp for schedule(static)
    for (long long k = 0; k < chunks; ++k)
    {
      const std::size_t first = static_cast<std::size_t>(k) * chunk, n = std::min(chunk, count - first);
      halvesToFloats(coordinates + first * components, n * components, x.data());
      for (std::size_t v = 0; v < n; ++v)
      {
        drawnCount += quantizeVoxel(x.data() + v * components, components, mask, first + v, range, scale,
          texels + 4 * (first + v)) ? 1 : 0;
      }
    }
  }
  return drawnCount;
}

} // namespace mcv
