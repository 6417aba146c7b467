#include "FeatureKnn.h"

#include "ExactKnn.h"

#ifdef MCV_HAS_CUDA
#include "cuda/KnnCandidatesCuda.h"
#endif

#include <nanoflann.hpp>

#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>
#include <numeric>

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

// L2_Simple_Adaptor: L2_Adaptor's early exit (in steps of 4 coordinates, once the sum
// passes the current worst) costs more than it saves at the dimensions the tree serves
// (<= 8, ExactKnn.cpp): 12-29 % slower queries on the brain's features at 3 to 10
// dimensions (docs/benchmarks.md, component measurements).
template <int Dim>
using Tree = nanoflann::KDTreeSingleIndexAdaptor<nanoflann::L2_Simple_Adaptor<float, RowMajorPoints, float>,
  RowMajorPoints, Dim, std::uint32_t>;

// Trees with the dimension fixed at compile time up to this one (the distance loop unrolled:
// ~13 % faster queries on the brain's 6-D features); a run-time dimension above it (the
// kd-tree is Auto's choice only up to 8 dimensions, ExactKnn.cpp).
constexpr int kMaxFixedDimension = 8;

struct UnionFind
{
  std::vector<std::uint32_t> parent;
  explicit UnionFind(std::size_t n)
    : parent(n)
  {
    std::iota(parent.begin(), parent.end(), 0u);
  }
  std::uint32_t find(std::uint32_t x)
  {
    while (parent[x] != x)
    {
      parent[x] = parent[parent[x]];
      x = parent[x];
    }
    return x;
  }
  bool unite(std::uint32_t a, std::uint32_t b)
  {
    a = find(a);
    b = find(b);
    if (a == b)
    {
      return false;
    }
    parent[std::max(a, b)] = std::min(a, b); // deterministic roots
    return true;
  }
};

} // namespace

struct KnnIndex::Impl
{
  virtual ~Impl() = default;
  virtual std::size_t query(const float* q, std::size_t k, std::uint32_t* indices, float* d2) const = 0;
};

namespace
{
template <int Dim>
struct TreeIndex final : KnnIndex::Impl
{
  RowMajorPoints points;
  Tree<Dim> tree;
  TreeIndex(const float* data, std::size_t n, int dim)
    : points{ data, n, dim }
    , tree(dim, points, nanoflann::KDTreeSingleIndexAdaptorParams(16))
  {
  }
  std::size_t query(const float* q, std::size_t k, std::uint32_t* indices, float* d2) const override
  {
    return tree.knnSearch(q, k, indices, d2);
  }
};

template <int Dim>
std::unique_ptr<KnnIndex::Impl> makeTree(const float* data, std::size_t n, int dim)
{
  if constexpr (Dim > kMaxFixedDimension)
  {
    return std::unique_ptr<KnnIndex::Impl>(new TreeIndex<-1>(data, n, dim));
  }
  else
  {
    return dim == Dim ? std::unique_ptr<KnnIndex::Impl>(new TreeIndex<Dim>(data, n, dim))
                      : makeTree<Dim + 1>(data, n, dim);
  }
}
} // namespace

KnnIndex::KnnIndex(const float* data, std::size_t n, int dim)
  : impl_(makeTree<1>(data, n, dim))
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
  return impl_->query(q, k, indices, squaredDistances);
}

KnnGraph buildReferenceGraph(
  const float* data, std::size_t n, int dim, int k, double* referenceRadius, Device device, std::string* deviceError)
{
  KnnGraph g = buildKnnGraph(data, n, dim, k, device, deviceError);
  if (g.largestFourthSquaredDistance >= 0.0)
  {
    *referenceRadius = std::sqrt(g.largestFourthSquaredDistance);
  }
  return g;
}

namespace
{

// Every point's kp float candidates from the GPU (cuda/KnnCandidatesCuda.h); empty where
// there is no GPU, the problem is larger than it takes, or it fails (*error says why).
void deviceCandidates(const float* data, std::size_t n, int dim, int kp, Device device, std::vector<std::uint32_t>& idx,
  std::vector<float>& f, std::string* error)
{
#ifdef MCV_HAS_CUDA
  if (device != Device::GPU || kp > cuda::kMaxKnnCandidatesOnDevice || static_cast<std::size_t>(kp) > n ||
    dim > cuda::kMaxKnnCandidateDimension || n > cuda::knnCandidatesMaxPoints())
  {
    return;
  }
  idx.resize(n * static_cast<std::size_t>(kp));
  f.resize(idx.size());
  if (!cuda::knnCandidates(data, n, dim, kp, idx.data(), f.data(), error))
  {
    idx.clear();
    f.clear();
  }
#else
  (void)data;
  (void)n;
  (void)dim;
  (void)kp;
  (void)device;
  (void)idx;
  (void)f;
  (void)error;
#endif
}

} // namespace

KnnGraph buildKnnGraph(const float* data, std::size_t n, int dim, int k, Device device, std::string* deviceError)
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
  // Low dimension (or many neighbours): the kd-tree. High dimension, where a kd-tree visits
  // most of its leaves: ExactKnn's tiled brute force (ties by index). ExactKnn's kd-tree
  // path would re-rank the tree's answer by the canonical rule, ~20% more time for the
  // same graph here.
  const int k1 = k + 1; // the point itself comes back too
  const bool bruteForce = chooseKnnMethod(dim, k1) == KnnMethod::BruteForce;
  std::unique_ptr<ExactKnn> tiled(bruteForce ? new ExactKnn(data, n, dim, KnnMethod::BruteForce) : nullptr);
  std::unique_ptr<KnnIndex> tree(bruteForce ? nullptr : new KnnIndex(data, n, dim));
  // The GPU's candidates, resolved here by the rule ExactKnn::query applies to TiledKnn's
  // (rows the bound does not settle take query()'s radius scan): the same neighbours.
  const int kp = std::min(k1 + kKnnCandidateMargin, kMaxKnnCandidates);
  std::vector<std::uint32_t> candidateIdx;
  std::vector<float> candidateF;
  if (tiled && k1 + kKnnCandidateMargin <= kMaxKnnCandidates)
  {
    deviceCandidates(data, n, dim, kp, device, candidateIdx, candidateF, deviceError);
  }
  const bool fromDevice = !candidateIdx.empty();
  const long long blocks = static_cast<long long>((n + kKnnQueryBlock - 1) / kKnnQueryBlock);
  const bool fourthKnown = tiled && k1 >= 4;
  double largestFourth = 0.0;
#pragma omp parallel reduction(max : largestFourth)
  {
    std::vector<std::uint32_t> idx(kKnnQueryBlock * static_cast<std::size_t>(k1));
    std::vector<double> d2(idx.size());
    std::vector<float> f2(static_cast<std::size_t>(k1));
#pragma omp for schedule(dynamic, 1)
    for (long long b = 0; b < blocks; ++b)
    {
      const std::size_t first = static_cast<std::size_t>(b) * kKnnQueryBlock;
      const std::size_t count = std::min(kKnnQueryBlock, n - first);
      if (fromDevice)
      {
        for (std::size_t r = 0; r < count; ++r)
        {
          const std::size_t i = first + r;
          const float* q = data + i * static_cast<std::size_t>(dim);
          if (!resolveCandidates(q, data, n, dim, candidateIdx.data() + i * kp, candidateF.data() + i * kp, kp, k1,
                idx.data() + r * k1, d2.data() + r * k1))
          {
            tiled->query(q, 1, k1, idx.data() + r * k1, d2.data() + r * k1);
          }
        }
      }
      else if (tiled)
      {
        tiled->query(data + first * static_cast<std::size_t>(dim), count, k1, idx.data(), d2.data());
      }
      else
      {
        for (std::size_t r = 0; r < count; ++r)
        {
          // k < n: the tree always finds k + 1 points.
          tree->query(data + (first + r) * static_cast<std::size_t>(dim), static_cast<std::size_t>(k1),
            idx.data() + r * k1, f2.data());
          std::copy(f2.begin(), f2.end(), d2.begin() + static_cast<std::ptrdiff_t>(r * k1));
        }
      }
      for (std::size_t r = 0; r < count; ++r)
      {
        const std::size_t i = first + r;
        if (fourthKnown)
        {
          largestFourth = std::max(largestFourth, d2[r * k1 + 3]);
        }
        // Drop the point itself; if an exact duplicate took its place, drop the last one.
        std::size_t out = 0;
        bool selfSeen = false;
        for (int j = 0; j < k1 && out < static_cast<std::size_t>(k); ++j)
        {
          const std::uint32_t nb = idx[r * k1 + j];
          if (nb == i && !selfSeen)
          {
            selfSeen = true;
            continue;
          }
          g.neighbors[i * k + out] = nb;
          g.distances[i * k + out] = static_cast<float>(std::sqrt(d2[r * k1 + j]));
          ++out;
        }
      }
    }
  }
  if (fourthKnown)
  {
    g.largestFourthSquaredDistance = largestFourth;
  }
  return g;
}

std::vector<GraphEdge> joinKnnComponents(const float* data, std::size_t n, int D, const KnnGraph& knn, std::size_t* componentsFound)
{
  UnionFind uf(n);
  for (std::size_t i = 0; i < n; ++i)
  {
    for (int j = 0; j < knn.k; ++j)
    {
      uf.unite(static_cast<std::uint32_t>(i), knn.neighbors[i * knn.k + j]);
    }
  }
  auto countComponents = [&]() {
    std::size_t c = 0;
    for (std::size_t i = 0; i < n; ++i)
    {
      c += uf.find(static_cast<std::uint32_t>(i)) == i;
    }
    return c;
  };
  *componentsFound = countComponents();
  std::vector<GraphEdge> added;
  if (*componentsFound <= 1)
  {
    return added;
  }
  // Low dimension: kd-tree queries with a doubling k. High dimension: one row of float
  // distances to every point (TiledKnn), where a kd-tree visits most of its leaves anyway.
  const bool bruteForce = chooseKnnMethod(D) == KnnMethod::BruteForce;
  std::unique_ptr<TiledKnn> tiled(bruteForce ? new TiledKnn(data, n, D) : nullptr);
  std::unique_ptr<KnnIndex> index(bruteForce ? nullptr : new KnnIndex(data, n, D));
  while (countComponents() > 1)
  {
    std::vector<std::uint32_t> root(n);
    std::vector<std::size_t> size(n, 0);
    for (std::size_t i = 0; i < n; ++i)
    {
      root[i] = uf.find(static_cast<std::uint32_t>(i));
      ++size[root[i]];
    }
    const std::uint32_t largest =
      static_cast<std::uint32_t>(std::max_element(size.begin(), size.end()) - size.begin());
    // Per point: its nearest point outside its component (squared distance).
    std::vector<std::uint32_t> partner(n, 0);
    std::vector<float> partnerD2(n, std::numeric_limits<float>::infinity());
    const long long count = static_cast<long long>(n);
#pragma omp parallel
    {
      std::vector<std::uint32_t> idx;
      std::vector<float> d2;
#pragma omp for schedule(dynamic, 64)
      for (long long ii = 0; ii < count; ++ii)
      {
        const std::size_t i = static_cast<std::size_t>(ii);
        if (root[i] == largest)
        {
          continue;
        }
        if (tiled)
        {
          d2.resize(n);
          tiled->distances(data + i * static_cast<std::size_t>(D), d2.data());
          for (std::size_t j = 0; j < n; ++j)
          {
            if (root[j] != root[i] && d2[j] < partnerD2[i])
            {
              partner[i] = static_cast<std::uint32_t>(j);
              partnerD2[i] = d2[j];
            }
          }
          continue;
        }
        for (std::size_t k = std::min(n, static_cast<std::size_t>(2 * knn.k + 2));; k = std::min(n, 2 * k))
        {
          idx.resize(k);
          d2.resize(k);
          const std::size_t found = index->query(data + i * static_cast<std::size_t>(D), k, idx.data(), d2.data());
          bool done = false;
          for (std::size_t j = 0; j < found; ++j)
          {
            if (idx[j] < n && std::isfinite(d2[j]) && root[idx[j]] != root[i])
            {
              partner[i] = idx[j];
              partnerD2[i] = d2[j];
              done = true;
              break;
            }
          }
          if (done)
          {
            break;
          }
          if (k == n)
          {
            // No point of another component among all the tree answered: their distances
            // overflow float (features beyond ~1e19). Scan them, a distance clamped to the
            // largest float, so that the component is still joined (else this never ends).
            const float* p = data + i * static_cast<std::size_t>(D);
            for (std::size_t j = 0; j < n; ++j)
            {
              if (root[j] == root[i])
              {
                continue;
              }
              const float* o = data + j * static_cast<std::size_t>(D);
              float s = 0.f;
              for (int c = 0; c < D; ++c)
              {
                s += (p[c] - o[c]) * (p[c] - o[c]);
              }
              s = std::min(s, std::numeric_limits<float>::max());
              if (s < partnerD2[i])
              {
                partner[i] = static_cast<std::uint32_t>(j);
                partnerD2[i] = s;
              }
            }
            break;
          }
        }
      }
    }
    // Per component: its closest pair (ties to the lowest index, so deterministic).
    std::vector<std::size_t> best(n, n);
    for (std::size_t i = 0; i < n; ++i)
    {
      if (root[i] == largest || !std::isfinite(partnerD2[i]))
      {
        continue;
      }
      std::size_t& b = best[root[i]];
      if (b == n || partnerD2[i] < partnerD2[b])
      {
        b = i;
      }
    }
    for (std::size_t r = 0; r < n; ++r)
    {
      const std::size_t i = best[r];
      if (i == n)
      {
        continue;
      }
      if (uf.unite(static_cast<std::uint32_t>(i), partner[i]))
      {
        added.push_back(GraphEdge{ static_cast<std::uint32_t>(i), partner[i], std::sqrt(std::max(0.f, partnerD2[i])) });
      }
    }
  }
  return added;
}

} // namespace mcv
