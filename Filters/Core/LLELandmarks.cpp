#include "LLELandmarks.h"

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>
#include <Spectra/MatOp/DenseSymMatProd.h>
#include <Spectra/SymGEigsShiftSolver.h>

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

// Spectra's generalized shift-invert mode applies T = (C - sigma B)^{-1} B with B-inner
// products; this operator is the (C - sigma B)^{-1} part, with the constant vector 1 (B 1 =
// Z^T 1, Z's column sums) projected out B-orthogonally on both sides: Q T Q with
// Q = I - 1 (B 1)^T / (1^T B 1), still B-self-adjoint. Otherwise the constant's eigenvalue
// 0 would become 1 / |sigma| and dwarf the wanted ones. Spectra hands it B x, so the
// projection on the right is x - (B 1) (1^T x) / (1^T B 1).
class ProjectedShiftInvert
{
public:
  using Scalar = double;
  ProjectedShiftInvert(const Eigen::MatrixXd& C, const Eigen::MatrixXd& B, const Eigen::VectorXd& columnSums)
    : C_(C)
    , B_(B)
    , columnSums_(columnSums)
    , total_(columnSums.sum())
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
    out = factor_.solve(in - columnSums_ * (in.sum() / total_));
    out.array() -= columnSums_.dot(out) / total_;
  }

private:
  const Eigen::MatrixXd& C_;
  const Eigen::MatrixXd& B_;
  const Eigen::VectorXd& columnSums_;
  const double total_;
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

  // B is positive definite: every landmark reconstructs itself, so Z holds an identity.
  const Eigen::VectorXd columnSums = B * Eigen::VectorXd::Ones(L);

  const int nev = static_cast<int>(std::min<Eigen::Index>(d + 1 + kExtraVectors, L - 2));
  const int ncv = static_cast<int>(std::min<Eigen::Index>(L - 1, std::max(2 * nev + 1, 20)));
  const double scale = std::max(1e-300, C.diagonal().maxCoeff() / B.diagonal().maxCoeff());
  Eigen::MatrixXd V;
  try
  {
    ProjectedShiftInvert op(C, B, columnSums);
    Spectra::DenseSymMatProd<double> productB(B);
    Spectra::SymGEigsShiftSolver<ProjectedShiftInvert, Spectra::DenseSymMatProd<double>,
      Spectra::GEigsMode::ShiftInvert>
      eigs(op, productB, nev, ncv, -kShiftInvertSigma * scale);
    eigs.init();
    eigs.compute(Spectra::SortRule::LargestMagn, 300, 1e-10);
    if (eigs.info() != Spectra::CompInfo::Successful)
    {
      r.error = "shift-invert Lanczos on the landmark pencil did not converge";
      return r;
    }
    V = eigs.eigenvectors();
  }
  catch (const std::exception& ex) // a failed factorisation or inner eigensolve
  {
    r.error = ex.what();
    return r;
  }

  // Centred over the n points (Y = Z V has column means columnSums^T V / n; the projection
  // made them ~0 already), then Rayleigh-Ritz with the exact pencil.
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
