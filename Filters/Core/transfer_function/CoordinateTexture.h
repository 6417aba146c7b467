// The reduced coordinates as the ray caster samples them for per-sample classification:
// four 16-bit normalised channels per voxel (x, y, z, foreground), uploaded once as a 3D
// texture; the fragment shader evaluates the Gaussian widgets at every interpolated sample.
//
// Component c of a voxel is stored as round(65535 (x_c - min_c) / extent_c), so the
// shader recovers x_c = min_c + extent_c * t_c from the texture value t_c in [0, 1]
// (extent_c = max_c - min_c; 0 for a constant component or the missing third component of
// 2D coordinates). The fourth channel is 65535 for a voxel that is drawn and 0 for one
// that is not (masked out as background, or a non-finite coordinate); linear
// interpolation of that channel fades opacity smoothly over half a voxel at the border.
// 16 bits resolve 1/65535 of each component's range: far finer than any widget's sigma,
// at 8 bytes per voxel instead of 16 for float32.
#pragma once

#include <cstddef>
#include <cstdint>

namespace mcv
{

// Per-component range of the coordinates of the drawn voxels (finite coordinates whose
// mask value, when a mask is given, is non-zero). Several pieces share one range:
// accumulate each piece into the same CoordinateRange before quantising any.
struct CoordinateRange
{
  double min[3] = { 0, 0, 0 };
  double max[3] = { 0, 0, 0 };
  bool empty = true;

  void Add(const float* coordinates, std::size_t count, int components,
    const std::uint8_t* mask = nullptr);
  // The same from float16 coordinates (binary16 bits, HalfCoordinates.h), decoded a chunk
  // at a time.
  void AddHalf(const std::uint16_t* coordinates, std::size_t count, int components,
    const std::uint8_t* mask = nullptr);
  double Extent(int c) const { return empty ? 0.0 : max[c] - min[c]; }
};

// Writes 4 x uint16 per voxel into `texels` (count x 4 values). components: 2 or 3.
// mask: optional, one byte per voxel, 0 = not drawn. Returns the number of drawn voxels.
std::size_t quantizeCoordinates(const float* coordinates, std::size_t count, int components,
  const std::uint8_t* mask, const CoordinateRange& range, std::uint16_t* texels);
// The same from float16 coordinates, decoded a chunk at a time (per thread).
std::size_t quantizeHalfCoordinates(const std::uint16_t* coordinates, std::size_t count, int components,
  const std::uint8_t* mask, const CoordinateRange& range, std::uint16_t* texels);

} // namespace mcv
