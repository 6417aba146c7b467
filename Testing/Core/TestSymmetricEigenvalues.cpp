// The values-only symmetric eigen-solver of landmark Isomap's MDS (SymmetricEigenvalues.h):
// known spectra, Eigen's answer, and the same bits on any number of threads.
#include "SymmetricEigenvalues.h"

#include <gtest/gtest.h>

#include <Eigen/Eigenvalues>
#include <Eigen/QR>

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>

namespace
{
// Q diag(values) Q^T with Q orthogonal (the Q of a random matrix's QR), seeded.
Eigen::MatrixXd withSpectrum(const Eigen::VectorXd& values, unsigned seed)
{
  std::mt19937 rng(seed);
  std::normal_distribution<double> normal;
  const Eigen::Index n = values.size();
  Eigen::MatrixXd g(n, n);
  for (Eigen::Index i = 0; i < g.size(); ++i)
  {
    g.data()[i] = normal(rng);
  }
  const Eigen::MatrixXd q = Eigen::HouseholderQR<Eigen::MatrixXd>(g).householderQ();
  Eigen::MatrixXd a = q * values.asDiagonal() * q.transpose();
  return 0.5 * (a + a.transpose());
}

// Landmark MDS's B: -1/2 J D J of squared distances between random points (indefinite for a
// non-Euclidean D; here Euclidean, so positive semi-definite of rank <= dim).
Eigen::MatrixXd doubleCentred(Eigen::Index n, int dim, unsigned seed)
{
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  Eigen::MatrixXd x(n, dim);
  for (Eigen::Index i = 0; i < x.size(); ++i)
  {
    x.data()[i] = u(rng);
  }
  Eigen::MatrixXd d(n, n);
  for (Eigen::Index a = 0; a < n; ++a)
  {
    for (Eigen::Index b = 0; b < n; ++b)
    {
      // Squared path lengths of a chain through the points: not Euclidean, so B has
      // negative eigenvalues too, as geodesic distances give.
      const double g = (x.row(a) - x.row(b)).lpNorm<1>();
      d(a, b) = g * g;
    }
  }
  Eigen::MatrixXd b = d;
  b.rowwise() -= d.colwise().mean();
  b.colwise() -= b.rowwise().mean();
  return -0.5 * b;
}

double spectralRadius(const Eigen::VectorXd& v)
{
  return v.cwiseAbs().maxCoeff();
}
} // namespace

TEST(SymmetricEigenvalues, KnownSpectrum)
{
  // 300 values with repeats, zeros and both signs, in shuffled order.
  Eigen::VectorXd values(300);
  for (Eigen::Index i = 0; i < values.size(); ++i)
  {
    values[i] = (i % 7 == 0) ? 0.0 : (i % 3 == 0 ? -1.0 : 1.0) * std::ldexp(1.0 + i % 11, static_cast<int>(i % 5));
  }
  const Eigen::MatrixXd a = withSpectrum(values, 3);
  Eigen::VectorXd expected = values;
  std::sort(expected.data(), expected.data() + expected.size());
  for (int threads : { 4, 6 })
  {
    Eigen::VectorXd got;
    ASSERT_TRUE(mcv::symmetricEigenvalues(a, got, threads));
    ASSERT_EQ(got.size(), expected.size());
    EXPECT_LE((got - expected).cwiseAbs().maxCoeff(), 1e-12 * spectralRadius(expected)) << threads << " threads";
  }
}

TEST(SymmetricEigenvalues, EigensOnMdsMatricesThreadCountsGiveTheSameBits)
{
  for (Eigen::Index n : { Eigen::Index(128), Eigen::Index(257), Eigen::Index(500) })
  {
    const Eigen::MatrixXd b = doubleCentred(n, 24, static_cast<unsigned>(n));
    Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig(b, Eigen::EigenvaluesOnly);
    ASSERT_EQ(eig.info(), Eigen::Success);
    EXPECT_LT(eig.eigenvalues()[0], 0.0) << "the test wants an indefinite B";
    Eigen::VectorXd four, five, one;
    ASSERT_TRUE(mcv::symmetricEigenvalues(b, four, 4));
    ASSERT_TRUE(mcv::symmetricEigenvalues(b, five, 5));
    ASSERT_TRUE(mcv::symmetricEigenvalues(b, one, 1)); // Eigen's solver
    const double r = spectralRadius(eig.eigenvalues());
    EXPECT_LE((four - eig.eigenvalues()).cwiseAbs().maxCoeff(), 1e-12 * r) << n;
    EXPECT_EQ((one - eig.eigenvalues()).cwiseAbs().maxCoeff(), 0.0) << n;
    EXPECT_TRUE(four == five) << n << ": the values depend on the thread count";
    // The variance retained sums the positive part: equal to 1e-8 relative, as Isomap needs.
    double pf = 0, pe = 0;
    for (Eigen::Index k = 0; k < n; ++k)
    {
      pf += std::max(0.0, four[k]);
      pe += std::max(0.0, eig.eigenvalues()[k]);
    }
    EXPECT_LE(std::abs(pf - pe), 1e-8 * pe) << n;
  }
}

TEST(SymmetricEigenvalues, SmallZeroAndNonFinite)
{
  Eigen::MatrixXd two(2, 2);
  two << 2, 1, 1, 2; // eigenvalues 1 and 3
  Eigen::VectorXd v;
  ASSERT_TRUE(mcv::symmetricEigenvalues(two, v, 8));
  EXPECT_NEAR(v[0], 1.0, 1e-15);
  EXPECT_NEAR(v[1], 3.0, 1e-15);

  ASSERT_TRUE(mcv::symmetricEigenvalues(Eigen::MatrixXd::Zero(200, 200), v, 4));
  EXPECT_EQ(v.size(), 200);
  EXPECT_EQ(v.cwiseAbs().maxCoeff(), 0.0);

  Eigen::MatrixXd bad = Eigen::MatrixXd::Identity(200, 200);
  bad(150, 3) = std::numeric_limits<double>::quiet_NaN();
  EXPECT_FALSE(mcv::symmetricEigenvalues(bad, v, 4));

  ASSERT_TRUE(mcv::symmetricEigenvalues(Eigen::MatrixXd(0, 0), v, 4));
  EXPECT_EQ(v.size(), 0);
}
