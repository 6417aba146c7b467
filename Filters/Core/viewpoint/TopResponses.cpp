#include "TopResponses.h"

#include <omp.h>

#include <algorithm>
#include <cfloat>
#include <cmath>
#include <utility>
#include <vector>

namespace mcv
{

namespace
{

using Candidate = TopResponseCollector::Candidate;

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

// Runs of this many values are tested at once before any is looked at alone.
constexpr std::size_t kChunk = 64;

} // namespace

TopResponseCollector::TopResponseCollector(std::size_t keep)
  : Keep(keep)
{
  Heap.reserve(keep);
}

void TopResponseCollector::offerOne(float value, std::int64_t index)
{
  // Candidates only: strictly positive and finite (NaN fails the first test).
  if (!(value > 0.f) || !(value <= FLT_MAX) || Keep == 0)
  {
    return;
  }
  const Candidate c(value, index);
  if (Heap.size() < Keep)
  {
    Heap.push_back(c);
    std::push_heap(Heap.begin(), Heap.end(), RanksBefore());
  }
  else if (RanksBefore()(c, Heap.front()))
  {
    std::pop_heap(Heap.begin(), Heap.end(), RanksBefore());
    Heap.back() = c;
    std::push_heap(Heap.begin(), Heap.end(), RanksBefore());
  }
  else
  {
    return;
  }
  if (Heap.size() == Keep)
  {
    Floor = Heap.front().first;
  }
}

void TopResponseCollector::offer(const float* values, std::int64_t firstIndex, std::size_t count)
{
  for (std::size_t begin = 0; begin < count; begin += kChunk)
  {
    const std::size_t end = std::min(count, begin + kChunk);
    // Whether any value of the run can enter: positive, finite and at least the floor (a
    // value equal to the weakest kept one enters when its index is lower).
    const float floor = Floor;
    int any = 0;
#pragma omp simd reduction(| : any)
    for (std::size_t i = begin; i < end; ++i)
    {
      const float v = values[i];
      any |= (v > 0.f) & (v >= floor) & (v <= FLT_MAX);
    }
    if (!any)
    {
      continue;
    }
    for (std::size_t i = begin; i < end; ++i)
    {
      if (values[i] >= Floor)
      {
        offerOne(values[i], firstIndex + static_cast<std::int64_t>(i));
      }
    }
  }
}

std::vector<Candidate> TopResponseCollector::take()
{
  std::vector<Candidate> out;
  out.swap(Heap);
  Floor = 0.f;
  Heap.reserve(Keep);
  return out;
}

InterestPoints mergeCollectors(std::vector<TopResponseCollector>& collectors, int N)
{
  std::vector<Candidate> merged;
  for (TopResponseCollector& c : collectors)
  {
    const std::vector<Candidate> part = c.take();
    merged.insert(merged.end(), part.begin(), part.end());
  }
  return strongest(merged, N > 0 ? static_cast<std::size_t>(N) : 0);
}

InterestPoints selectTopResponsesCPU(const float* response, std::size_t count, int N)
{
  if (N <= 0 || count == 0)
  {
    return InterestPoints();
  }
  const std::size_t keep = static_cast<std::size_t>(N);
  std::vector<TopResponseCollector> collectors;

#pragma omp parallel
  {
#pragma omp single
    collectors.assign(static_cast<std::size_t>(omp_get_num_threads()), TopResponseCollector(keep));

    // Each thread one contiguous share of the volume, offered in runs (a fixed split, so
    // the work per thread does not depend on the values).
    TopResponseCollector& mine = collectors[static_cast<std::size_t>(omp_get_thread_num())];
    const std::size_t threads = static_cast<std::size_t>(omp_get_num_threads());
    const std::size_t id = static_cast<std::size_t>(omp_get_thread_num());
    const std::size_t begin = count * id / threads, end = count * (id + 1) / threads;
    mine.offer(response + begin, static_cast<std::int64_t>(begin), end - begin);
  }
  return mergeCollectors(collectors, N);
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
