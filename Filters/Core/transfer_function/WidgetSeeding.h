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
//  - peak opacity = `opacity` * smallest seeded cluster / this cluster (sizes in voxels:
//    the points' weights), at least 0.05 * `opacity`: every widget then adds about the
//    same opacity (peak x voxels) to the picture, so a class that fills the volume (the
//    tissue of a whole head) is a faint veil and the small inner structures stay visible.
//    On the main job's brain (Examples/transfer_function.py, 4 widgets) a cube-root rule
//    left the largest class (the scalp) at 0.165 and it hid the brain; this one gives it
//    0.025 and the brain's structures show through.
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
