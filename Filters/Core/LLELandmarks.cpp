#include "LLELandmarks.h"

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>
#include <Spectra/SymEigsShiftSolver.h>

#include <algorithm>
#include <stdexcept>

namespace mcv
{

namespace
{
// Relative to the pencil's scale (max diag C / max diag B): far below the wanted
// eigenvalues, so the shift changes nothing but makes C - sigma B positive definite.
constexpr double kShiftInvertSigma = 1e-12;
// Lanczos vectors beyond d + 1 kept for the Rayleigh-Ritz step (as in LLEEigen.cpp).
constexpr int kExtraVectors = 3;

// x -> L^T (C - sigma B)^{-1} L x on the complement of u = L^T 1 / |L^T 1|: the shift-inverted
// standard form of the pencil, S = L^{-1} C L^{-T}, never formed (two dense L x L
// triangular solves would cost more than the whole solve). Projecting u out removes the
// constant vector's 1/|sigma| eigenvalue, which would otherwise dwarf the wanted ones.
class ReducedShiftInvert
{
public:
  using Scalar = double;
  ReducedShiftInvert(const Eigen::MatrixXd& C, const Eigen::MatrixXd& B, const Eigen::MatrixXd& lowerB,
    const Eigen::VectorXd& u)
    : C_(C)
    , B_(B)
    , lowerB_(lowerB)
    , u_(u)
  {
  }
  Eigen::Index rows() const { return C_.rows(); }
  Eigen::Index cols() const { return C_.cols(); }
  void set_shift(double sigma)
  {
    factor_.compute(C_ - sigma * B_);
    if (factor_.info() != Eigen::Success)
    {
      throw std::runtime_error("the Cholesky factorisation of C - sigma B failed");
    }
  }
  void perform_op(const double* x, double* y) const
  {
    Eigen::Map<const Eigen::VectorXd> in(x, C_.rows());
    Eigen::Map<Eigen::VectorXd> out(y, C_.rows());
    const Eigen::VectorXd p = in - u_ * u_.dot(in);
    const Eigen::VectorXd s = factor_.solve(lowerB_.triangularView<Eigen::Lower>() * p);
    out.noalias() = lowerB_.triangularView<Eigen::Lower>().transpose() * s;
    out -= u_ * u_.dot(out);
  }

private:
  const Eigen::MatrixXd& C_;
  const Eigen::MatrixXd& B_;
  const Eigen::MatrixXd& lowerB_;
  const Eigen::VectorXd& u_;
  Eigen::LLT<Eigen::MatrixXd> factor_;
};
} // namespace

LLEBottomEigen lleLandmarkEigenvectors(const LLESparse& A, const LandmarkWeights& Z, int d)
{
  LLEBottomEigen r;
  const Eigen::Index n = Z.rows();
  const Eigen::Index L = Z.cols();
  if (d < 1 || L < d + 2 || A.rows() != n || A.cols() != n)
  {
    r.error = "need d >= 1, at least d + 2 landmarks and A of Z's row count";
    return r;
  }
  // The pencil. A Z has at most (K + 1) x (landmark neighbours) entries per row.
  const LandmarkWeights AZ = LandmarkWeights(A) * Z;
  const Eigen::MatrixXd C = Eigen::MatrixXd(LandmarkWeights(AZ.transpose()) * AZ);
  const Eigen::MatrixXd B = Eigen::MatrixXd(LandmarkWeights(Z.transpose()) * Z);

  // B = L L^T: positive definite because every landmark reconstructs itself.
  const Eigen::LLT<Eigen::MatrixXd> cholB(B);
  if (cholB.info() != Eigen::Success)
  {
    r.error = "Z^T Z is not positive definite (a landmark is nobody's neighbour)";
    return r;
  }
  const Eigen::MatrixXd lowerB = cholB.matrixL();
  // The constant: B 1 = Z^T 1 (Z's column sums); in standard form u = L^T 1.
  const Eigen::VectorXd columnSums = B * Eigen::VectorXd::Ones(L);
  Eigen::VectorXd u = lowerB.triangularView<Eigen::Lower>().transpose() * Eigen::VectorXd::Ones(L);
  u.normalize();

  const int nev = static_cast<int>(std::min<Eigen::Index>(d + 1 + kExtraVectors, L - 2));
  const int ncv = static_cast<int>(std::min<Eigen::Index>(L - 1, std::max(2 * nev + 1, 20)));
  const double scale = std::max(1e-300, C.diagonal().maxCoeff() / B.diagonal().maxCoeff());
  Eigen::MatrixXd X;
  try
  {
    ReducedShiftInvert op(C, B, lowerB, u);
    Spectra::SymEigsShiftSolver<ReducedShiftInvert> eigs(op, nev, ncv, -kShiftInvertSigma * scale);
    eigs.init();
    eigs.compute(Spectra::SortRule::LargestMagn, 300, 1e-10);
    if (eigs.info() != Spectra::CompInfo::Successful)
    {
      r.error = "shift-invert Lanczos on the landmark pencil did not converge";
      return r;
    }
    X = eigs.eigenvectors();
  }
  catch (const std::exception& ex) // a failed factorisation or inner eigensolve
  {
    r.error = ex.what();
    return r;
  }

  // Back to landmark coordinates, centred over the n points (Y = Z V has column means
  // columnSums^T V / n), then Rayleigh-Ritz with the exact pencil.
  Eigen::MatrixXd V = lowerB.triangularView<Eigen::Lower>().transpose().solve(X);
  V -= Eigen::VectorXd::Ones(L) * (columnSums.transpose() * V / static_cast<double>(n));
  const Eigen::MatrixXd HC = V.transpose() * C * V;
  const Eigen::MatrixXd HB = V.transpose() * B * V;
  Eigen::GeneralizedSelfAdjointEigenSolver<Eigen::MatrixXd> ritz(HC, HB);
  if (ritz.info() != Eigen::Success)
  {
    r.error = "the Rayleigh-Ritz step on the landmark pencil failed";
    return r;
  }
  r.values = ritz.eigenvalues().head(d); // ascending
  r.vectors = Z * (V * ritz.eigenvectors().leftCols(d));
  return r;
}

} // namespace mcv
