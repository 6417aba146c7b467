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

// The N strongest of several lists (each the top-N of one piece of a volume, with indices
// of the whole volume), in the same order: the top-N of the whole volume, because every
// voxel of the global top-N is in its own piece's top-N.
InterestPoints mergeTopResponses(const InterestPoints& lists, int N);

} // namespace mcv
