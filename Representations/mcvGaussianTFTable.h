// The Gaussian widgets baked into a 3D table over the reduced domain, for per-sample
// classification: the ray caster's shader then costs one trilinear fetch of the table per
// sample (after the fetch of the sample's coordinates) instead of one exp per widget.
//
// Node (i, j, k) of an nx x ny x nz table holds the classification of the reduced point
//   x = minimum + extent * (i / (nx - 1), j / (ny - 1), k / (nz - 1))
// (an axis of extent 0, or the third of 2D coordinates, has one node) by the formula of
// GaussianWidgetFormula.h: opacity 1 - prod_i (1 - alpha_i(x)) and colour
// sum_i alpha_i c_i / sum_i alpha_i (black where every alpha_i is 0), as 16-bit
// normalised RGBA. The shader samples it at the interpolated coordinates t (in [0, 1]^3)
// with linear filtering: texture coordinate (t (n - 1) + 0.5) / n per axis, so node k is
// at t = k / (n - 1), and multiplies the opacity by the sample's drawn fraction (the
// coordinate texture's fourth channel) as the exact evaluation does.
//
// The table is a linear interpolation of a smooth function: its error on a widget of
// standard deviation sigma is at most (h / sigma)^2 / 8 of the peak opacity per axis for a
// node spacing h. chooseTableSize takes CellsPerSigma intervals per sigma of the narrowest
// visible widget on every axis (at most 3 / (8 * 9) = 4 % of the peak near its centre,
// where the three axes add up; the pictures stay within a few 1/255 of the exact ones:
// test_gaussian_tf_table, docs/benchmarks.md section 20); when that needs more than
// MaximumNodes nodes on an axis or MaximumTableNodes in all, the table would blur the
// widget, and the caller evaluates every widget per sample instead.
//
// The texture has one more z slice than the table: CheckTexel, which the shader reads to
// know that the table is bound (the sampler is pointed at it after the first frame of a
// new shader, as for the widget table of mcvGaussianTFBricks.h). No sample reaches it: the
// largest texture coordinate is the centre of slice nz - 1.
#pragma once

#include "GaussianTransferFunction.h" // mcv::detail::PackedGaussianWidget

#include <cstdint>
#include <string>
#include <vector>

namespace mcv
{
namespace tftable
{

constexpr double CellsPerSigma = 3.0;
constexpr int MaximumNodes = 512;
constexpr long long MaximumTableNodes = 1LL << 23; // 64 MiB of 16-bit RGBA
// The check slice's texel (16-bit RGBA); the shader compares it with a tolerance.
constexpr std::uint16_t CheckTexel[4] = { 65535, 0, 65535, 4369 };
// Widgets below this opacity per unit length at a node are left out of it (as the brick
// table's Cutoff): less than a tenth of the table's 16-bit resolution.
constexpr double Cutoff = 1.0e-6;

struct TableSize
{
  int nodes[3] = { 0, 0, 0 };  // 0: no table (evaluate every widget per sample)
  std::string reason;          // why there is none ("" when there is one)
  bool Valid() const { return nodes[0] > 0; }
  long long Count() const { return static_cast<long long>(nodes[0]) * nodes[1] * nodes[2]; }
};

// The node counts for `widgets` over the domain [minimum, minimum + extent] (extent 0 for a
// constant or missing component): CellsPerSigma intervals per sigma of the narrowest widget
// that exceeds Cutoff in the domain, on each axis of non-zero extent (at least 2 nodes);
// none (with the reason) when that is more than the limits above. No such widget: 2 nodes
// per axis (a transparent table).
TableSize chooseTableSize(const std::vector<mcv::detail::PackedGaussianWidget>& widgets,
  const float minimum[3], const float extent[3]);

// The texture: nodes[0] x nodes[1] x (nodes[2] + 1) texels of 4 x uint16, x fastest, the
// last z slice CheckTexel. Runs over z slices in parallel (vtkSMPTools); each widget is
// evaluated only over the nodes where it exceeds Cutoff, as a product of per-axis factors
// (exp(-k d^2) separates over the axes: 3 exps per node and widget become 3 per node row).
std::vector<std::uint16_t> bakeTable(const std::vector<mcv::detail::PackedGaussianWidget>& widgets,
  const float minimum[3], const float extent[3], const TableSize& size);

} // namespace tftable
} // namespace mcv
