#include "LLEEigen.h"

#include <Eigen/Dense>
#include <Eigen/SparseCholesky>
#include <Eigen/SparseLU>
#include <Spectra/SymEigsShiftSolver.h>
#include <Spectra/SymEigsSolver.h>

#include <algorithm>
#include <stdexcept>
#include <vector>

namespace mcv
{

namespace
{
// A_eps^T A_eps - M ~ 2 eps ||A||: small against the eigenvalues that carry an embedding
// on real data (1e-13 .. 1e-8, ||M|| ~ 25), yet ~50x the unit roundoff x ||A||, so the
// pivots of A's exact null vectors are not pure rounding noise (a shift of 1e-12 moves an
// eigenvalue of 4e-13 to 5e-13; 1e-15 leaves the pivots noisier). A has a unit diagonal: the
// scale is absolute.
constexpr double kFactorShift = 1e-14;
constexpr double kShiftInvertSigma = 1e-12; // relative to max(diag M)
// Lanczos vectors beyond d + 1 kept for the Rayleigh-Ritz step.
constexpr int kExtraVectors = 3;
// Auto accepts a solver's eigenpairs when ||M v - lambda v|| <= this x ||M|| (ARPACK's
// tolerance in scikit-learn's LLE is 1e-6 too). The smallest non-null eigenvalues of real
// data sit at 1e-14 ||M||, at the rounding floor of any factorisation, so a tighter test
// would reject FactorA for noise.
constexpr double kResidualTolerance = 1e-6;

// x minus its mean: the projection onto 1-perp. M 1 = 0 exactly, so projecting the
// shift-inverted operator removes the constant vector's 1/|shift| eigenvalue, which would
// otherwise dwarf the wanted ones by up to 1e12 and drown them in rounding.
void centre(Eigen::Map<Eigen::VectorXd>& v)
{
  v.array() -= v.mean();
}

// (A_eps^T A_eps)^{-1} x = A_eps^{-1} (A_eps^{-T} x), through one sparse LU.
class LUNormalInverse
{
public:
  using Scalar = double;
  explicit LUNormalInverse(const LLESparse& A)
    : n_(A.rows())
  {
    LLESparse shifted = A;
    for (Eigen::Index i = 0; i < n_; ++i)
    {
      shifted.coeffRef(i, i) += kFactorShift;
    }
    shifted.makeCompressed();
    lu_.compute(shifted);
    ok_ = lu_.info() == Eigen::Success;
  }
  bool ok() const { return ok_; }
  Eigen::Index rows() const { return n_; }
  Eigen::Index cols() const { return n_; }
  void perform_op(const double* x, double* y) const
  {
    Eigen::Map<const Eigen::VectorXd> in(x, n_);
    Eigen::Map<Eigen::VectorXd> out(y, n_);
    // Not projected onto 1-perp: the constant is not an exact eigenvector here, and the
    // projected operator's tridiagonal breaks down (Spectra throws); Rayleigh-Ritz drops it.
    const Eigen::VectorXd z = lu_.transpose().solve(in);
    out = lu_.solve(z);
  }

private:
  Eigen::Index n_;
  // transpose() is not const in Eigen 3.4; solving changes nothing.
  mutable Eigen::SparseLU<LLESparse, Eigen::COLAMDOrdering<int>> lu_;
  bool ok_ = false;
};

// (M - sigma I)^{-1} x through a sparse LDLT (Spectra's SparseSymShiftSolve uses a sparse
// LU, twice the work for a symmetric matrix).
class LDLTShiftInvert
{
public:
  using Scalar = double;
  explicit LDLTShiftInvert(const LLESparse& M)
    : M_(M)
  {
  }
  Eigen::Index rows() const { return M_.rows(); }
  Eigen::Index cols() const { return M_.cols(); }
  void set_shift(double sigma)
  {
    LLESparse S = M_;
    for (Eigen::Index i = 0; i < S.rows(); ++i)
    {
      S.coeffRef(i, i) -= sigma;
    }
    ldlt_.compute(S);
    ok_ = ldlt_.info() == Eigen::Success;
  }
  bool ok() const { return ok_; }
  void perform_op(const double* x, double* y) const
  {
    Eigen::Map<const Eigen::VectorXd> in(x, M_.rows());
    Eigen::Map<Eigen::VectorXd> out(y, M_.rows());
    const Eigen::VectorXd z = in.array() - in.mean();
    out = ldlt_.solve(z);
    centre(out);
  }

private:
  const LLESparse& M_;
  Eigen::SimplicialLDLT<LLESparse, Eigen::Lower, Eigen::AMDOrdering<int>> ldlt_;
  bool ok_ = false;
};

// (c I - M) x with M = A^T A applied as two sparse products (never formed).
class ShiftedProduct
{
public:
  using Scalar = double;
  ShiftedProduct(const LLESparse& A, double c)
    : A_(A)
    , c_(c)
  {
  }
  Eigen::Index rows() const { return A_.cols(); }
  Eigen::Index cols() const { return A_.cols(); }
  void perform_op(const double* x, double* y) const
  {
    Eigen::Map<const Eigen::VectorXd> in(x, A_.cols());
    Eigen::Map<Eigen::VectorXd> out(y, A_.cols());
    const Eigen::VectorXd t = A_ * in;
    out = c_ * in - A_.transpose() * t;
  }

private:
  const LLESparse& A_;
  double c_;
};

// Rayleigh-Ritz with the exact M on span(V) minus the constant vector: the d best
// approximations there to the bottom eigenvectors of M restricted to 1-perp.
bool rayleighRitz(const LLESparse& A, Eigen::MatrixXd V, int d, LLEBottomEigen& out)
{
  V.rowwise() -= V.colwise().mean();
  Eigen::ColPivHouseholderQR<Eigen::MatrixXd> qr(V);
  qr.setThreshold(1e-10);
  const Eigen::Index rank = qr.rank();
  if (rank < d)
  {
    return false;
  }
  const Eigen::MatrixXd Q = qr.householderQ() * Eigen::MatrixXd::Identity(V.rows(), rank);
  const Eigen::MatrixXd AQ = A * Q;
  const Eigen::MatrixXd H = AQ.transpose() * AQ;
  Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig(H);
  if (eig.info() != Eigen::Success)
  {
    return false;
  }
  out.values = eig.eigenvalues().head(d); // ascending
  out.vectors = Q * eig.eigenvectors().leftCols(d);
  return true;
}

// The eigenvectors of a Spectra solver run to convergence (`rule`, up to `iterations`
// restarts, tolerance 1e-8), or an empty matrix and `failure` as why.
template <class Solver>
Eigen::MatrixXd converged(Solver& eigs, Spectra::SortRule rule, int iterations,
  const char* failure, std::string& why)
{
  eigs.init();
  eigs.compute(rule, iterations, 1e-8);
  if (eigs.info() != Spectra::CompInfo::Successful)
  {
    why = failure;
    return {};
  }
  return eigs.eigenvectors();
}

// The nev candidate vectors of one solver, or an empty matrix and why.
Eigen::MatrixXd candidates(const LLESparse& A, LLESolver solver, int nev, std::string& why)
{
  const int n = static_cast<int>(A.rows());
  const int ncv = std::min(n, std::max(2 * nev + 1, 20));
  if (solver == LLESolver::FactorA)
  {
    LUNormalInverse op(A);
    if (!op.ok())
    {
      why = "the sparse LU of A failed";
      return {};
    }
    Spectra::SymEigsSolver<LUNormalInverse> eigs(op, nev, ncv);
    return converged(
      eigs, Spectra::SortRule::LargestMagn, 300, "shift-invert (LU of A) did not converge", why);
  }
  if (solver == LLESolver::ShiftInvert)
  {
    const LLESparse M = LLESparse(A.transpose()) * A;
    const double sigma = -kShiftInvertSigma * std::max(1e-300, M.diagonal().maxCoeff());
    LDLTShiftInvert op(M);
    Spectra::SymEigsShiftSolver<LDLTShiftInvert> eigs(op, nev, ncv, sigma);
    if (!op.ok())
    {
      why = "the sparse LDLT of M failed";
      return {};
    }
    return converged(
      eigs, Spectra::SortRule::LargestMagn, 300, "shift-invert (LDLT of M) did not converge", why);
  }
  // c >= lambda_max(M) = ||A||_2^2 <= ||A||_1 ||A||_inf.
  const double norm1 = Eigen::RowVectorXd(Eigen::RowVectorXd::Ones(n) * A.cwiseAbs()).maxCoeff();
  const double normInf = Eigen::VectorXd(A.cwiseAbs() * Eigen::VectorXd::Ones(n)).maxCoeff();
  ShiftedProduct op(A, norm1 * normInf);
  Spectra::SymEigsSolver<ShiftedProduct> eigs(op, nev, std::min(n, std::max(4 * nev, 40)));
  return converged(eigs, Spectra::SortRule::LargestAlge, 3000, "Lanczos did not converge", why);
}

// ||M v - lambda v|| of every pair, against max(diag M) ~ ||M||.
bool accurate(const LLESparse& A, const LLEBottomEigen& r)
{
  const Eigen::MatrixXd AV = A * r.vectors;
  const Eigen::MatrixXd MV = A.transpose() * AV;
  const double scale = Eigen::VectorXd(A.cwiseAbs2().transpose() * Eigen::VectorXd::Ones(A.rows())).maxCoeff();
  for (Eigen::Index k = 0; k < r.values.size(); ++k)
  {
    if ((MV.col(k) - r.values[k] * r.vectors.col(k)).norm() > kResidualTolerance * scale)
    {
      return false;
    }
  }
  return true;
}
} // namespace

LLEBottomEigen lleBottomEigenvectors(const LLESparse& A, int d, LLESolver solver)
{
  LLEBottomEigen r;
  const int n = static_cast<int>(A.rows());
  if (d < 1 || n < d + 2)
  {
    r.error = "need d >= 1 and at least d + 2 points";
    return r;
  }
  const int nev = std::min(d + 1 + kExtraVectors, n - 1);
  // Auto: FactorA where it is accurate (the hard, near-singular spectra of real data, where
  // it is also the fastest), else the exact shift-invert, else Lanczos.
  const std::vector<LLESolver> order = solver == LLESolver::Auto
    ? std::vector<LLESolver>{ LLESolver::FactorA, LLESolver::ShiftInvert, LLESolver::Lanczos }
    : std::vector<LLESolver>{ solver };
  std::string why;
  for (LLESolver s : order)
  {
    std::string failed;
    Eigen::MatrixXd V;
    try
    {
      V = candidates(A, s, nev, failed);
    }
    catch (const std::exception& ex) // Spectra throws on a failed inner eigensolve
    {
      failed = ex.what();
    }
    if (V.size() == 0)
    {
      why += (why.empty() ? "" : "; ") + failed;
      continue;
    }
    LLEBottomEigen attempt;
    if (!rayleighRitz(A, V, d, attempt))
    {
      why += std::string(why.empty() ? "" : "; ") + "fewer than d independent eigenvectors besides the constant one";
      continue;
    }
    if (solver == LLESolver::Auto && s != order.back() && !accurate(A, attempt))
    {
      why += std::string(why.empty() ? "" : "; ") + "inaccurate eigenvectors";
      continue;
    }
    return attempt;
  }
  r.error = why;
  return r;
}

} // namespace mcv
