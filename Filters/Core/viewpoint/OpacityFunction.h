// Scalars -> opacity: a piecewise-linear function applied to one or more channels.
#pragma once

#include "ChannelView.h"
#include "GridPiece.h"

#include <array>
#include <cstddef>
#include <utility>
#include <vector>

namespace mcv
{

// Piecewise-linear opacity: nodes (x ascending, alpha in [0,1]); constant beyond the ends.
struct OpacityFunction
{
  std::vector<double> x;
  std::vector<double> alpha;

  // 0 at `lo` rising linearly to 1 at `hi` (the default: a channel's own range).
  static OpacityFunction ramp(double lo, double hi);
  bool empty() const { return x.empty(); }
  double evaluate(double value) const;
};

// Finite min and max of a channel; {+inf, -inf} when it holds no finite value.
std::pair<double, double> finiteRange(const ChannelView& channel, std::size_t count);

// opacity[v] = max(opacity[v], f(channel[v])) for every voxel (OpenMP). NaN/Inf voxels
// map to 0; returns how many there were so the caller can warn.
std::size_t accumulateOpacity(
  const ChannelView& channel, std::size_t count, const OpacityFunction& f, float* opacity);

// The voxels of a block that its process OWNS (piece) and that hold NaN or Inf in at least
// one of the channels: summed over processes, each voxel of the volume counts once (ghost
// layers and shared boundaries do not). Integer channels hold no such value.
std::size_t countNonFiniteVoxels(
  const std::vector<ChannelView>& channels, const ImageGrid& block, const GridPiece& piece);

// The voxels of a block that its process owns and whose opacity is at least `threshold`
// (summed over processes, each voxel of the volume counts once).
std::size_t countOwnedAtLeast(
  const float* opacity, const ImageGrid& block, const GridPiece& piece, float threshold);

// The voxels (block indices i, j, k) the process owns whose opacity is at least
// `threshold` that can be the furthest along some direction: of each x row its first and
// last such voxel, and of those, per slice k, only the vertices of the slice's 2D convex
// hull (in k order). The bounds and the convex hull of all such voxels are those of these.
std::vector<std::array<int, 3>> ownedHullCandidatesAtLeast(
  const float* opacity, const ImageGrid& block, const GridPiece& piece, float threshold);

} // namespace mcv
