// GPU path of the out-of-sample placement (Filters/Core/reduction/OutOfSample.h). Plain C++ interface
// (no CUDA types) so the core can call it; built only when MCV_ENABLE_CUDA is on. Returns
// false with `error` set on any CUDA failure (allocation included): the core then runs the
// CPU path.
//
// The rows are uploaded once, the coordinates downloaded once. Per row, a tiled kernel
// (references through shared memory, one query per thread, its 8 best float distances in
// registers ordered by (distance, index)) gives candidates; a second kernel applies the
// canonical rule of ExactKnn.h (double distances rounded like the CPU's, ties by index),
// checks it with the float error bound and computes the barycentric weights and the
// coordinates; rows whose check fails get an exact double scan of every reference. So the
// GPU picks the same neighbours as the CPU.
#pragma once

#include <cstddef>
#include <cstdint>
#include <functional>
#include <string>

namespace mcv
{
namespace cuda
{

constexpr int kMaxPlacementDimension = 64; // D (features used)
constexpr int kMaxPlacementNeighbors = 6;  // k (8 float candidates are kept per row)

struct PlacementInput
{
  const float* refX = nullptr; // M x D reference features, row-major
  const float* refY = nullptr; // M x d their embedding
  std::size_t M = 0;
  int D = 0;
  int d = 0;
  const float* rows = nullptr; // n x dim, row-major
  std::size_t n = 0;
  int dim = 0;
  const int* columns = nullptr; // D column indices into a row, or null (dim == D)
  int neighbors = 3;
  double regularization = 1e-3;
  double distanceMargin = 0; // floatDistanceMargin(D) of ExactKnn.h
};

struct PlacementStats
{
  double uploadMs = 0, computeMs = 0, downloadMs = 0;
  std::size_t radiusScans = 0; // rows solved by the exact scan
};

// out: n x d floats; neighbors (optional): n x k references each row was placed by.
// progress (optional) receives the fraction of rows done, from the calling thread.
bool placeOutOfSample(const PlacementInput& input, float* out, std::uint32_t* neighbors,
  const std::function<void(double)>& progress, PlacementStats* stats, std::string* error);

} // namespace cuda
} // namespace mcv
