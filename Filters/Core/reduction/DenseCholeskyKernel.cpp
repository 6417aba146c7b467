// Compiled once per instruction set (Filters/Core/CMakeLists.txt: -mavx2 -mfma, and the
// AVX-512 set), each time with MCV_KERNEL_EIGEN (the name Eigen's namespace takes here) and
// MCV_KERNEL_SUFFIX (of the function names) of its own; called only where the CPU has that
// set (DenseCholesky.cpp). Eigen is included under another namespace name so that its
// templates instantiated here are distinct symbols from the baseline ones in every other
// file: the linker cannot pick one of these for baseline code (or the reverse). Include
// nothing else here: a standard-library template instantiated in this file would be a
// shared (weak) symbol built for that instruction set.
#define Eigen MCV_KERNEL_EIGEN
#include <Eigen/Cholesky>
#undef Eigen

#define MCV_KERNEL_PASTE(name, suffix) name##suffix
#define MCV_KERNEL_NAME(name, suffix) MCV_KERNEL_PASTE(name, suffix)

namespace mcv
{

bool MCV_KERNEL_NAME(choleskyInPlace, MCV_KERNEL_SUFFIX)(double* a, MCV_KERNEL_EIGEN::Index n, MCV_KERNEL_EIGEN::Index ld)
{
  using Matrix = MCV_KERNEL_EIGEN::MatrixXd;
  MCV_KERNEL_EIGEN::Map<Matrix, 0, MCV_KERNEL_EIGEN::OuterStride<>> A(a, n, n, MCV_KERNEL_EIGEN::OuterStride<>(ld));
  const MCV_KERNEL_EIGEN::LLT<MCV_KERNEL_EIGEN::Ref<Matrix, 0, MCV_KERNEL_EIGEN::OuterStride<>>> factor(A);
  return factor.info() == MCV_KERNEL_EIGEN::Success;
}

void MCV_KERNEL_NAME(solveWithFactor, MCV_KERNEL_SUFFIX)(const double* f, MCV_KERNEL_EIGEN::Index n, MCV_KERNEL_EIGEN::Index ld, double* x,
  bool transposed)
{
  using Matrix = MCV_KERNEL_EIGEN::MatrixXd;
  const MCV_KERNEL_EIGEN::Map<const Matrix, 0, MCV_KERNEL_EIGEN::OuterStride<>> F(
    f, n, n, MCV_KERNEL_EIGEN::OuterStride<>(ld));
  MCV_KERNEL_EIGEN::Map<MCV_KERNEL_EIGEN::VectorXd> v(x, n);
  if (transposed)
  {
    F.triangularView<MCV_KERNEL_EIGEN::Lower>().transpose().solveInPlace(v);
  }
  else
  {
    F.triangularView<MCV_KERNEL_EIGEN::Lower>().solveInPlace(v);
  }
}

} // namespace mcv
