#include "FeatureKnn.h"

#include <nanoflann.hpp>

#include <algorithm>
#include <cmath>

namespace mcv
{

namespace
{
// nanoflann's dataset interface over a row-major float array.
struct RowMajorPoints
{
  const float* data;
  std::size_t n;
  int dim;
  std::size_t kdtree_get_point_count() const { return n; }
  float kdtree_get_pt(std::size_t i, std::size_t d) const { return data[i * static_cast<std::size_t>(dim) + d]; }
  template <class BBox>
  bool kdtree_get_bbox(BBox&) const
  {
    return false;
  }
};

// L2_Adaptor (not L2_Simple) stops a distance early once it exceeds the current worst:
// worth it for the 6..24 dimensions of feature vectors.
using Tree = nanoflann::KDTreeSingleIndexAdaptor<nanoflann::L2_Adaptor<float, RowMajorPoints, float>,
  RowMajorPoints, -1, std::uint32_t>;
} // namespace

struct KnnIndex::Impl
{
  RowMajorPoints points;
  Tree tree;
  Impl(const float* data, std::size_t n, int dim)
    : points{ data, n, dim }
    , tree(dim, points, nanoflann::KDTreeSingleIndexAdaptorParams(16))
  {
  }
};

KnnIndex::KnnIndex(const float* data, std::size_t n, int dim)
  : impl_(new Impl(data, n, dim))
  , n_(n)
  , dim_(dim)
{
}

KnnIndex::~KnnIndex() = default;

std::size_t KnnIndex::query(const float* q, std::size_t k, std::uint32_t* indices, float* squaredDistances) const
{
  if (k == 0 || n_ == 0)
  {
    return 0;
  }
  return impl_->tree.knnSearch(q, k, indices, squaredDistances);
}

KnnGraph buildKnnGraph(const float* data, std::size_t n, int dim, int k)
{
  KnnGraph g;
  g.n = n;
  g.k = k;
  g.neighbors.assign(n * static_cast<std::size_t>(k), 0);
  g.distances.assign(n * static_cast<std::size_t>(k), 0.f);
  if (n == 0 || k <= 0 || static_cast<std::size_t>(k) >= n)
  {
    return g;
  }
  const KnnIndex index(data, n, dim);
  const long long count = static_cast<long long>(n);
#pragma omp parallel
  {
    std::vector<std::uint32_t> idx(static_cast<std::size_t>(k) + 1);
    std::vector<float> d2(static_cast<std::size_t>(k) + 1);
#pragma omp for schedule(dynamic, 256)
    for (long long ii = 0; ii < count; ++ii)
    {
      const std::size_t i = static_cast<std::size_t>(ii);
      const std::size_t found = index.query(data + i * static_cast<std::size_t>(dim), idx.size(), idx.data(), d2.data());
      // Drop the point itself; if an exact duplicate took its place, drop the last one.
      std::size_t out = 0;
      bool selfSeen = false;
      for (std::size_t j = 0; j < found && out < static_cast<std::size_t>(k); ++j)
      {
        if (idx[j] == i && !selfSeen)
        {
          selfSeen = true;
          continue;
        }
        g.neighbors[i * k + out] = idx[j];
        g.distances[i * k + out] = std::sqrt(std::max(0.f, d2[j]));
        ++out;
      }
    }
  }
  return g;
}

} // namespace mcv
