// Locally linear embedding (Roweis & Saul 2000), as scikit-learn's "standard" LLE:
//  1. kNN (K neighbours) of every reference point;
//  2. local weights: G = Z Z^T (Z = neighbours - point), G += reg * trace(G) * I
//     (reg = 1e-3, scikit-learn's default), solve G w = 1, w /= sum(w);
//  3. M = (I - W)^T (I - W), sparse;
//  4. its d+1 smallest eigenvectors through Spectra; the first (constant, eigenvalue 0) is
//     dropped. Coordinates are the eigenvectors scaled by sqrt(n) (unit mean square).
// Eigenvalues: the d smallest non-trivial ones, ascending.
#pragma once

#include "Embedding.h"

namespace mcv
{

enum class LLESolver
{
  Auto = 0,        // ShiftInvert while the factor stays small, else Lanczos
  ShiftInvert = 1, // Spectra shift-invert around a tiny negative shift, sparse LDLT of M
  Lanczos = 2      // Spectra Lanczos on c I - M (largest), M applied as two sparse products
};

struct LLEOptions
{
  int outputDimension = 3;
  int numberOfNeighbors = 50;
  double regularization = 1e-3;
  LLESolver solver = LLESolver::Auto;
  StageProgress progress;
};

Embedding fitLLE(const RowMatrixF& X, const LLEOptions& options);

} // namespace mcv
