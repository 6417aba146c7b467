// UMAP's fuzzy simplicial set (McInnes, Healy & Melville 2018, section 3.1; umap-learn
// 0.5.3's fuzzy_simplicial_set) from a kNN graph:
//  1. smooth kNN distances: per point rho_i (distance to its nearest non-identical neighbour)
//     and sigma_i (binary search, 64 steps, tolerance 1e-5) with
//       sum_j exp(-max(0, d_ij - rho_i) / sigma_i) = log2(K + 1),
//     the point itself counting as its own first neighbour as in umap-learn (whose
//     n_neighbors is our K + 1); sigma_i is kept above 1e-3 of the mean neighbour distance;
//  2. directed memberships p_(j|i) = exp(-max(0, d_ij - rho_i) / sigma_i);
//  3. fuzzy union: w_ij = p_(j|i) + p_(i|j) - p_(j|i) p_(i|j), symmetric.
#pragma once

#include "FeatureKnn.h"

#include <cstddef>
#include <cstdint>
#include <vector>

namespace mcv
{

// A symmetric weighted graph in compressed rows, without self loops; each row sorted by
// neighbour. Every undirected edge is stored twice (i -> j and j -> i), as umap-learn's
// COO matrix holds it and as its layout samples it.
struct FuzzyGraph
{
  std::size_t n = 0;
  std::vector<std::size_t> start; // n + 1
  std::vector<std::uint32_t> to;
  std::vector<float> weight; // in (0, 1]
  std::size_t edgeCount() const { return to.size(); }
};

// Step 1 on the K (self excluded) neighbour distances of n points, nearest first
// (distances[i*K + j]): sigma and rho, n each.
void smoothKnnDistances(const float* distances, std::size_t n, int K, float* sigma, float* rho);

// Steps 1-3.
FuzzyGraph fuzzySimplicialSet(const KnnGraph& knn);

// Drops the edges lighter than `threshold` (umap-learn drops those below max weight /
// epochs: they would be sampled less than once).
void dropWeakEdges(FuzzyGraph& graph, float threshold);

// Connected components of the graph: a label per point in [0, components); returns the count.
std::size_t connectedComponents(const FuzzyGraph& graph, std::vector<std::uint32_t>& label);

} // namespace mcv
