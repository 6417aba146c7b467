// The float candidates of the reference neighbour graph on the GPU (the 10000 x 10000 search
// of an Isomap fit, FeatureKnn.cpp's buildKnnGraph): for every point, its kp smallest float
// squared distances to all n points, ordered by (distance, index) as ExactKnn.h's
// resolveCandidates takes them. The host then applies the canonical rule to them, so the
// graph is the CPU's.
//
// Plain C++ interface; built only with MCV_ENABLE_CUDA. False with `error` on a CUDA failure
// (the caller searches on the CPU).
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>

namespace mcv
{
namespace cuda
{

// Candidates per row at most, and the dimension at most.
constexpr int kMaxKnnCandidatesOnDevice = 64;
constexpr int kMaxKnnCandidateDimension = 64;

// The largest n knnCandidates takes on this device (one row's n distances, 8 B each, sit in
// a block's shared memory). 0 where no device is usable.
std::size_t knnCandidatesMaxPoints();

// data: n x dim floats, row-major. idx, f: n x kp (kp <= min(n, 64)): row i's kp nearest
// points (itself included) by float squared distance (summed in any order: ExactKnn's
// floatDistanceMargin covers it), ties by index.
bool knnCandidates(const float* data, std::size_t n, int dim, int kp, std::uint32_t* idx, float* f, std::string* error);

} // namespace cuda
} // namespace mcv
