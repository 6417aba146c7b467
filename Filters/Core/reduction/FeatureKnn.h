// Exact k-nearest neighbours in feature space (Euclidean), through nanoflann's kd-tree.
// The one place the reduction code talks to nanoflann, so the other files see plain arrays.
#pragma once

#include "Device.h"

#include <cstddef>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

namespace mcv
{

// A kd-tree over n points of `dim` floats, row-major. The points are not copied: `data`
// must outlive the index.
class KnnIndex
{
public:
  KnnIndex(const float* data, std::size_t n, int dim);
  ~KnnIndex();
  KnnIndex(const KnnIndex&) = delete;
  KnnIndex& operator=(const KnnIndex&) = delete;

  std::size_t size() const { return n_; }
  int dimension() const { return dim_; }

  // The k nearest points of `query` (dim floats), nearest first: indices and squared
  // distances. Returns how many were found (min(k, n)). Thread-safe (read-only).
  std::size_t query(const float* query, std::size_t k, std::uint32_t* indices, float* squaredDistances) const;

  struct Impl; // the tree, its dimension fixed at compile time where it is small (FeatureKnn.cpp)

private:
  std::unique_ptr<Impl> impl_;
  std::size_t n_ = 0;
  int dim_ = 0;
};

// The kNN graph of n points: for every point its k nearest OTHER points (self excluded),
// nearest first (the kd-tree in low dimension; ExactKnn's tiled brute force in high, where
// a kd-tree visits most of its leaves). neighbors[i*k + j], distances (Euclidean, not
// squared) likewise. k must be < n. OpenMP over blocks of points. With device GPU the brute
// force's float candidates come from the GPU (cuda/KnnCandidatesCuda.h) and the host applies
// the same canonical rule to them: the same graph (the CPU search where the GPU is missing,
// the graph is too large for it, or it fails; *deviceError, if given, then says why it failed).
struct KnnGraph
{
  std::size_t n = 0;
  int k = 0;
  std::vector<std::uint32_t> neighbors;
  std::vector<float> distances;
  // The largest, over the points, squared distance to the 4th nearest point counting the
  // point itself, in ExactKnn's canonical double arithmetic: what referenceRadius
  // (ModelDistance.h) takes the root of, found on the way by the tiled brute force when
  // k >= 3. -1 when not known (the kd-tree's float distances, or k < 3).
  double largestFourthSquaredDistance = -1.0;
};
KnnGraph buildKnnGraph(
  const float* data, std::size_t n, int dim, int k, Device device = Device::CPU, std::string* deviceError = nullptr);
// buildKnnGraph of a fit's reference points that also sets *referenceRadius (ModelDistance.h)
// to the root of largestFourthSquaredDistance when the search found it, so that the fit need
// not search every reference's neighbours a second time; else *referenceRadius is unchanged.
KnnGraph buildReferenceGraph(const float* data, std::size_t n, int dim, int k, double* referenceRadius,
  Device device = Device::CPU, std::string* deviceError = nullptr);

// An edge between two points, Euclidean length.
struct GraphEdge
{
  std::uint32_t a, b;
  float length;
};

// Joins the connected components of a kNN graph (taken as undirected): Boruvka rounds in
// which every component but the largest finds its closest pair of points to any other
// component (kd-tree queries with a doubling k; full rows of distances in high dimension;
// ties to the lowest index). Returns the edges to add (none when the
// graph is connected); `components` receives how many components there were.
std::vector<GraphEdge> joinKnnComponents(const float* data, std::size_t n, int dim, const KnnGraph& graph,
  std::size_t* components);

} // namespace mcv
