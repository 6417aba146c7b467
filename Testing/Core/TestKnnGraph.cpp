// The kNN graph of Isomap and LLE (buildKnnGraph) against a plain full scan, on both of its
// backends: the kd-tree (6-D) and the tiled brute force (24-D).
#include "ExactKnn.h"
#include "FeatureKnn.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <vector>

namespace
{

std::vector<float> randomPoints(std::size_t n, int D, unsigned seed)
{
  std::mt19937 rng(seed);
  std::normal_distribution<float> gauss(0.f, 1.f);
  std::vector<float> x(n * static_cast<std::size_t>(D));
  for (float& v : x)
  {
    v = gauss(rng);
  }
  return x;
}

// Point i's k nearest other points, distances in long double (on random data no two are
// within rounding of each other).
std::vector<std::pair<long double, std::uint32_t>> naiveNeighbours(
  const std::vector<float>& x, std::size_t n, int D, std::size_t i, int k)
{
  std::vector<std::pair<long double, std::uint32_t>> all;
  for (std::size_t j = 0; j < n; ++j)
  {
    if (j == i)
    {
      continue;
    }
    long double s = 0;
    for (int c = 0; c < D; ++c)
    {
      const long double t = static_cast<long double>(x[i * D + c]) - x[j * D + c];
      s += t * t;
    }
    all.emplace_back(std::sqrt(s), static_cast<std::uint32_t>(j));
  }
  std::partial_sort(all.begin(), all.begin() + k, all.end());
  all.resize(static_cast<std::size_t>(k));
  return all;
}

class KnnGraphBackends : public ::testing::TestWithParam<int>
{
};

TEST_P(KnnGraphBackends, MatchesAFullScan)
{
  const int D = GetParam();
  const std::size_t n = 700;
  const int k = 10;
  const std::vector<float> x = randomPoints(n, D, 5 + D);
  const mcv::KnnGraph g = mcv::buildKnnGraph(x.data(), n, D, k);
  ASSERT_EQ(g.neighbors.size(), n * k);
  for (std::size_t i = 0; i < n; ++i)
  {
    const auto expected = naiveNeighbours(x, n, D, i, k);
    for (int j = 0; j < k; ++j)
    {
      ASSERT_EQ(g.neighbors[i * k + j], expected[j].second) << "point " << i << ", neighbour " << j;
      EXPECT_NEAR(g.distances[i * k + j], static_cast<double>(expected[j].first), 1e-5 * static_cast<double>(expected[j].first));
    }
  }
}

// 6-D takes the kd-tree, 24-D the brute force: both backends are covered.
INSTANTIATE_TEST_SUITE_P(KdTreeAndBruteForce, KnnGraphBackends, ::testing::Values(6, 24));

TEST(KnnGraph, BothDimensionsTakeTheExpectedBackend)
{
  EXPECT_EQ(mcv::chooseKnnMethod(6), mcv::KnnMethod::KdTree);
  EXPECT_EQ(mcv::chooseKnnMethod(24), mcv::KnnMethod::BruteForce);
  EXPECT_EQ(mcv::chooseKnnMethod(24, mcv::kMaxKnnCandidates), mcv::KnnMethod::KdTree) << "k beyond the candidate lists";
  EXPECT_EQ(mcv::chooseKnnMethod(6, 10, 500), mcv::KnnMethod::BruteForce) << "few references (LLE's landmarks)";
  EXPECT_EQ(mcv::chooseKnnMethod(6, 10, 10000), mcv::KnnMethod::KdTree);
}

TEST(KnnGraph, ManyNeighboursInHighDimension)
{
  // k + 1 beyond the brute force's candidate lists: the kd-tree answers instead.
  const int D = 24, k = mcv::kMaxKnnCandidates;
  const std::size_t n = 300;
  const std::vector<float> x = randomPoints(n, D, 3);
  const mcv::KnnGraph g = mcv::buildKnnGraph(x.data(), n, D, k);
  for (std::size_t i = 0; i < n; i += 7)
  {
    const auto expected = naiveNeighbours(x, n, D, i, k);
    for (int j = 0; j < k; ++j)
    {
      ASSERT_EQ(g.neighbors[i * k + j], expected[j].second) << "point " << i << ", neighbour " << j;
    }
  }
}

TEST(KnnGraph, ADuplicatePointIsANeighbourButNeverThePointItself)
{
  for (int D : { 6, 24 })
  {
    SCOPED_TRACE("D " + std::to_string(D));
    const std::size_t n = 300;
    std::vector<float> x = randomPoints(n, D, 11);
    std::copy(x.begin() + 7 * D, x.begin() + 8 * D, x.begin() + 200 * D); // point 200 = point 7
    const mcv::KnnGraph g = mcv::buildKnnGraph(x.data(), n, D, 4);
    for (std::size_t i = 0; i < n; ++i)
    {
      for (int j = 0; j < 4; ++j)
      {
        EXPECT_NE(g.neighbors[i * 4 + j], i) << "point " << i;
      }
    }
    EXPECT_EQ(g.neighbors[7 * 4], 200u);
    EXPECT_EQ(g.neighbors[200 * 4], 7u);
    EXPECT_EQ(g.distances[7 * 4], 0.f);
  }
}

TEST_P(KnnGraphBackends, SeparateClustersAreJoinedByTheirClosestPair)
{
  const int D = GetParam();
  // 200 points around the origin and 50 around (30, 30, ...): two components of the graph.
  const std::size_t big = 200, small = 50, n = big + small;
  std::vector<float> x = randomPoints(n, D, 21 + D);
  for (std::size_t i = big; i < n; ++i)
  {
    for (int c = 0; c < D; ++c)
    {
      x[i * D + c] += 30.f;
    }
  }
  const mcv::KnnGraph g = mcv::buildKnnGraph(x.data(), n, D, 5);
  std::size_t components = 0;
  const std::vector<mcv::GraphEdge> joins = mcv::joinKnnComponents(x.data(), n, D, g, &components);
  EXPECT_EQ(components, 2u);
  ASSERT_EQ(joins.size(), 1u);
  // The closest pair between the clusters, by a full scan.
  long double bestD = -1;
  std::size_t bestA = 0, bestB = 0;
  for (std::size_t a = big; a < n; ++a)
  {
    for (std::size_t b = 0; b < big; ++b)
    {
      long double s = 0;
      for (int c = 0; c < D; ++c)
      {
        const long double t = static_cast<long double>(x[a * D + c]) - x[b * D + c];
        s += t * t;
      }
      if (bestD < 0 || s < bestD)
      {
        bestD = s;
        bestA = a;
        bestB = b;
      }
    }
  }
  const std::size_t lo = std::min<std::size_t>(joins[0].a, joins[0].b), hi = std::max<std::size_t>(joins[0].a, joins[0].b);
  EXPECT_EQ(lo, bestB);
  EXPECT_EQ(hi, bestA);
  EXPECT_NEAR(joins[0].length, static_cast<double>(std::sqrt(bestD)), 1e-4 * static_cast<double>(std::sqrt(bestD)));

  // A connected graph needs nothing.
  const mcv::KnnGraph one = mcv::buildKnnGraph(x.data(), big, D, 5);
  EXPECT_TRUE(mcv::joinKnnComponents(x.data(), big, D, one, &components).empty());
  EXPECT_EQ(components, 1u);
}

} // namespace
