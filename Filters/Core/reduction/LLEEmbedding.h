// Locally linear embedding (Roweis & Saul 2000), as scikit-learn's "standard" LLE:
//  1. kNN (K neighbours) of every reference point;
//  2. local weights: G = Z Z^T (Z = neighbours - point), G += reg * trace(G) * I
//     (reg = 1e-3, scikit-learn's default), solve G w = 1, w /= sum(w);
//  3. M = (I - W)^T (I - W), sparse;
//  4. its d smallest eigenvectors orthogonal to the constant vector, either
//     - exact (LLEEigen.h: shift-invert through a sparse LU of I - W), or
//     - restricted to embeddings reconstructed from L landmarks (locally linear landmarks,
//       LLELandmarks.h; the default, L = 500, drawn uniformly with the seed): every point
//       takes barycentric weights from its `landmarkNeighbors` nearest landmarks.
//     Coordinates are the eigenvectors scaled by sqrt(n) (unit mean square).
// Eigenvalues: those d, ascending.
#pragma once

#include "Embedding.h"
#include "LLEEigen.h"

#include <cstdint>

namespace mcv
{

struct LLEOptions
{
  int outputDimension = 3;
  int numberOfNeighbors = 50;
  double regularization = 1e-3;
  // Locally linear landmarks when 0 < L < n (clamped to at least 2 (d + 4) + 1, what the
  // Lanczos step needs); 0 or L >= n: exact LLE.
  int numberOfLandmarks = 0;
  int landmarkNeighbors = 10; // clamped to L
  std::uint64_t seed = 0;     // draws the landmarks
  LLESolver solver = LLESolver::Auto; // the exact path's eigensolver
  StageProgress progress;
};

Embedding fitLLE(const RowMatrixF& X, const LLEOptions& options);

} // namespace mcv
