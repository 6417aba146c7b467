// Which Gaussian widgets can reach each brick of the volume, for per-sample classification:
// the ray caster's shader looks a sample's brick up, skips a brick that no widget reaches
// (empty space: masked voxels, or coordinates far from every widget) to the brick's exit
// in whole sample steps, and in the other bricks evaluates only the widgets listed for it.
//
// A brick is BrickSize^3 voxels: brick b of an axis holds the samples whose continuous
// voxel index u (texture coordinate * size - 0.5) lies in [b B, (b + 1) B). Such a sample
// interpolates the voxels floor(u) and floor(u) + 1, so a brick's bounds in the reduced
// domain are those of the drawn voxels [b B, (b + 1) B] (one more than the brick). The
// interpolated coordinate (the drawn corners' weighted mean) lies inside those bounds.
// A widget reaches a brick when its largest log-opacity over the bounds,
// ln a - k d^2 (d: the distance from its centre to the bounds), exceeds ln(Cutoff): the
// widgets left out add less than Cutoff opacity per unit length to any of its samples.
//
// The table is one stream of (x, y) float pairs, TableWidth to a row of an RG float
// texture: entry 0 is a check value, entries 1 .. bricks are each brick's (list start,
// list length) in x-fastest brick order, then the lists (widget index in x). Identical
// lists are stored once. A brick reached by more than 1/ListShare of the widgets gets
// (-1, all widgets): the shader then loops over every widget with the same index in all
// lanes, which costs less per widget than a list (a software rasteriser gathers a listed
// widget's uniforms per sample: about 2.2 times the cost, llvmpipe).
#pragma once

#include "GaussianTransferFunction.h" // mcv::detail::PackedGaussianWidget

#include <cstddef>
#include <cstdint>
#include <vector>

namespace mcv
{
namespace bricks
{

constexpr int BrickSize = 8;
constexpr int TableWidth = 2048; // OpenGL 4.5 guarantees 3D textures of 2048 (llvmpipe: 2048)
constexpr float CheckValue = 16777.0f; // entry 0: the shader draws nothing without it
constexpr double Cutoff = 1.0e-6;
constexpr size_t ListShare = 3;

// Per-brick bounds of the drawn voxels' texture coordinates (quantised, in [0, 1]).
struct BrickBounds
{
  int volume[3] = { 0, 0, 0 };
  int grid[3] = { 0, 0, 0 };
  std::vector<float> low, high; // 3 per brick; low > high: no drawn voxel
  int Count() const { return grid[0] * grid[1] * grid[2]; }
};

// texels: 4 x uint16 per voxel (CoordinateTexture.h), x fastest, dims[0] x dims[1] x dims[2].
BrickBounds computeBrickBounds(const std::uint16_t* texels, const int dims[3]);

// The table for `widgets` (coordinates x = minimum + extent * t): width x height RG texels.
std::vector<float> buildWidgetTable(const BrickBounds& bounds,
  const std::vector<mcv::detail::PackedGaussianWidget>& widgets, const float minimum[3],
  const float extent[3], int& height, int& emptyBricks, long long& listedWidgets);

} // namespace bricks
} // namespace mcv
