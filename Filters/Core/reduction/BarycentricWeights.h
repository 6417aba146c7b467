// The regularised barycentric weights that LLE, locally linear landmarks and the
// out-of-sample step all use: the w with sum w = 1 that minimise |x - sum_j w_j x_j|^2,
// from the k differences z_j = x_j - x (rows of Z):
//   G = Z Z^T, G += r I with r = reg * trace(G) (reg where the trace is 0), G w = 1,
//   w /= sum w.
// The ridge makes G solvable when k exceeds the dimension or neighbours coincide (it picks
// the smallest-norm weights, as scikit-learn's LLE does with reg = 1e-3). Where the solve
// still fails (non-finite or zero sum) the weights are uniform. G is factored in place
// (Cholesky: G + r I is positive definite; no allocation per call, which cost as much as the
// arithmetic for the k = 10 systems of LLE).
#pragma once

#include <Eigen/Cholesky>
#include <Eigen/Core>

#include <cmath>

namespace mcv
{

// Z: k x D differences (k >= 1). G is scratch (resized as needed); w receives k weights.
template <typename DerivedZ>
void barycentricWeights(const Eigen::MatrixBase<DerivedZ>& Z, double regularization, Eigen::MatrixXd& G,
  Eigen::VectorXd& w)
{
  const Eigen::Index k = Z.rows();
  G.resize(k, k);
  G.noalias() = Z * Z.transpose();
  const double tr = G.trace();
  G.diagonal().array() += tr > 0 ? regularization * tr : regularization;
  const Eigen::LLT<Eigen::Ref<Eigen::MatrixXd>> factor(G);
  w.setOnes(k);
  if (factor.info() == Eigen::Success)
  {
    factor.solveInPlace(w);
  }
  const double s = w.sum();
  if (factor.info() != Eigen::Success || !std::isfinite(s) || s == 0.0)
  {
    w.setConstant(1.0 / static_cast<double>(k));
  }
  else
  {
    w /= s;
  }
}

} // namespace mcv
