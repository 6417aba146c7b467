// Locally linear landmarks (LLELandmarks.h) against a dense solve of the same L x L pencil
// (Z^T M Z, Z^T Z), and with every point its own landmark (Z = I) against exact LLE.
#include "LLEEigen.h"
#include "LLELandmarks.h"
#include "LLETestMatrices.h"

#include <Eigen/Eigenvalues>
#include <gtest/gtest.h>

#include <numeric>
#include <random>
#include <vector>

namespace
{

// n x L weights: row landmarks[l] is the unit vector e_l; every other row takes `k` random
// landmarks with positive weights summing to 1.
mcv::LandmarkWeights randomLandmarkWeights(int n, int L, int k, unsigned seed)
{
  std::mt19937 rng(seed);
  std::vector<int> order(static_cast<std::size_t>(n));
  std::iota(order.begin(), order.end(), 0);
  std::shuffle(order.begin(), order.end(), rng);
  std::vector<int> landmarkOf(static_cast<std::size_t>(n), -1);
  for (int l = 0; l < L; ++l)
  {
    landmarkOf[static_cast<std::size_t>(order[static_cast<std::size_t>(l)])] = l;
  }
  std::uniform_int_distribution<int> pick(0, L - 1);
  std::uniform_real_distribution<double> weight(0.2, 1.0);
  std::vector<Eigen::Triplet<double, int>> t;
  for (int i = 0; i < n; ++i)
  {
    if (landmarkOf[static_cast<std::size_t>(i)] >= 0)
    {
      t.emplace_back(i, landmarkOf[static_cast<std::size_t>(i)], 1.0);
      continue;
    }
    std::vector<int> nb;
    std::vector<double> w;
    while (static_cast<int>(nb.size()) < k)
    {
      const int j = pick(rng);
      if (std::find(nb.begin(), nb.end(), j) == nb.end())
      {
        nb.push_back(j);
        w.push_back(weight(rng));
      }
    }
    const double s = std::accumulate(w.begin(), w.end(), 0.0);
    for (int a = 0; a < k; ++a)
    {
      t.emplace_back(i, nb[static_cast<std::size_t>(a)], w[static_cast<std::size_t>(a)] / s);
    }
  }
  mcv::LandmarkWeights Z(n, L);
  Z.setFromTriplets(t.begin(), t.end());
  return Z;
}

// The columns of got span the same space as those of want, one by one (up to sign).
void expectSameVectors(const Eigen::MatrixXd& got, const Eigen::MatrixXd& want, double tolerance)
{
  ASSERT_EQ(got.rows(), want.rows());
  ASSERT_EQ(got.cols(), want.cols());
  for (Eigen::Index k = 0; k < want.cols(); ++k)
  {
    const double cosine = std::abs(got.col(k).dot(want.col(k))) / (got.col(k).norm() * want.col(k).norm());
    EXPECT_GT(cosine, 1.0 - tolerance) << "vector " << k;
  }
}

} // namespace

TEST(LLELandmarks, MatchesADenseSolveOfThePencil)
{
  const int n = 500, L = 60, d = 3;
  const mcv::LLESparse A = mcvtest::randomWeights({ n }, 8, 5);
  const mcv::LandmarkWeights Z = randomLandmarkWeights(n, L, 4, 9);
  const Eigen::MatrixXd Zd = Eigen::MatrixXd(Z);
  const Eigen::MatrixXd AZ = Eigen::MatrixXd(A) * Zd;
  Eigen::GeneralizedSelfAdjointEigenSolver<Eigen::MatrixXd> dense(AZ.transpose() * AZ, Zd.transpose() * Zd);
  // The constant (Z 1 = 1, M 1 = 0) first, then d distinct eigenvalues.
  ASSERT_LT(std::abs(dense.eigenvalues()[0]), 1e-10);
  for (int k = 1; k <= d; ++k)
  {
    ASSERT_GT(dense.eigenvalues()[k + 1] - dense.eigenvalues()[k], 1e-4 * dense.eigenvalues()[k]);
  }

  const mcv::LLEBottomEigen r = mcv::lleLandmarkEigenvectors(A, Z, d);
  ASSERT_TRUE(r.error.empty()) << r.error;
  ASSERT_EQ(r.vectors.rows(), n);
  ASSERT_EQ(r.vectors.cols(), d);
  for (int k = 0; k < d; ++k)
  {
    const double expected = dense.eigenvalues()[k + 1];
    EXPECT_NEAR(r.values[k], expected, 1e-8 * expected) << "k " << k;
  }
  expectSameVectors(r.vectors, Zd * dense.eigenvectors().middleCols(1, d), 1e-8);
  // LLE's constraints on Y = Z U: centred, orthonormal.
  const Eigen::MatrixXd gram = r.vectors.transpose() * r.vectors;
  EXPECT_LT((gram - Eigen::MatrixXd::Identity(d, d)).norm(), 1e-8);
  for (int k = 0; k < d; ++k)
  {
    EXPECT_LT(std::abs(r.vectors.col(k).sum()), 1e-8);
  }
}

TEST(LLELandmarks, EveryPointALandmarkIsExactLLE)
{
  const int n = 300, d = 2;
  const mcv::LLESparse A = mcvtest::randomWeights({ n }, 7, 11);
  mcv::LandmarkWeights identity(n, n);
  identity.setIdentity();
  const mcv::LLEBottomEigen exact = mcv::lleBottomEigenvectors(A, d, mcv::LLESolver::ShiftInvert);
  const mcv::LLEBottomEigen reduced = mcv::lleLandmarkEigenvectors(A, identity, d);
  ASSERT_TRUE(exact.error.empty()) << exact.error;
  ASSERT_TRUE(reduced.error.empty()) << reduced.error;
  for (int k = 0; k < d; ++k)
  {
    EXPECT_NEAR(reduced.values[k], exact.values[k], 1e-8 * exact.values[k]);
  }
  expectSameVectors(reduced.vectors, exact.vectors, 1e-8);
}

TEST(LLELandmarks, RefusesTooFewLandmarks)
{
  const mcv::LLESparse A = mcvtest::randomWeights({ 50 }, 5, 1);
  const mcv::LandmarkWeights Z = randomLandmarkWeights(50, 4, 2, 1);
  const mcv::LLEBottomEigen r = mcv::lleLandmarkEigenvectors(A, Z, 3);
  EXPECT_FALSE(r.error.empty());
  EXPECT_EQ(r.vectors.size(), 0);
}
