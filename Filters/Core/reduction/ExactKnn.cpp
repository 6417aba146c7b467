// Built with -ffp-contract=off (Filters/Core/CMakeLists.txt): the canonical distance must
// round every product and sum on its own, as the CUDA kernel does with __dmul_rn/__dadd_rn.
#include "ExactKnn.h"

#include "EnumNames.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

namespace mcv
{

namespace
{
// Auto: the kd-tree up to this dimension, the tiled brute force above, where a kd-tree
// visits most of its leaves. The crossover on the real brain's features (10000 references,
// k = 3, one thread): Testing/Benchmarks/BenchmarkReduction --sweep (docs/benchmarks.md).
constexpr int kKdTreeMaxDimension = 8;
// Few references: the brute force at any dimension. With LLE's 500 landmarks at 6D it is
// 1.3-1.8x faster than the kd-tree (one thread); the two tie at about 2000 references.
constexpr std::size_t kBruteForceMaxReferences = 1024;

constexpr std::uint32_t kNone = std::numeric_limits<std::uint32_t>::max();

struct Pair
{
  double d;
  std::uint32_t i;
  bool operator<(const Pair& o) const { return d < o.d || (d == o.d && i < o.i); }
};
} // namespace

const char* knnMethodName(KnnMethod method)
{
  static const EnumName<KnnMethod> names[] = { { KnnMethod::Auto, "auto" },
    { KnnMethod::KdTree, "kd-tree" }, { KnnMethod::BruteForce, "brute force" } };
  return nameOf(names, method, "unknown");
}

KnnMethod chooseKnnMethod(int dimension, int k, std::size_t references)
{
  const bool fits = k + kKnnCandidateMargin <= kMaxKnnCandidates;
  const bool bruteForceFaster = dimension > kKdTreeMaxDimension || references <= kBruteForceMaxReferences;
  return fits && bruteForceFaster ? KnnMethod::BruteForce : KnnMethod::KdTree;
}

double canonicalSquaredDistance(const float* a, const float* b, int dimension)
{
  double s = 0.0;
  for (int c = 0; c < dimension; ++c)
  {
    const double t = static_cast<double>(a[c]) - static_cast<double>(b[c]);
    s += t * t;
  }
  return s;
}

double floatDistanceMargin(int dimension)
{
  return 4.0 * (dimension + 4) * std::ldexp(1.0, -24);
}

bool resolveCandidates(const float* query, const float* refs, std::size_t M, int D, const std::uint32_t* cIdx,
  const float* cF, int kp, int k, std::uint32_t* idx, double* d2)
{
  Pair p[kMaxKnnCandidates];
  int valid = 0;
  for (int s = 0; s < kp && s < kMaxKnnCandidates; ++s)
  {
    if (cIdx[s] == kNone)
    {
      break;
    }
    p[valid++] = { canonicalSquaredDistance(query, refs + static_cast<std::size_t>(cIdx[s]) * D, D), cIdx[s] };
  }
  std::sort(p, p + valid);
  for (int j = 0; j < k; ++j)
  {
    idx[j] = j < valid ? p[j].i : kNone;
    d2[j] = j < valid ? p[j].d : std::numeric_limits<double>::infinity();
  }
  if (valid < k)
  {
    return false; // overflowing float distances: let the radius scan decide
  }
  if (static_cast<std::size_t>(valid) == M)
  {
    return true; // every reference was a candidate
  }
  // Every other reference has a float distance >= cF[kp-1], so d2 >= cF[kp-1] / (1 + margin).
  const double margin = floatDistanceMargin(D);
  return static_cast<double>(cF[valid - 1]) > p[k - 1].d * (1.0 + margin) * (1.0 + margin);
}

ExactKnn::ExactKnn(const float* refs, std::size_t M, int D, KnnMethod method)
  : refs_(refs)
  , M_(M)
  , D_(D)
  , method_(method == KnnMethod::Auto ? chooseKnnMethod(D, 1, M) : method)
  , tiled_(new TiledKnn(refs, M, D)) // also serves the radius scans of the kd-tree path
{
  if (method_ == KnnMethod::KdTree)
  {
    tree_.reset(new KnnIndex(refs, M, D));
  }
}

ExactKnn::~ExactKnn() = default;

std::size_t ExactKnn::query(const float* queries, std::size_t count, int k, std::uint32_t* idx, double* d2) const
{
  if (count == 0 || k <= 0 || M_ == 0)
  {
    return 0;
  }
  const int kp = std::min(k + kKnnCandidateMargin, kMaxKnnCandidates);
  std::vector<std::uint32_t> cIdx(count * static_cast<std::size_t>(kp));
  std::vector<float> cF(count * static_cast<std::size_t>(kp));
  if (method_ == KnnMethod::BruteForce)
  {
    tiled_->candidates(queries, count, kp, cIdx.data(), cF.data());
  }
  else
  {
    for (std::size_t r = 0; r < count; ++r)
    {
      std::uint32_t* ci = cIdx.data() + r * kp;
      float* cf = cF.data() + r * kp;
      const std::size_t found = tree_->query(queries + r * D_, static_cast<std::size_t>(kp), ci, cf);
      std::fill(ci + found, ci + kp, kNone);
      std::fill(cf + found, cf + kp, std::numeric_limits<float>::infinity());
    }
  }

  std::size_t fallbacks = 0;
  std::vector<float> all;
  std::vector<Pair> near;
  const double margin = floatDistanceMargin(D_);
  for (std::size_t r = 0; r < count; ++r)
  {
    const float* q = queries + r * D_;
    std::uint32_t* ri = idx + r * k;
    double* rd = d2 + r * k;
    if (resolveCandidates(q, refs_, M_, D_, cIdx.data() + r * kp, cF.data() + r * kp, kp, k, ri, rd))
    {
      continue;
    }
    // Radius scan: the k candidates found bound the true k-th distance from above (rd[k-1]);
    // every true neighbour has a float distance within the margin of it.
    ++fallbacks;
    all.resize(M_);
    tiled_->distances(q, all.data());
    const double bound = rd[k - 1] * (1.0 + margin) * (1.0 + margin);
    near.clear();
    for (std::size_t j = 0; j < M_; ++j)
    {
      if (!(static_cast<double>(all[j]) <= bound) && std::isfinite(bound) && std::isfinite(all[j]))
      {
        continue;
      }
      near.push_back({ canonicalSquaredDistance(q, refs_ + j * D_, D_), static_cast<std::uint32_t>(j) });
    }
    const std::size_t keep = std::min<std::size_t>(static_cast<std::size_t>(k), near.size());
    std::partial_sort(near.begin(), near.begin() + static_cast<std::ptrdiff_t>(keep), near.end());
    for (std::size_t j = 0; j < keep; ++j)
    {
      ri[j] = near[j].i;
      rd[j] = near[j].d;
    }
  }
  return fallbacks;
}

} // namespace mcv
