// Landmark Isomap (Tenenbaum et al. 2000; de Silva & Tenenbaum 2003, "Global versus local
// methods in nonlinear dimensionality reduction"):
//  1. kNN graph (K neighbours, Euclidean edge lengths, made symmetric; on the GPU with device
//     GPU, the same graph: FeatureKnn.h);
//  2. a disconnected graph is joined: each component is linked to its nearest other one by
//     the closest pair of points (Boruvka rounds) and a warning says how many there were;
//  3. L landmarks drawn uniformly with the seed (see uniformLandmarks for why not MaxMin);
//  4. Dijkstra from every landmark (OpenMP over landmarks, 4-ary heap with decrease-key):
//     the L x n geodesic distances; on the GPU (device GPU) one block per landmark finds the
//     same distances, bit for bit (cuda/GeodesicsCuda.h);
//  5. landmark MDS: classical MDS of the L x L squared geodesics, then every point placed by
//     distance-based triangulation y = -1/2 L# (delta_i - delta_mean); finally the result is
//     centred and rotated to its principal axes (de Silva & Tenenbaum's last step).
// Eigenvalues: those of the landmark MDS Gram matrix, descending (all of them, values only,
// by cuSOLVER on the GPU where the build links it (MCV_USE_CUSOLVER), else on the host's
// threads (SymmetricEigenvalues.h); the top d eigenvectors by Lanczos on the host either way).
#pragma once

#include "Device.h"
#include "Embedding.h"

#include <cstdint>

namespace mcv
{

struct IsomapOptions
{
  int outputDimension = 3;
  int numberOfNeighbors = 50;
  int numberOfLandmarks = 500; // clamped to [d+1, n]
  std::uint64_t seed = 0;
  Device device = Device::CPU; // GPU: the graph's search, shortest paths and MDS eigenvalues on the
                               // device (each on the CPU if it fails)
  StageProgress progress;
};

// X: n x D reference feature vectors (distinct rows).
Embedding fitIsomap(const RowMatrixF& X, const IsomapOptions& options);

} // namespace mcv
