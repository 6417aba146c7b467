// Automatic starting widgets for the Gaussian transfer function (the dissertation's future
// work, section 7.7): k-means clusters of the reduced domain, one widget per cluster.
//
// Centre = the cluster mean; sigma = the cluster's RMS spread per axis,
// sqrt(mean |x - mu|^2 / dims) (the sigma of an isotropic Gaussian with that spread);
// colour = evenly spaced hues, largest cluster first; opacity = `opacity`.
// With `skipLargest`, count + 1 clusters are made and the largest is left out: in a volume
// the largest class is almost always the background (air around a head, the dark field
// of a micrograph), which a widget would turn into an opaque box; each widget's sigma is
// then at most a quarter of its centre's distance to the skipped cluster's centre, so the
// background keeps a weight below exp(-8) and stays dark.
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
};

struct WidgetSeeding
{
  std::string error;
  std::vector<GaussianWidget> widgets;      // largest cluster first
  std::vector<std::size_t> clusterSizes;    // points per widget's cluster
  std::vector<int> labels;                  // widget of every finite point (-1: not finite,
                                            // -2: in the skipped largest cluster)
  std::size_t skippedSize = 0;              // points of the skipped cluster
  int iterations = 0;
  bool ok() const { return error.empty(); }
};

// k-means++ seeding then Lloyd iterations until no point changes cluster. Points with a
// non-finite coordinate are ignored. Fewer distinct points than `count`: as many widgets as
// distinct points.
WidgetSeeding seedGaussianWidgets(const CoordinateView& points, const WidgetSeedingOptions& options);

// Hue h in [0,1) at full value and 85 % saturation, as RGB in [0,1].
void distinctColor(int index, int count, double rgb[3]);

} // namespace mcv
