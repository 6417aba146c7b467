#include "SymmetricEigenvalues.h"

#include <Eigen/Eigenvalues>

#ifdef _OPENMP
#include <omp.h>
#endif

namespace mcv
{

namespace
{
// Below this size the threads' start and barriers cost more than the reduction: Eigen's.
constexpr Eigen::Index kSmallForThreads = 128;
// With fewer threads than this, Eigen's (its symmetric products read half the matrix, so one
// thread of it is ~1.4x faster than one of the full-storage reduction; two threads of a busy
// 2-core machine spin at the barriers).
constexpr int kFewestThreads = 4;
} // namespace

bool symmetricEigenvalues(const Eigen::MatrixXd& A, Eigen::VectorXd& ascending)
{
#ifdef _OPENMP
  return symmetricEigenvalues(A, ascending, omp_get_max_threads());
#else
  return symmetricEigenvalues(A, ascending, 1);
#endif
}

bool symmetricEigenvalues(const Eigen::MatrixXd& A, Eigen::VectorXd& ascending, int threads)
{
  const Eigen::Index n = A.rows();
  ascending.resize(n);
  if (n == 0)
  {
    return true;
  }
  if (A.cols() != n || !A.triangularView<Eigen::Lower>().toDenseMatrix().allFinite())
  {
    return false;
  }
  if (n < kSmallForThreads || threads < kFewestThreads)
  {
    Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig(A, Eigen::EigenvaluesOnly);
    if (eig.info() != Eigen::Success)
    {
      return false;
    }
    ascending = eig.eigenvalues();
    return true;
  }
  // Full symmetric storage from the lower triangle, scaled to at most 1 in magnitude as Eigen
  // scales before its reduction (no overflow in the norms).
  Eigen::MatrixXd a = A.selfadjointView<Eigen::Lower>();
  const double scale = a.cwiseAbs().maxCoeff();
  if (scale == 0.0)
  {
    ascending.setZero();
    return true;
  }
  a /= scale;

  Eigen::VectorXd diag(n), sub(n - 1), p(n);
  // Two barriers per column (after p, after the update): every thread forms the reflector and
  // w itself (O(n) each) instead of waiting for one thread to share them.
#pragma omp parallel num_threads(threads)
  {
    Eigen::VectorXd v(n), w(n);
    for (Eigen::Index k = 0; k + 2 < n; ++k)
    {
      // Column k below the diagonal becomes beta e1 through H = I - tau v v^T (v(0) = 1);
      // then the trailing block A22 <- H A22 H as A22 - v w^T - w v^T with p = tau A22 v,
      // w = p - (tau / 2)(p^T v) v.
      const Eigen::Index m = n - k - 1;
      double tau = 0.0, beta = 0.0;
      auto vk = v.head(m);
      vk = a.col(k).tail(m);
      vk.makeHouseholderInPlace(tau, beta);
      vk[0] = 1.0;
#pragma omp single nowait
      {
        diag[k] = a(k, k);
        sub[k] = beta;
      }
      if (tau == 0.0)
      {
        continue; // every thread alike: A22 is left as it is
      }
      // p = tau A22 v, by columns: A22 is symmetric, so p(i) is column i's dot with v.
#pragma omp for schedule(static)
      for (Eigen::Index i = 0; i < m; ++i)
      {
        p[i] = tau * a.col(k + 1 + i).tail(m).dot(vk);
      }
      const double alpha = -0.5 * tau * p.head(m).dot(vk);
      auto wk = w.head(m);
      wk = p.head(m) + alpha * vk;
#pragma omp for schedule(static)
      for (Eigen::Index j = 0; j < m; ++j)
      {
        a.col(k + 1 + j).tail(m) -= vk * wk[j] + wk * vk[j];
      }
    }
  }
  diag[n - 2] = a(n - 2, n - 2);
  sub[n - 2] = a(n - 1, n - 2);
  diag[n - 1] = a(n - 1, n - 1);
  Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> tri;
  tri.computeFromTridiagonal(diag, sub, Eigen::EigenvaluesOnly);
  if (tri.info() != Eigen::Success)
  {
    return false;
  }
  ascending = tri.eigenvalues() * scale;
  return true;
}

} // namespace mcv
