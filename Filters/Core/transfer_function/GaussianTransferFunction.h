// The multichannel transfer function (dissertation chapter 5): Gaussian widgets placed in
// the reduced (2D/3D) domain give every voxel a colour and an opacity.
//
// Widget i: centre mu_i, isotropic sigma_i, colour c_i (RGB in [0,1]), peak opacity a_i.
//   alpha_i(x) = a_i * exp(-|x - mu_i|^2 / (2 sigma_i^2))
//   opacity(x) = 1 - prod_i (1 - alpha_i(x))
//   colour(x)  = sum_i alpha_i(x) c_i / sum_i alpha_i(x)   (black where every alpha_i is 0)
// With 2D coordinates the widgets' third centre coordinate is ignored. A voxel whose
// coordinates are not finite is transparent black.
//
// How it is computed (CPU and GPU alike, float32): with the log-weights
// e_i = ln a_i - |x - mu_i|^2 / (2 sigma_i^2) and m = max_i e_i,
//   alpha_i = exp(e_i - m) exp(m),   colour = sum_i exp(e_i - m) c_i / sum_i exp(e_i - m),
// which is the formula above with no underflow: far from every widget the colour is still
// the formula's weighted mean (the opacity there is ~0), and CPU and GPU agree there too.
// e_i is computed with the same float operations on both (no fused multiply-add), so
// the two differ only by their exp (a few ulp). Every widget is evaluated at every voxel
// (skipping far widgets per block of voxels saved only ~10 % on smooth coordinates). A
// voxel whose squared distances overflow float for every widget is transparent black,
// like a non-finite one.
#pragma once

#include "Device.h"
#include "GaussianWidgetFormula.h"

#include <cstddef>
#include <cstdint>
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
// version: 0 = unknown. Non-zero: a tag that the caller changes whenever the values change
// (e.g. the VTK array's MTime). The GPU path keeps the coordinates on the device between
// calls and uploads them again only when data, count, components or version differ, so a
// widget edit on unchanged coordinates costs no upload (16 M voxels x 3 floats = 192 MB).
struct CoordinateView
{
  const float* data = nullptr;
  std::size_t count = 0;
  int components = 3;
  std::uint64_t version = 0;
  // Instead of data: float16 coordinates (binary16 bits, HalfCoordinates.h), decoded a
  // block of voxels at a time on the CPU; the GPU path uploads them as they are and widens
  // them on the device (the same float32 values).
  const std::uint16_t* halves = nullptr;
};

struct TransferFunctionRun
{
  std::string error; // bad components, null pointers, sigma <= 0 or a non-finite widget value
  std::vector<std::string> warnings;
  Device deviceUsed = Device::CPU;
  bool ok() const { return error.empty(); }
};

// RGBA per voxel, 4 values per voxel: floats in [0,1], or bytes round(255 v) (what the
// volume mapper is given). The widgets are checked like parseGaussianWidgets does (error:
// sigma <= 0 or a non-finite value; colours/opacity outside [0,1] clamped with a warning);
// no widgets gives a transparent volume without a further warning. Device Auto/GPU runs
// the CUDA path when one is usable and falls back to the CPU with a warning on any CUDA
// error; deviceUsed says where it ran.
TransferFunctionRun applyGaussianWidgets(const CoordinateView& coordinates,
  const std::vector<GaussianWidget>& widgets, float* rgba, Device device = Device::Auto);
TransferFunctionRun applyGaussianWidgets(const CoordinateView& coordinates,
  const std::vector<GaussianWidget>& widgets, unsigned char* rgba, Device device = Device::Auto);

// Opacity only (one float per voxel): what the best viewpoint looks at.
TransferFunctionRun gaussianWidgetOpacity(const CoordinateView& coordinates,
  const std::vector<GaussianWidget>& widgets, float* opacity, Device device = Device::Auto);

// Frees the coordinates and output kept on the GPU between calls (nothing without CUDA).
void releaseGaussianWidgetDeviceCache();

namespace detail
{

// A widget as both paths evaluate it: centre (cz = 0 for 2D coordinates), k = 1/(2 sigma^2),
// logA = ln(opacity), colour; all float, computed once in double on the host.
struct PackedGaussianWidget
{
  float cx, cy, cz, k, logA, r, g, b;
};

// Checks and packs `widgets` for `components` (2 or 3) coordinates; widgets of opacity 0
// are left out (they add nothing). `error`/`warnings` as in parseGaussianWidgets.
std::vector<PackedGaussianWidget> packGaussianWidgets(const std::vector<GaussianWidget>& widgets,
  int components, std::string& error, std::vector<std::string>& warnings);

// exp(x) for x in [-87.3, 0] (lower x, NaN included, give exp(-87.3) ~ 1e-38) without a
// libm call, so that loops over it vectorise: Cody-Waite reduction by ln 2 and the
// degree-5 polynomial of Cephes' expf; relative error 8.1e-8 at most on a 2 M-point
// sweep of [-87.3, 0] (TestGaussianTransferFunction.ExpKernelRelativeError).
float expNonPositive(float x);

} // namespace detail

} // namespace mcv
