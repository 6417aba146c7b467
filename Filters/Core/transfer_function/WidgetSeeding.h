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
//  - peak opacity: with `rayLength` (the default of vtkReducedDomain), derived from what
//    the widget selects so that it lets inner structures show (see "Opacity from the voxels
//    a widget selects" below); without it, `opacity`, except for the largest of several
//    widgets (by voxels: the points' weights), which gets 0.05 * `opacity`. Once the empty background is masked,
//    the largest class is the one that holds the others (the scalp and skull around a
//    brain, the tissue around labelled cells) and, in front of them along most rays, it
//    hid them at any comparable opacity: on the main job's brain a peak of 0.165 (and
//    still 0.042) made the brain a red ball; at 0.025 it is a veil and the brain's widgets
//    show through.
// With `skipLargest`, count + 1 clusters are made and the largest is left out: without a
// foreground mask the largest class is almost always the background (air around a head,
// the dark field of a micrograph), which a widget would turn into an opaque box. The cap
// above then also keeps the background's centre at a weight below exp(-8), dark.
//
// Opacity from the voxels a widget selects (options.rayLength > 0). A widget's opacity
// hides what lies behind it when a ray through the volume crosses many of its voxels:
// a veil of peak 0.03 over a class that fills the head still absorbed most of the light
// (the brain behind it was a red haze), and a class of a third of the head saturated at
// 0.05. So each widget gets the peak that lets a fraction `transmission` (default 1/2) of
// the light through it along a typical ray:
//  - its share s = its cluster's voxels / the voxels of all widgets' clusters (weights);
//  - a ray through the volume crosses on average rayLength opacity unit distances of the
//    foreground (the caller's estimate: the mean chord of the foreground), and, voxels of
//    all classes being mixed along it, s * rayLength of them belong to this widget;
//  - at those voxels the widget gives on average a * g, g = the mean Gaussian weight
//    exp(-|x - mu|^2 / (2 sigma^2)) over its cluster's points (known after sigma is set);
//  - transmission through it: (1 - a g)^(s rayLength) = t, hence
//        a = (1 - t^(1 / (s rayLength))) / g, capped at `opacity` (small classes, crossed
//        by less than one unit, keep the peak the user asked for).
// A widget whose share exceeds `hideShare` (default 1/2: it selects more than half of the
// volume, the background-sized class that surrounds the others) is flagged `hidden`: the
// caller shows it off (the GUI's hidden widget, shown again with its check box).
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
  // Mean length of a ray through the foreground in opacity unit distances; > 0 derives
  // each peak opacity from the widget's share (see above), 0 keeps `opacity` and the veil.
  double rayLength = 0;
  // Fraction of the light a widget lets through along a typical ray (rayLength > 0).
  double transmission = 0.5;
  // A widget selecting more than this share of the voxels is flagged hidden (rayLength > 0).
  double hideShare = 0.5;
};

struct WidgetSeeding
{
  std::string error;
  std::vector<GaussianWidget> widgets;      // largest cluster first
  std::vector<std::size_t> clusterSizes;    // size (weights) of each widget's cluster, descending
  std::vector<double> shares;               // each widget's share of the points (weights) of
                                            // all widgets' clusters
  std::vector<double> meanWeights;          // mean Gaussian weight over its cluster's points
  std::vector<bool> hidden;                 // share > hideShare (rayLength > 0 only)
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
