// Top-N selection against a full sort (the obvious reference), ties and exclusions included.
#include "TopResponses.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>

namespace
{

mcv::InterestPoints referenceTopN(const std::vector<float>& r, int N)
{
  std::vector<std::int64_t> order;
  for (std::size_t i = 0; i < r.size(); ++i)
  {
    if (r[i] > 0.f && std::isfinite(r[i]))
    {
      order.push_back(static_cast<std::int64_t>(i));
    }
  }
  std::stable_sort(order.begin(), order.end(), [&](std::int64_t a, std::int64_t b) { return r[a] > r[b]; });
  order.resize(std::min<std::size_t>(order.size(), static_cast<std::size_t>(N)));
  mcv::InterestPoints p;
  p.indices = order;
  for (auto i : order)
  {
    p.scores.push_back(r[i]);
  }
  return p;
}

TEST(TopResponses, MatchesFullSortWithTiesAndExclusions)
{
  std::mt19937 rng(5);
  std::uniform_int_distribution<int> level(-50, 50); // coarse levels: many exact ties
  std::vector<float> r(100000);
  for (float& v : r)
  {
    v = static_cast<float>(level(rng)) * 0.25f;
  }
  r[17] = std::numeric_limits<float>::quiet_NaN();
  r[18] = std::numeric_limits<float>::infinity();
  for (int N : { 1, 7, 2048, 60000 })
  {
    const mcv::InterestPoints got = mcv::selectTopResponsesCPU(r.data(), r.size(), N);
    const mcv::InterestPoints want = referenceTopN(r, N);
    EXPECT_EQ(got.indices, want.indices) << "N=" << N;
    EXPECT_EQ(got.scores, want.scores) << "N=" << N;
  }
}

TEST(TopResponses, FewerCandidatesThanNReturnsAll)
{
  std::vector<float> r(1000, 0.f);
  r[10] = 3.f;
  r[500] = 5.f;
  r[999] = -4.f;
  const mcv::InterestPoints got = mcv::selectTopResponsesCPU(r.data(), r.size(), 2048);
  ASSERT_EQ(got.size(), 2u);
  EXPECT_EQ(got.indices[0], 500);
  EXPECT_EQ(got.indices[1], 10);
}

TEST(TopResponses, NothingForConstantOrNonPositiveN)
{
  std::vector<float> r(1000, 0.f);
  EXPECT_EQ(mcv::selectTopResponsesCPU(r.data(), r.size(), 10).size(), 0u);
  r[3] = 1.f;
  EXPECT_EQ(mcv::selectTopResponsesCPU(r.data(), r.size(), 0).size(), 0u);
  EXPECT_EQ(mcv::selectTopResponsesCPU(r.data(), r.size(), -5).size(), 0u);
}

} // namespace
