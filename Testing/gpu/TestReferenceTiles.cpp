// The GPU placement's reference tiles, built on the host (reduction/cuda/ReferenceTiles.h; no GPU
// needed): the order is a permutation; every tile's box is exactly the minimum and maximum
// of its references, its centroid their mean, its radius the smallest float at or above
// their largest norm; the norms are the double sums rounded; two far clusters of one tile
// each are split apart; a reference that is not finite makes its tile's box and radius
// infinite (that tile is never skipped).
#include "cuda/ReferenceTiles.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>
#include <random>
#include <vector>

namespace
{
using mcv::cuda::kReferenceTile;

std::vector<float> clustered(std::size_t M, int D, std::mt19937& rng)
{
  std::normal_distribution<float> g(0.f, 1.f);
  std::vector<float> centres(static_cast<std::size_t>(20 * D));
  for (float& c : centres)
    c = 5.f * g(rng);
  std::vector<float> X(M * static_cast<std::size_t>(D));
  for (std::size_t i = 0; i < M; ++i)
    for (int c = 0; c < D; ++c)
      X[i * D + c] = centres[(i % 20) * D + c] + g(rng);
  return X;
}

void expectConsistent(const std::vector<float>& X, std::size_t M, int D, int DP, const mcv::cuda::ReferenceTiles& t)
{
  const std::size_t tiles = (M + kReferenceTile - 1) / kReferenceTile;
  ASSERT_EQ(t.tiles(), tiles);
  ASSERT_EQ(t.order.size(), M);
  ASSERT_EQ(t.centroids.size(), tiles * DP);
  ASSERT_EQ(t.lo.size(), tiles * DP);
  ASSERT_EQ(t.hi.size(), tiles * DP);
  ASSERT_EQ(t.centroidNorms.size(), tiles);
  ASSERT_EQ(t.norms.size(), M);
  std::vector<unsigned> sorted = t.order;
  std::sort(sorted.begin(), sorted.end());
  for (std::size_t i = 0; i < M; ++i)
    ASSERT_EQ(sorted[i], i) << "not a permutation";
  for (std::size_t k = 0; k < tiles; ++k)
  {
    const std::size_t first = k * kReferenceTile, last = std::min(M, first + kReferenceTile);
    bool finite = true;
    double largest = 0;
    for (std::size_t i = first; i < last; ++i)
    {
      double sum = 0;
      for (int c = 0; c < D; ++c)
      {
        const double v = X[static_cast<std::size_t>(t.order[i]) * D + c];
        finite = finite && std::isfinite(v);
        sum += v * v;
      }
      if (std::isfinite(sum))
        EXPECT_EQ(t.norms[i], static_cast<float>(sum));
      largest = std::max(largest, std::sqrt(sum));
    }
    if (!finite)
    {
      for (int c = 0; c < D; ++c)
      {
        EXPECT_EQ(t.lo[k * DP + c], -std::numeric_limits<float>::infinity());
        EXPECT_EQ(t.hi[k * DP + c], std::numeric_limits<float>::infinity());
      }
      EXPECT_EQ(t.radius[k], std::numeric_limits<float>::infinity());
      continue;
    }
    for (int c = 0; c < DP; ++c)
    {
      float lo = 0, hi = 0;
      double mean = 0;
      if (c < D)
      {
        lo = std::numeric_limits<float>::infinity();
        hi = -lo;
        for (std::size_t i = first; i < last; ++i)
        {
          const float v = X[static_cast<std::size_t>(t.order[i]) * D + c];
          lo = std::min(lo, v);
          hi = std::max(hi, v);
          mean += v;
        }
        mean /= static_cast<double>(last - first);
      }
      EXPECT_EQ(t.lo[k * DP + c], lo) << "tile " << k << " coordinate " << c;
      EXPECT_EQ(t.hi[k * DP + c], hi);
      EXPECT_EQ(t.centroids[k * DP + c], static_cast<float>(mean));
    }
    // The radius bounds every norm from above and is the smallest float that does.
    EXPECT_GE(static_cast<double>(t.radius[k]), largest);
    EXPECT_LT(static_cast<double>(std::nextafter(t.radius[k], 0.f)), largest);
    double centroid = 0;
    for (int c = 0; c < DP; ++c)
      centroid += static_cast<double>(t.centroids[k * DP + c]) * t.centroids[k * DP + c];
    EXPECT_EQ(t.centroidNorms[k], static_cast<float>(centroid));
  }
}
} // namespace

TEST(ReferenceTiles, BoxesCentroidsNormsAndRadiiOfEveryTile)
{
  std::mt19937 rng(5);
  for (auto [M, D, DP] : { std::tuple<std::size_t, int, int>{ 10000, 24, 24 }, { 1000, 6, 8 }, { 1037, 23, 24 } })
  {
    SCOPED_TRACE("M = " + std::to_string(M) + ", D = " + std::to_string(D));
    const std::vector<float> X = clustered(M, D, rng);
    expectConsistent(X, M, D, DP, mcv::cuda::buildReferenceTiles(X.data(), M, D, DP));
  }
}

TEST(ReferenceTiles, TwoFarClustersFillOneTileEach)
{
  // 32 points near (-100, 0, 0) and 32 near (+100, 0, 0), interleaved in index order: the
  // split across the principal axis puts each cluster in its own tile.
  std::mt19937 rng(9);
  std::normal_distribution<float> g(0.f, 1.f);
  const std::size_t M = 2 * kReferenceTile;
  std::vector<float> X(M * 3);
  for (std::size_t i = 0; i < M; ++i)
  {
    X[i * 3] = (i % 2 ? 100.f : -100.f) + g(rng);
    X[i * 3 + 1] = g(rng);
    X[i * 3 + 2] = g(rng);
  }
  const mcv::cuda::ReferenceTiles t = mcv::cuda::buildReferenceTiles(X.data(), M, 3, 8);
  expectConsistent(X, M, 3, 8, t);
  for (std::size_t k = 0; k < 2; ++k)
  {
    const unsigned parity = t.order[k * kReferenceTile] % 2;
    for (std::size_t i = k * kReferenceTile; i < (k + 1) * kReferenceTile; ++i)
      EXPECT_EQ(t.order[i] % 2, parity) << "position " << i;
  }
  EXPECT_LT(t.hi[0] - t.lo[0], 20.f);
  EXPECT_LT(t.hi[8] - t.lo[8], 20.f);
}

TEST(ReferenceTiles, ANonFiniteReferenceMakesItsTileUnbounded)
{
  std::mt19937 rng(11);
  const std::size_t M = 40 * kReferenceTile;
  std::vector<float> X = clustered(M, 6, rng);
  X[123 * 6 + 2] = std::numeric_limits<float>::quiet_NaN();
  X[777 * 6 + 4] = std::numeric_limits<float>::infinity();
  const mcv::cuda::ReferenceTiles t = mcv::cuda::buildReferenceTiles(X.data(), M, 6, 8);
  expectConsistent(X, M, 6, 8, t);
  int unbounded = 0;
  for (std::size_t k = 0; k < t.tiles(); ++k)
    unbounded += std::isinf(t.radius[k]);
  EXPECT_GE(unbounded, 1);
  EXPECT_LE(unbounded, 2);
}
