// LLE's eigen step (LLEEigen.h) against a dense Eigen solve of M = A^T A: every solver must
// find the same bottom eigenvalues and eigenvectors, and exclude the constant vector even
// when M has more than one null vector.
#include "LLEEigen.h"
#include "LLETestMatrices.h"

#include <Eigen/Eigenvalues>
#include <gtest/gtest.h>

TEST(LLEEigen, EverySolverMatchesADenseSolve)
{
  const int n = 400, d = 3;
  const mcv::LLESparse A = mcvtest::randomWeights({ n }, 8, 3);
  const Eigen::MatrixXd M = Eigen::MatrixXd(A).transpose() * Eigen::MatrixXd(A);
  Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> dense(M);
  // Dense: eigenvalue 0 is the constant vector (M 1 = 0); the next d are the answer.
  ASSERT_LT(dense.eigenvalues()[0], 1e-10);
  ASSERT_GT(dense.eigenvalues()[1], 1e-6);
  for (int k = 1; k <= d; ++k)
  {
    // Distinct eigenvalues, so each eigenvector is defined up to sign.
    ASSERT_GT(dense.eigenvalues()[k + 1] - dense.eigenvalues()[k], 1e-4 * dense.eigenvalues()[k]);
  }
  // (FactorA alone is not exact on such a well-separated spectrum; Auto must notice.)
  for (auto solver : { mcv::LLESolver::Auto, mcv::LLESolver::ShiftInvert, mcv::LLESolver::Lanczos })
  {
    const mcv::LLEBottomEigen r = mcv::lleBottomEigenvectors(A, d, solver);
    ASSERT_TRUE(r.error.empty()) << static_cast<int>(solver) << ": " << r.error;
    ASSERT_EQ(r.vectors.rows(), n);
    ASSERT_EQ(r.vectors.cols(), d);
    for (int k = 0; k < d; ++k)
    {
      const double expected = dense.eigenvalues()[k + 1];
      EXPECT_NEAR(r.values[k], expected, 1e-8 * expected + 1e-12) << "solver " << static_cast<int>(solver) << " k " << k;
      const double cosine = std::abs(r.vectors.col(k).dot(dense.eigenvectors().col(k + 1)));
      EXPECT_GT(cosine, 1.0 - 1e-8) << "solver " << static_cast<int>(solver) << " k " << k;
    }
  }
}

TEST(LLEEigen, ClosedSetsGiveNonConstantNullVectors)
{
  // Two closed sets: M's null space is spanned by the two block indicators. LLE's answer
  // for the first coordinate is their centred difference, never the constant vector.
  const int d = 2;
  const mcv::LLESparse A = mcvtest::randomWeights({ 150, 250 }, 6, 7);
  const int n = static_cast<int>(A.rows());
  for (auto solver : { mcv::LLESolver::Auto, mcv::LLESolver::ShiftInvert })
  {
    const mcv::LLEBottomEigen r = mcv::lleBottomEigenvectors(A, d, solver);
    ASSERT_TRUE(r.error.empty()) << static_cast<int>(solver) << ": " << r.error;
    EXPECT_LT(std::abs(r.values[0]), 1e-10);
    EXPECT_GT(r.values[1], 1e-6);
    for (int k = 0; k < d; ++k)
    {
      EXPECT_LT(std::abs(r.vectors.col(k).sum()), 1e-8);           // orthogonal to 1
      EXPECT_NEAR(r.vectors.col(k).norm(), 1.0, 1e-10);
    }
    // Constant on each block, unit norm, zero sum: +-sqrt(250/(150*400)) on the first.
    const double a = std::sqrt(250.0 / (150.0 * n));
    const double b = std::sqrt(150.0 / (250.0 * n));
    for (int i = 0; i < n; ++i)
    {
      EXPECT_NEAR(std::abs(r.vectors(i, 0)), i < 150 ? a : b, 1e-6);
    }
  }
}
