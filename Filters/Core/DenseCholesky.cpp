#include "DenseCholesky.h"

#include <Eigen/Cholesky>

#ifdef MCV_AVX2_CHOLESKY
namespace mcv
{
// DenseCholeskyAvx2.cpp: column-major, leading dimension ld.
bool choleskyInPlaceAvx2Fma(double* a, Eigen::Index n, Eigen::Index ld);
void solveWithFactorAvx2Fma(const double* f, Eigen::Index n, Eigen::Index ld, double* x, bool transposed);
}
#endif

namespace mcv
{

bool avx2CholeskyAvailable()
{
#ifdef MCV_AVX2_CHOLESKY
  static const bool ok = __builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma");
  return ok;
#else
  return false;
#endif
}

bool choleskyInPlace(Eigen::Ref<Eigen::MatrixXd> A, CholeskyKernel kernel)
{
  if (A.rows() != A.cols())
  {
    return false;
  }
#ifdef MCV_AVX2_CHOLESKY
  if (kernel != CholeskyKernel::Baseline && avx2CholeskyAvailable())
  {
    return choleskyInPlaceAvx2Fma(A.data(), A.rows(), A.outerStride());
  }
#endif
  const Eigen::LLT<Eigen::Ref<Eigen::MatrixXd>> factor(A);
  return factor.info() == Eigen::Success;
}

void solveWithFactor(
  const Eigen::Ref<const Eigen::MatrixXd>& F, Eigen::Ref<Eigen::VectorXd> x, bool transposed, CholeskyKernel kernel)
{
#ifdef MCV_AVX2_CHOLESKY
  if (kernel != CholeskyKernel::Baseline && avx2CholeskyAvailable())
  {
    solveWithFactorAvx2Fma(F.data(), F.rows(), F.outerStride(), x.data(), transposed);
    return;
  }
#endif
  if (transposed)
  {
    F.triangularView<Eigen::Lower>().transpose().solveInPlace(x);
  }
  else
  {
    F.triangularView<Eigen::Lower>().solveInPlace(x);
  }
}

} // namespace mcv
