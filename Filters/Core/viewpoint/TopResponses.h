// Selection of the N strongest interest points from a response volume.
// Candidates are voxels with a strictly positive, finite response (corners and bright
// blobs; flat regions give 0 and edges negative). Order: response descending, then linear
// index ascending, so the result is unique even with ties.
#pragma once

#include <cstddef>
#include <cstdint>
#include <utility>
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

// The `keep` strongest candidates among the runs of responses offered to it, for one
// thread: a bounded heap whose top is the weakest kept candidate. A run whose values all
// fall below that candidate's score is rejected by one vectorised pass, without a branch
// per voxel. Several collectors that together saw every voxel merge (mergeCollectors) into
// the same top-N as selectTopResponsesCPU over the whole response, in any order of offers.
class TopResponseCollector
{
public:
  using Candidate = std::pair<float, std::int64_t>; // (response, linear index)

  explicit TopResponseCollector(std::size_t keep);

  // values[i] is the response of voxel firstIndex + i, for i < count.
  void offer(const float* values, std::int64_t firstIndex, std::size_t count);

  // The kept candidates (any order); the collector is empty afterwards.
  std::vector<Candidate> take();

private:
  void offerOne(float value, std::int64_t index);

  std::size_t Keep;
  std::vector<Candidate> Heap; // std::push_heap / pop_heap order: the weakest on top
  float Floor = 0.f;           // a value below this cannot enter (the top's score once full)
};

// The top-N (rank order) of what several collectors kept; each collector is emptied.
InterestPoints mergeCollectors(std::vector<TopResponseCollector>& collectors, int N);

} // namespace mcv
