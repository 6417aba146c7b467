// The multichannel transfer function (dissertation chapter 5): Gaussian widgets placed in
// the reduced (2D/3D) domain give every voxel a colour and an opacity.
//
// Widget i: centre mu_i, isotropic sigma_i, colour c_i (RGB in [0,1]), peak opacity a_i.
//   alpha_i(x) = a_i * exp(-|x - mu_i|^2 / (2 sigma_i^2))
//   opacity(x) = 1 - prod_i (1 - alpha_i(x))
//   colour(x)  = sum_i alpha_i(x) c_i / sum_i alpha_i(x)   (black where every alpha_i is 0)
// With 2D coordinates the widgets' third centre coordinate is ignored. A voxel whose
// coordinates are not finite is transparent black.
#pragma once

#include "Device.h"

#include <cstddef>
#include <string>
#include <vector>

namespace mcv
{

struct GaussianWidget
{
  double center[3] = { 0, 0, 0 };
  double sigma = 1;
  double color[3] = { 1, 1, 1 };
  double opacity = 1;
};

// Number of values per widget in the flat list (cx, cy, cz, sigma, r, g, b, opacity): the
// layout of the ParaView property `GaussianWidgets`.
constexpr int GaussianWidgetStride = 8;

struct WidgetList
{
  std::vector<GaussianWidget> widgets;
  std::string error;                 // non-empty: the list is unusable
  std::vector<std::string> warnings; // clamped colours/opacities, no widgets
  bool ok() const { return error.empty(); }
};

// Parses a flat list. Errors: a length that is not a multiple of 8, a non-finite value,
// sigma <= 0. Colours and opacity outside [0,1] are clamped with a warning; an empty list
// is valid (a transparent volume) with a warning.
WidgetList parseGaussianWidgets(const double* values, std::size_t count);
std::vector<double> flattenGaussianWidgets(const std::vector<GaussianWidget>& widgets);

// coordinates: n points x `components` floats (2 or 3), row-major.
struct CoordinateView
{
  const float* data = nullptr;
  std::size_t count = 0;
  int components = 3;
};

struct TransferFunctionRun
{
  std::string error; // bad components, null pointers
  std::vector<std::string> warnings;
  Device deviceUsed = Device::CPU;
  bool ok() const { return error.empty(); }
};

// RGBA per voxel, 4 values per voxel: floats in [0,1], or bytes round(255 v) (what the
// volume mapper is given).
TransferFunctionRun applyGaussianWidgets(const CoordinateView& coordinates,
  const std::vector<GaussianWidget>& widgets, float* rgba, Device device = Device::Auto);
TransferFunctionRun applyGaussianWidgets(const CoordinateView& coordinates,
  const std::vector<GaussianWidget>& widgets, unsigned char* rgba, Device device = Device::Auto);

// Opacity only (one float per voxel): what the best viewpoint looks at.
TransferFunctionRun gaussianWidgetOpacity(const CoordinateView& coordinates,
  const std::vector<GaussianWidget>& widgets, float* opacity, Device device = Device::Auto);

} // namespace mcv
