// PCA of interest-point positions -> best and worst view directions.
#pragma once

#include "ImageGrid.h"
#include "TopResponses.h"

#include <array>
#include <string>
#include <vector>

namespace mcv
{

using Vec3 = std::array<double, 3>;

struct ViewDirections
{
  bool valid = false;       // false: too few or degenerate points; `message` says why
  Vec3 best{ 0, 0, 0 };     // v3, the direction of least variance: the camera looks along it
  Vec3 worst{ 0, 0, 0 };    // v1, the direction of most variance
  Vec3 viewUp{ 0, 0, 0 };   // v2 (see computeViewDirections)
  Vec3 eigenvalues{ 0, 0, 0 }; // covariance eigenvalues, descending, normalised to sum 1
  Vec3 center{ 0, 0, 0 };   // mean of the points
  std::string message;
};

// Sign conventions (so that results are reproducible and CPU/GPU comparable):
// each eigenvector is flipped so that its largest-magnitude component is positive.
// View-up is v2, the axis of middle variance: the widest spread (v1) then runs
// horizontally across the usually wider-than-tall viewport.
ViewDirections computeViewDirections(const std::vector<Vec3>& points);

// World positions of interest points (spacing and origin respected).
std::vector<Vec3> worldPositions(const InterestPoints& points, const ImageGrid& grid);

// Angle in degrees between the axes through a and b: a and -a are the same axis, since
// PCA directions are defined up to sign. 0 when either vector is zero.
double axisAngleDegrees(const Vec3& a, const Vec3& b);

} // namespace mcv
