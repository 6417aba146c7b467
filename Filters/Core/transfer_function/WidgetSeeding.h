// Automatic starting widgets for the Gaussian transfer function (the dissertation's future
// work, section 7.7): k-means clusters of the reduced domain, one widget per cluster.
//
// Widgets are ordered largest cluster first. For each:
//  - centre = the cluster mean;
//  - sigma = the cluster's RMS spread per axis, sqrt(mean |x - mu|^2 / dims) (the sigma of
//    an isotropic Gaussian with that spread), capped at a quarter of the distance from its
//    centre to the nearest other cluster centre: two neighbouring widgets then weigh at
//    most exp(-2) = 0.14 at the point halfway between them, so each one selects its own
//    structure instead of one widget covering everything;
//  - colour = widgetColor(i): ColorBrewer's qualitative Set1, one palette for the suite;
//  - peak opacity = `opacity`, except for the largest of several widgets (by voxels: the
//    points' weights), which gets 0.05 * `opacity`. Once the empty background is masked,
//    the largest class is the one that holds the others (the scalp and skull around a
//    brain, the tissue around labelled cells) and, in front of them along most rays, it
//    hid them at any comparable opacity: on the main job's brain a peak of 0.165 (and
//    still 0.042) made the brain a red ball; at 0.025 it is a veil and the brain's widgets
//    show through.
// With `skipLargest`, count + 1 clusters are made and the largest is left out: without a
// foreground mask the largest class is almost always the background (air around a head,
// the dark field of a micrograph), which a widget would turn into an opaque box. The cap
// above then also keeps the background's centre at a weight below exp(-8), dark.
#pragma once

#include "GaussianTransferFunction.h"

#include <cstdint>
#include <string>
#include <vector>

namespace mcv
{

struct WidgetSeedingOptions
{
  int count = 4;
  std::uint64_t seed = 0;
  int maxIterations = 100;
  double opacity = 0.8;
  bool skipLargest = false;
  // Optional, one per point: the voxels the point stands for (ReducedDomain clusters
  // distinct coordinates, each standing for all voxels at it). They weigh in the cluster
  // sizes (order, skipped cluster, opacity), not in the k-means. Null: 1 each.
  const double* weights = nullptr;
};

struct WidgetSeeding
{
  std::string error;
  std::vector<GaussianWidget> widgets;      // largest cluster first
  std::vector<std::size_t> clusterSizes;    // size (weights) of each widget's cluster, descending
  std::vector<int> labels;                  // widget of every finite point (-1: not finite,
                                            // -2: in the skipped largest cluster)
  std::size_t skippedSize = 0;              // size (weights) of the skipped cluster
  int iterations = 0;
  bool ok() const { return error.empty(); }
};

// k-means++ seeding then Lloyd iterations until no point changes cluster. Points with a
// non-finite coordinate are ignored. Fewer distinct points than `count`: as many widgets as
// distinct points.
WidgetSeeding seedGaussianWidgets(const CoordinateView& points, const WidgetSeedingOptions& options);

// The colour of seeded widget `index` (0-based), RGB in [0,1]: the 8 colours of ColorBrewer
// Set1 without its grey (red, blue, green, purple, orange, yellow, brown, pink), readable
// on dark and light backgrounds; then the same 8 at 60 % brightness, so the first 16
// differ; after that they repeat.
void widgetColor(int index, double rgb[3]);

// The number of colours of the qualitative palette behind widgetColor.
int widgetPaletteSize();

} // namespace mcv
