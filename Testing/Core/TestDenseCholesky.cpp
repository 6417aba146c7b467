// DenseCholesky.h: every kernel this CPU has factors a random SPD matrix (L L^T = A),
// agrees with the others and with Eigen's LLT to rounding, leaves the strict upper triangle
// alone, solves with the factor, and reports a matrix that is not positive definite.
#include "DenseCholesky.h"

#include <Eigen/Cholesky>
#include <gtest/gtest.h>

#include <vector>

namespace
{

Eigen::MatrixXd randomSpd(Eigen::Index n, unsigned seed)
{
  std::srand(seed);
  const Eigen::MatrixXd R = Eigen::MatrixXd::Random(n, n);
  Eigen::MatrixXd A = R * R.transpose();
  A.diagonal().array() += 1e-3 * static_cast<double>(n);
  return A;
}

std::vector<mcv::CholeskyKernel> kernels()
{
  std::vector<mcv::CholeskyKernel> k{ mcv::CholeskyKernel::Baseline };
  for (const mcv::CholeskyKernel simd : { mcv::CholeskyKernel::Avx2Fma, mcv::CholeskyKernel::Avx512 })
  {
    if (mcv::choleskyKernelAvailable(simd))
    {
      k.push_back(simd);
    }
  }
  return k;
}

} // namespace

TEST(DenseCholesky, FactorsRandomSpdMatricesLikeEigen)
{
  // Sizes below, at and above Eigen's blocking (the blocked path starts at 128 columns).
  for (const Eigen::Index n : { 1, 7, 64, 129, 300, 517 })
  {
    const Eigen::MatrixXd A = randomSpd(n, static_cast<unsigned>(n));
    const Eigen::MatrixXd reference = Eigen::LLT<Eigen::MatrixXd>(A).matrixL();
    for (const mcv::CholeskyKernel kernel : kernels())
    {
      Eigen::MatrixXd F = A;
      F.triangularView<Eigen::StrictlyUpper>().setConstant(7.0); // must stay untouched
      ASSERT_TRUE(mcv::choleskyInPlace(F, kernel)) << "n = " << n;
      const Eigen::MatrixXd L = F.triangularView<Eigen::Lower>();
      EXPECT_LE((L * L.transpose() - A).norm(), 1e-12 * A.norm()) << "n = " << n;
      EXPECT_LE((L - reference).norm(), 1e-10 * reference.norm()) << "n = " << n;
      const Eigen::MatrixXd upper = F.triangularView<Eigen::StrictlyUpper>();
      EXPECT_EQ(upper, Eigen::MatrixXd(Eigen::MatrixXd::Constant(n, n, 7.0).triangularView<Eigen::StrictlyUpper>()));
    }
  }
}

TEST(DenseCholesky, FactorsABlockOfALargerMatrix)
{
  const Eigen::MatrixXd A = randomSpd(200, 3);
  for (const mcv::CholeskyKernel kernel : kernels())
  {
    Eigen::MatrixXd big = Eigen::MatrixXd::Zero(260, 230);
    big.block(40, 20, 200, 200) = A;
    ASSERT_TRUE(mcv::choleskyInPlace(big.block(40, 20, 200, 200), kernel));
    const Eigen::MatrixXd L = big.block(40, 20, 200, 200).triangularView<Eigen::Lower>();
    EXPECT_LE((L * L.transpose() - A).norm(), 1e-12 * A.norm());
    EXPECT_EQ(big.leftCols(20).norm(), 0.0);
    EXPECT_EQ(big.topRows(40).norm(), 0.0);
  }
}

TEST(DenseCholesky, ReportsAMatrixThatIsNotPositiveDefinite)
{
  Eigen::MatrixXd A = randomSpd(150, 5);
  A(100, 100) = -1.0;
  for (const mcv::CholeskyKernel kernel : kernels())
  {
    Eigen::MatrixXd F = A;
    EXPECT_FALSE(mcv::choleskyInPlace(F, kernel));
  }
  Eigen::MatrixXd notSquare = Eigen::MatrixXd::Identity(4, 3);
  EXPECT_FALSE(mcv::choleskyInPlace(notSquare));
}

TEST(DenseCholesky, SimdKernelsRunWhereTheCpuHasThem)
{
#if defined(__x86_64__) && (defined(__GNUC__) || defined(__clang__))
  // This build compiles the SIMD units on x86-64; they must be used where the CPU allows.
  const bool avx2 = __builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma");
  EXPECT_EQ(mcv::choleskyKernelAvailable(mcv::CholeskyKernel::Avx2Fma), avx2);
  EXPECT_EQ(mcv::choleskyKernelAvailable(mcv::CholeskyKernel::Avx512), avx2 && __builtin_cpu_supports("avx512f") &&
      __builtin_cpu_supports("avx512dq") && __builtin_cpu_supports("avx512vl") &&
      __builtin_cpu_supports("avx512bw") && __builtin_cpu_supports("avx512cd"));
#else
  EXPECT_FALSE(mcv::choleskyKernelAvailable(mcv::CholeskyKernel::Avx2Fma));
  EXPECT_FALSE(mcv::choleskyKernelAvailable(mcv::CholeskyKernel::Avx512));
#endif
  EXPECT_TRUE(mcv::choleskyKernelAvailable(mcv::CholeskyKernel::Auto));
  EXPECT_TRUE(mcv::choleskyKernelAvailable(mcv::CholeskyKernel::Baseline));
}

TEST(DenseCholesky, SolvesWithTheFactorLikeEigen)
{
  for (const Eigen::Index n : { 1, 9, 130, 500 })
  {
    Eigen::MatrixXd F = randomSpd(n, 11 + static_cast<unsigned>(n));
    ASSERT_TRUE(mcv::choleskyInPlace(F, mcv::CholeskyKernel::Baseline));
    const Eigen::MatrixXd L = F.triangularView<Eigen::Lower>();
    const Eigen::VectorXd b = Eigen::VectorXd::Random(n);
    for (const mcv::CholeskyKernel kernel : kernels())
    {
      for (const bool transposed : { false, true })
      {
        Eigen::VectorXd x = b;
        mcv::solveWithFactor(F, x, transposed, kernel);
        const Eigen::VectorXd residual = transposed ? Eigen::VectorXd(L.transpose() * x - b) : Eigen::VectorXd(L * x - b);
        EXPECT_LE(residual.norm(), 1e-12 * L.norm() * x.norm()) << "n = " << n << " transposed " << transposed;
      }
    }
  }
}
