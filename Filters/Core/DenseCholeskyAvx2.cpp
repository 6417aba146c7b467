// Compiled with -mavx2 -mfma (Filters/Core/CMakeLists.txt), called only where the CPU has
// both (DenseCholesky.cpp). Eigen is included under another namespace name so that its
// templates instantiated here, with AVX2 code, are distinct symbols from the baseline ones
// in every other file: the linker cannot pick one of these for baseline code (or the
// reverse). Include nothing else here: a standard-library template instantiated in this
// file would be a shared (weak) symbol built for AVX2.
#define Eigen mcvEigenAvx2Fma
#include <Eigen/Cholesky>
#undef Eigen

namespace mcv
{

bool choleskyInPlaceAvx2Fma(double* a, mcvEigenAvx2Fma::Index n, mcvEigenAvx2Fma::Index ld)
{
  using Matrix = mcvEigenAvx2Fma::MatrixXd;
  mcvEigenAvx2Fma::Map<Matrix, 0, mcvEigenAvx2Fma::OuterStride<>> A(a, n, n, mcvEigenAvx2Fma::OuterStride<>(ld));
  const mcvEigenAvx2Fma::LLT<mcvEigenAvx2Fma::Ref<Matrix, 0, mcvEigenAvx2Fma::OuterStride<>>> factor(A);
  return factor.info() == mcvEigenAvx2Fma::Success;
}

void solveWithFactorAvx2Fma(const double* f, mcvEigenAvx2Fma::Index n, mcvEigenAvx2Fma::Index ld, double* x,
  bool transposed)
{
  using Matrix = mcvEigenAvx2Fma::MatrixXd;
  const mcvEigenAvx2Fma::Map<const Matrix, 0, mcvEigenAvx2Fma::OuterStride<>> F(
    f, n, n, mcvEigenAvx2Fma::OuterStride<>(ld));
  mcvEigenAvx2Fma::Map<mcvEigenAvx2Fma::VectorXd> v(x, n);
  if (transposed)
  {
    F.triangularView<mcvEigenAvx2Fma::Lower>().transpose().solveInPlace(v);
  }
  else
  {
    F.triangularView<mcvEigenAvx2Fma::Lower>().solveInPlace(v);
  }
}

} // namespace mcv
