// Locally linear landmarks (Vladymyrov & Carreira-Perpinan, "Locally Linear Landmarks for
// Large-Scale Manifold Learning", ECML PKDD 2013): LLE's problem restricted to embeddings
// that every point takes from L landmarks, Y = Z U, where row i of Z (n x L) holds the
// barycentric weights of point i from its nearest landmarks (a landmark reconstructs itself)
// and U (L x d) are the landmarks' coordinates. With M = (I - W)^T (I - W):
//   min tr(U^T Z^T M Z U)  subject to  (Z U)^T (Z U) = I,  1^T Z U = 0,
// i.e. the smallest eigenvectors of the L x L pencil (C, B) = (Z^T M Z, Z^T Z) other than the
// constant one (Z 1 = 1 and M 1 = 0, so the constant has eigenvalue 0).
//
// Why: exact LLE needs the bottom of M's spectrum, which on real feature vectors sits at the
// rounding floor (1e-15 .. 1e-10 of ||M||) and is degenerate when the kNN graph has closed
// sets of neighbours, so it costs a sparse LU of I - W (fill ~1000 per row for 24-D features
// at n = 10000, 1.3 s) and returns an arbitrary basis of that near-null space
// (trustworthiness 0.70-0.77 on the brain's 6-D features). Restricted to span(Z) the
// problem is small and well posed: 0.92-0.96 there, 0.80-0.84 at 24D (compare_sklearn.py).
//
// The pencil is solved by shift-invert: one dense Cholesky C - sigma B = F F^T (summed a
// column at a time from the sparse A Z and Z into a huge-page buffer, factored in place by
// Eigen's LLT), then Spectra's symmetric
// Lanczos on F^{-1} B F^{-T} with the constant deflated, then Rayleigh-Ritz with the exact
// (C, B) on the Lanczos vectors (LLELandmarks.cpp says why each step takes that form).
#pragma once

#include "LLEEigen.h"

#include <Eigen/SparseCore>

namespace mcv
{

using LLESparseRows = Eigen::SparseMatrix<double, Eigen::RowMajor, int>;
using LandmarkWeights = LLESparseRows;

// A: n x n, I - W. Z: n x L barycentric weights (rows sum to 1), every landmark used by at
// least one row (each reconstructs itself). d >= 1, L >= d + 2. The result's vectors are
// n x d: Y = Z U with Y^T Y = I and 1^T Y = 0; values are the pencil's eigenvalues.
LLEBottomEigen lleLandmarkEigenvectors(const LLESparseRows& A, const LandmarkWeights& Z, int d);

} // namespace mcv
