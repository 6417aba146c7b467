#include "TopResponses.h"

#include <omp.h>

#include <algorithm>
#include <cmath>
#include <queue>
#include <utility>
#include <vector>

namespace mcv
{

namespace
{

using Candidate = std::pair<float, std::int64_t>; // (response, linear index)

// Strict "ranks before": higher response first, then lower index (unique order under ties).
struct RanksBefore
{
  bool operator()(const Candidate& a, const Candidate& b) const
  {
    return a.first > b.first || (a.first == b.first && a.second < b.second);
  }
};

// The `keep` candidates that rank first, in rank order.
InterestPoints strongest(std::vector<Candidate>& merged, std::size_t keep)
{
  InterestPoints result;
  const std::size_t taken = std::min(keep, merged.size());
  std::partial_sort(merged.begin(), merged.begin() + static_cast<std::ptrdiff_t>(taken),
    merged.end(), RanksBefore());
  result.indices.reserve(taken);
  result.scores.reserve(taken);
  for (std::size_t i = 0; i < taken; ++i)
  {
    result.scores.push_back(merged[i].first);
    result.indices.push_back(merged[i].second);
  }
  return result;
}

} // namespace

InterestPoints selectTopResponsesCPU(const float* response, std::size_t count, int N)
{
  if (N <= 0 || count == 0)
  {
    return InterestPoints();
  }
  const std::size_t keep = static_cast<std::size_t>(N);
  std::vector<std::vector<Candidate>> perThread;

#pragma omp parallel
  {
#pragma omp single
    perThread.resize(static_cast<std::size_t>(omp_get_num_threads()));

    // A bounded heap per thread whose top is the weakest kept candidate (as in the
    // dissertation's filtering step); once full, most voxels are rejected by one compare.
    std::priority_queue<Candidate, std::vector<Candidate>, RanksBefore> heap;
    const std::int64_t n = static_cast<std::int64_t>(count);
#pragma omp for schedule(static) nowait
    for (std::int64_t v = 0; v < n; ++v)
    {
      const float r = response[v];
      if (!(r > 0.f) || !std::isfinite(r))
      {
        continue;
      }
      if (heap.size() < keep)
      {
        heap.emplace(r, v);
      }
      else if (RanksBefore()(Candidate(r, v), heap.top()))
      {
        heap.pop();
        heap.emplace(r, v);
      }
    }
    std::vector<Candidate>& mine = perThread[static_cast<std::size_t>(omp_get_thread_num())];
    mine.reserve(heap.size());
    while (!heap.empty())
    {
      mine.push_back(heap.top());
      heap.pop();
    }
  }

  std::vector<Candidate> merged;
  for (const auto& part : perThread)
  {
    merged.insert(merged.end(), part.begin(), part.end());
  }
  return strongest(merged, keep);
}

InterestPoints mergeTopResponses(const InterestPoints& lists, int N)
{
  std::vector<Candidate> merged(lists.size());
  for (std::size_t i = 0; i < lists.size(); ++i)
  {
    merged[i] = Candidate(lists.scores[i], lists.indices[i]);
  }
  return strongest(merged, N > 0 ? static_cast<std::size_t>(N) : 0);
}

} // namespace mcv
