// Locally linear embedding (Roweis & Saul 2000), as scikit-learn's "standard" LLE:
//  1. kNN (K neighbours) of every reference point;
//  2. local weights: G = Z Z^T (Z = neighbours - point), G += reg * trace(G) * I
//     (reg = 1e-3, scikit-learn's default), solve G w = 1, w /= sum(w);
//  3. M = (I - W)^T (I - W), sparse;
//  4. its d smallest eigenvectors orthogonal to the constant vector (LLEEigen.h: shift-invert
//     through a sparse LU of I - W). Coordinates are the eigenvectors scaled by sqrt(n)
//     (unit mean square).
// Eigenvalues: those d, ascending.
#pragma once

#include "Embedding.h"
#include "LLEEigen.h"

namespace mcv
{

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
