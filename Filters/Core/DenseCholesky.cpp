#include "DenseCholesky.h"

#include <Eigen/Cholesky>

#include <cstdlib>
#include <cstring>

#ifdef MCV_SIMD_CHOLESKY
namespace mcv
{
// DenseCholeskyKernel.cpp, built twice: column-major, leading dimension ld.
bool choleskyInPlaceAvx2Fma(double* a, Eigen::Index n, Eigen::Index ld);
void solveWithFactorAvx2Fma(const double* f, Eigen::Index n, Eigen::Index ld, double* x, bool transposed);
bool choleskyInPlaceAvx512(double* a, Eigen::Index n, Eigen::Index ld);
void solveWithFactorAvx512(const double* f, Eigen::Index n, Eigen::Index ld, double* x, bool transposed);
}
#endif

namespace mcv
{

bool choleskyKernelAvailable(CholeskyKernel kernel)
{
#ifdef MCV_SIMD_CHOLESKY
  static const bool avx2 = __builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma");
  static const bool avx512 = avx2 && __builtin_cpu_supports("avx512f") && __builtin_cpu_supports("avx512dq") &&
    __builtin_cpu_supports("avx512vl") && __builtin_cpu_supports("avx512bw") && __builtin_cpu_supports("avx512cd");
  switch (kernel)
  {
    case CholeskyKernel::Avx2Fma:
      return avx2;
    case CholeskyKernel::Avx512:
      return avx512;
    default:
      return true;
  }
#else
  return kernel == CholeskyKernel::Auto || kernel == CholeskyKernel::Baseline;
#endif
}

namespace
{
// The kernel a request runs: the one asked for where this CPU has it, else the widest
// available below it (Auto: the widest of all).
CholeskyKernel resolve(CholeskyKernel kernel)
{
  // MCV_CHOLESKY_KERNEL=baseline makes Auto the plain Eigen LLT (docs/benchmarks-libraries.md).
  static const bool forceBaseline = [] {
    const char* v = std::getenv("MCV_CHOLESKY_KERNEL");
    return v && std::strcmp(v, "baseline") == 0;
  }();
  if (kernel == CholeskyKernel::Auto && forceBaseline)
  {
    return CholeskyKernel::Baseline;
  }
  if ((kernel == CholeskyKernel::Auto || kernel == CholeskyKernel::Avx512) &&
    choleskyKernelAvailable(CholeskyKernel::Avx512))
  {
    return CholeskyKernel::Avx512;
  }
  if (kernel != CholeskyKernel::Baseline && choleskyKernelAvailable(CholeskyKernel::Avx2Fma))
  {
    return CholeskyKernel::Avx2Fma;
  }
  return CholeskyKernel::Baseline;
}
} // namespace

bool choleskyInPlace(Eigen::Ref<Eigen::MatrixXd> A, CholeskyKernel kernel)
{
  if (A.rows() != A.cols())
  {
    return false;
  }
  switch (resolve(kernel))
  {
#ifdef MCV_SIMD_CHOLESKY
    case CholeskyKernel::Avx512:
      return choleskyInPlaceAvx512(A.data(), A.rows(), A.outerStride());
    case CholeskyKernel::Avx2Fma:
      return choleskyInPlaceAvx2Fma(A.data(), A.rows(), A.outerStride());
#endif
    default:
    {
      const Eigen::LLT<Eigen::Ref<Eigen::MatrixXd>> factor(A);
      return factor.info() == Eigen::Success;
    }
  }
}

void solveWithFactor(
  const Eigen::Ref<const Eigen::MatrixXd>& F, Eigen::Ref<Eigen::VectorXd> x, bool transposed, CholeskyKernel kernel)
{
  switch (resolve(kernel))
  {
#ifdef MCV_SIMD_CHOLESKY
    case CholeskyKernel::Avx512:
      solveWithFactorAvx512(F.data(), F.rows(), F.outerStride(), x.data(), transposed);
      return;
    case CholeskyKernel::Avx2Fma:
      solveWithFactorAvx2Fma(F.data(), F.rows(), F.outerStride(), x.data(), transposed);
      return;
#endif
    default:
      if (transposed)
      {
        F.triangularView<Eigen::Lower>().transpose().solveInPlace(x);
      }
      else
      {
        F.triangularView<Eigen::Lower>().solveInPlace(x);
      }
  }
}

} // namespace mcv
