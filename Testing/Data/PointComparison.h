// Comparing two interest-point selections (CPU vs GPU): shared by tests and benchmarks.
#pragma once

#include "TopResponses.h"

#include <algorithm>
#include <unordered_set>

namespace mcv
{
namespace testing
{

// Fraction of the larger selection's voxel indices that both selections hold (1 for two
// empty selections).
inline double indexOverlap(const InterestPoints& a, const InterestPoints& b)
{
  const std::size_t n = std::max(a.size(), b.size());
  if (n == 0)
  {
    return 1.0;
  }
  const std::unordered_set<std::int64_t> inA(a.indices.begin(), a.indices.end());
  std::size_t common = 0;
  for (const std::int64_t i : b.indices)
  {
    common += inA.count(i);
  }
  return static_cast<double>(common) / static_cast<double>(n);
}

} // namespace testing
} // namespace mcv
