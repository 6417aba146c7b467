// Selection of the N strongest interest points from a response volume.
// Candidates are voxels with a strictly positive, finite response (corners and bright
// blobs; flat regions give 0 and edges negative). Order: response descending, then linear
// index ascending, so the result is unique even with ties.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

namespace mcv
{

struct InterestPoints
{
  std::vector<std::int64_t> indices; // linear voxel indices (x fastest)
  std::vector<float> scores;         // Harris responses, same order
  std::size_t size() const { return indices.size(); }
};

// CPU (OpenMP): per-thread bounded heaps, merged. Returns min(N, #candidates) points.
InterestPoints selectTopResponsesCPU(const float* response, std::size_t count, int N);

} // namespace mcv
