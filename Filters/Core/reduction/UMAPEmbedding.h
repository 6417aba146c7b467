// UMAP (McInnes, Healy & Melville 2018, "UMAP: Uniform Manifold Approximation and
// Projection for Dimension Reduction"), as umap-learn 0.5.3 runs it with its defaults
// (Euclidean metric, spread 1, local connectivity 1, set_op_mix_ratio 1, repulsion 1,
// 5 negative samples, learning rate 1, spectral initialisation):
//  1. exact kNN graph, K neighbours besides the point itself (buildKnnGraph: kd-tree or tiled
//     brute force); umap-learn's n_neighbors counts the point, so its 15 is our K = 14;
//  2. fuzzy simplicial set: smooth kNN distances and fuzzy union (UMAPGraph.h); edges
//     lighter than max weight / epochs are dropped;
//  3. spectral initialisation (UMAPSpectral.h), scaled to max |y| = 10, noise N(0, 1e-4)
//     added, then every axis mapped to [0, 10]; a disconnected graph, or a solver that does
//     not converge, gets a uniform random start in [-10, 10]^d instead, with a warning;
//  4. SGD of the cross-entropy with negative sampling (UMAPLayout.h), a and b of the low-
//     dimensional similarity fitted from minimumDistance (fitCurveParameters); on the GPU
//     when `device` resolves to it (UMAPLayoutDevice.h; cuda/UMAPLayoutCuda.h says how that
//     layout differs from the CPU's), on the CPU with a warning if the GPU fails;
//  5. the layout is centred and rotated to its principal axes (largest spread first; a rigid
//     motion: distances and trustworthiness unchanged), signs as fixColumnSigns.
// Deterministic: the same seed gives the same coordinates, for any number of threads
// (UMAPLayout.h says how the SGD stays so in parallel); on the GPU, the same on every run
// of one GPU model (not the CPU's coordinates).
// Eigenvalues: those of the normalised Laplacian behind the initialisation, ascending (none
// with a random start).
//
// Input: rows must be finite (error otherwise). Duplicate rows are allowed (the reference
// sample of reduceDimension has none): a point's zero distances are skipped when rho is
// chosen, as umap-learn does, and duplicates end up next to each other.
#pragma once

#include "Device.h"
#include "Embedding.h"

#include <cstdint>

namespace mcv
{

struct UMAPOptions
{
  int outputDimension = 3; // 2 or 3
  int numberOfNeighbors = 15; // K, the point itself not counted (K + 1 = umap-learn's n_neighbors)
  double minimumDistance = 0.1; // in [0, 1] (spread 1); 0 lets points coincide
  int numberOfEpochs = 0;       // 0: umap-learn's default (500 up to 10000 points, 200 beyond)
  std::uint64_t seed = 0;
  Device device = Device::CPU; // of the layout (step 4); Auto and GPU as resolveDevice says
  int gpuLayoutRounds = 0;      // parallel rounds per epoch of the GPU layout; 0: its default
                                // (cuda/UMAPLayoutCuda.h: 4 up to 10000 points, 16 beyond)
  StageProgress progress;
};

Embedding fitUMAP(const RowMatrixF& X, const UMAPOptions& options);

} // namespace mcv
