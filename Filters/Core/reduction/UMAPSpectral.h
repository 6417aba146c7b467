// UMAP's spectral initialisation (umap-learn 0.5.3's spectral_layout): the eigenvectors of
// the normalised Laplacian L = I - D^(-1/2) W D^(-1/2) of the fuzzy graph with the d
// smallest non-zero eigenvalues (the smallest, 0, belongs to D^(1/2) 1 and is dropped).
// Lanczos (Spectra) on 2I - L, whose largest eigenvalues are L's smallest, with umap-learn's
// start vector (all ones) and tolerance (1e-4); 20 Lanczos vectors (UMAPSpectral.cpp).
#pragma once

#include "Embedding.h"

#include <string>

namespace mcv
{

struct FuzzyGraph;

struct SpectralLayout
{
  std::string error;         // non-empty: the solver failed (no layout)
  RowMatrixF coordinates;    // n x d
  std::vector<double> eigenvalues; // the d eigenvalues of L used, ascending
};

// graph: connected (a disconnected graph has a multiple eigenvalue 0 and no meaningful
// layout; the caller checks). n >= d + 2.
SpectralLayout spectralLayout(const FuzzyGraph& graph, int d);

} // namespace mcv
