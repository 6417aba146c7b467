// The bottom of LLE's spectrum: the d unit eigenvectors of M = A^T A (A = I - W, W the
// reconstruction weights, rows summing to 1) with the smallest eigenvalues among the
// vectors orthogonal to the constant one; LLE's constraints (centred, uncorrelated
// coordinates) make this the answer even when M has more than one null vector (closed sets
// of neighbours: every point's neighbours inside the set), where "drop the first
// eigenvector" could keep the constant.
//
// The wanted eigenvalues are tiny (1e-15 .. 1e-10 of ||M|| on the brain features) and close together,
// so Lanczos on M itself needs thousands of steps; all solvers here invert:
//  - FactorA (the default): sparse LU (supernodal, COLAMD) of A + eps I, eps = 1e-14; the
//    operator (A_eps^T A_eps)^{-1} is two triangular solve pairs per step, and the LU of A
//    (the kNN pattern) fills in far less than a Cholesky of M (its two-hop pattern), e.g.
//    1000 vs 1600 non-zeros per row for 24-D features at n = 10000, and is supernodal.
//    A_eps^T A_eps = M + eps (A + A^T) + eps^2 I differs from M by ~1e-14, and a
//    Rayleigh-Ritz step with the exact M on the Lanczos vectors (d + 4 of them) removes that.
//    But the constant vector is not an exact eigenvector of A_eps^T A_eps: its ~1/eps^2
//    eigenvalue leaks into 1-perp as a spurious term of size ~1/lambda^2, harmless when the
//    wanted lambda are tiny (real data, near-closed sets of neighbours) and wrong when they
//    are large (a smooth manifold). Auto therefore accepts FactorA only when every
//    ||M v - lambda v|| <= 1e-6 ||M|| (ARPACK's tolerance in
//    scikit-learn), else it uses ShiftInvert.
//  - ShiftInvert: exact (M 1 = 0 is projected out of the operator); SimplicialLDLT (AMD
//    ordering) of M - sigma I, sigma = -1e-12 max(diag M):
//    M is PSD, so M - sigma I is positive definite while sigma stays well below the wanted
//    eigenvalues (a larger shift, e.g. 1e-9, maps them all to ~1/|sigma| and Lanczos
//    crawls: 30-50 restarts instead of 1).
//  - Lanczos: c I - M (c >= lambda_max), largest eigenvalues; slow, the fallback.
#pragma once

#include <Eigen/Core>
#include <Eigen/SparseCore>

#include <string>

namespace mcv
{

enum class LLESolver
{
  Auto = 0,        // FactorA, then ShiftInvert, then Lanczos: the first accurate one
  FactorA = 1,     // shift-invert through a sparse LU of A + eps I, Rayleigh-Ritz on M
  ShiftInvert = 2, // shift-invert through a sparse LDLT of M - sigma I
  Lanczos = 3      // Lanczos on c I - M
};

struct LLEBottomEigen
{
  std::string error;      // non-empty: no result
  Eigen::VectorXd values; // d eigenvalues of M, ascending
  Eigen::MatrixXd vectors; // n x d, orthonormal, orthogonal to the constant vector
};

using LLESparse = Eigen::SparseMatrix<double, Eigen::ColMajor, int>;

// A: n x n, I - W. d >= 1, n >= d + 2.
LLEBottomEigen lleBottomEigenvectors(const LLESparse& A, int d, LLESolver solver = LLESolver::Auto);

} // namespace mcv
