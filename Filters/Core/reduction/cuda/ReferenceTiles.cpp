// Host side of the GPU placement's tile pruning (ReferenceTiles.h).
#include "ReferenceTiles.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <utility>

namespace mcv
{
namespace cuda
{

namespace
{
// The references reordered so that each tile of kReferenceTile consecutive ones is compact: a node
// of the recursion is split across its principal axis (a few power iterations on its
// covariance, in double) at a multiple of kReferenceTile, by rank along the axis (ties by index),
// until it is one tile. order[sorted position] = original index; deterministic.
std::vector<unsigned> orderReferences(const float* X, std::size_t M, int D)
{
  std::vector<unsigned> order(M);
  for (std::size_t i = 0; i < M; ++i)
  {
    order[i] = static_cast<unsigned>(i);
  }
  std::vector<double> mean(D), axis(D), next(D), x(D);
  std::vector<std::pair<double, unsigned>> keyed;
  struct Node
  {
    std::size_t lo, hi;
  };
  std::vector<Node> todo{ { 0, M } };
  while (!todo.empty())
  {
    const Node node = todo.back();
    todo.pop_back();
    const std::size_t n = node.hi - node.lo;
    if (n <= static_cast<std::size_t>(kReferenceTile))
    {
      continue;
    }
    std::fill(mean.begin(), mean.end(), 0.0);
    for (std::size_t i = node.lo; i < node.hi; ++i)
    {
      for (int c = 0; c < D; ++c)
      {
        mean[c] += X[static_cast<std::size_t>(order[i]) * D + c];
      }
    }
    for (int c = 0; c < D; ++c)
    {
      mean[c] /= static_cast<double>(n);
    }
    // Start from the widest coordinate (by variance) and iterate axis <- C axis.
    std::fill(axis.begin(), axis.end(), 0.0);
    for (std::size_t i = node.lo; i < node.hi; ++i)
    {
      for (int c = 0; c < D; ++c)
      {
        const double t = X[static_cast<std::size_t>(order[i]) * D + c] - mean[c];
        axis[c] += t * t;
      }
    }
    const int widest = static_cast<int>(std::max_element(axis.begin(), axis.end()) - axis.begin());
    std::fill(axis.begin(), axis.end(), 0.0);
    axis[widest] = 1.0;
    for (int iteration = 0; iteration < 8; ++iteration)
    {
      std::fill(next.begin(), next.end(), 0.0);
      for (std::size_t i = node.lo; i < node.hi; ++i)
      {
        double dot = 0.0;
        for (int c = 0; c < D; ++c)
        {
          x[c] = X[static_cast<std::size_t>(order[i]) * D + c] - mean[c];
          dot += x[c] * axis[c];
        }
        for (int c = 0; c < D; ++c)
        {
          next[c] += dot * x[c];
        }
      }
      double norm = 0.0;
      for (double v : next)
      {
        norm += v * v;
      }
      if (!(norm > 0.0) || !std::isfinite(norm))
      {
        break; // all equal (or not finite): keep the last axis
      }
      norm = std::sqrt(norm);
      for (int c = 0; c < D; ++c)
      {
        axis[c] = next[c] / norm;
      }
    }
    keyed.clear();
    for (std::size_t i = node.lo; i < node.hi; ++i)
    {
      double dot = 0.0;
      for (int c = 0; c < D; ++c)
      {
        dot += (X[static_cast<std::size_t>(order[i]) * D + c] - mean[c]) * axis[c];
      }
      keyed.emplace_back(std::isnan(dot) ? std::numeric_limits<double>::infinity() : dot, order[i]);
    }
    const std::size_t left = (n + kReferenceTile - 1) / kReferenceTile / 2 * kReferenceTile;
    std::nth_element(keyed.begin(), keyed.begin() + static_cast<std::ptrdiff_t>(left), keyed.end());
    for (std::size_t i = 0; i < n; ++i)
    {
      order[node.lo + i] = keyed[i].second;
    }
    todo.push_back({ node.lo, node.lo + left });
    todo.push_back({ node.lo + left, node.hi });
  }
  return order;
}

// Per tile of the ordered references: the centroid and the bounding box (the exact float
// minimum and maximum of each coordinate), padded to DP with zeros like the rows. A tile
// with a value that is not finite gets an infinite box (never skipped).
void tileBounds(const float* X, std::size_t M, int D, int DP, const std::vector<unsigned>& order,
  std::vector<float>& centroids, std::vector<float>& lo, std::vector<float>& hi)
{
  const std::size_t tiles = (M + kReferenceTile - 1) / kReferenceTile;
  centroids.assign(tiles * static_cast<std::size_t>(DP), 0.f);
  lo.assign(tiles * static_cast<std::size_t>(DP), 0.f);
  hi.assign(tiles * static_cast<std::size_t>(DP), 0.f);
  std::vector<double> mean(D);
  for (std::size_t t = 0; t < tiles; ++t)
  {
    const std::size_t first = t * kReferenceTile, last = std::min(M, first + kReferenceTile);
    float* l = lo.data() + t * DP;
    float* h = hi.data() + t * DP;
    std::fill(mean.begin(), mean.end(), 0.0);
    std::fill(l, l + D, std::numeric_limits<float>::infinity());
    std::fill(h, h + D, -std::numeric_limits<float>::infinity());
    bool finite = true;
    for (std::size_t i = first; i < last; ++i)
    {
      for (int c = 0; c < D; ++c)
      {
        const float v = X[static_cast<std::size_t>(order[i]) * D + c];
        finite = finite && std::isfinite(v);
        mean[c] += v;
        l[c] = std::min(l[c], v);
        h[c] = std::max(h[c], v);
      }
    }
    for (int c = 0; c < D; ++c)
    {
      centroids[t * DP + c] = finite ? static_cast<float>(mean[c] / static_cast<double>(last - first)) : 0.f;
      if (!finite)
      {
        l[c] = -std::numeric_limits<float>::infinity();
        h[c] = std::numeric_limits<float>::infinity();
      }
    }
  }
}

// The dot-product filter's |r|^2 per reference (tile order; the double sum rounded to float,
// within u of the exact one) and per tile the largest |r|, rounded up to a float (infinite
// when a value is not finite, so the filter rules nothing out there).
void referenceNorms(const float* X, std::size_t M, int D, const std::vector<unsigned>& order,
  std::vector<float>& norms, std::vector<float>& radius)
{
  norms.assign(M, 0.f);
  radius.assign((M + kReferenceTile - 1) / kReferenceTile, 0.f);
  for (std::size_t i = 0; i < M; ++i)
  {
    double sum = 0.0;
    for (int c = 0; c < D; ++c)
    {
      const double v = X[static_cast<std::size_t>(order[i]) * D + c];
      sum += v * v;
    }
    norms[i] = static_cast<float>(sum);
    const double length = std::sqrt(sum);
    float up = static_cast<float>(length);
    if (!std::isfinite(up))
    {
      up = std::numeric_limits<float>::infinity();
    }
    else if (static_cast<double>(up) < length)
    {
      up = std::nextafter(up, std::numeric_limits<float>::infinity());
    }
    float& r = radius[i / kReferenceTile];
    r = std::isnan(length) ? std::numeric_limits<float>::infinity() : std::max(r, up);
  }
}
} // namespace

ReferenceTiles buildReferenceTiles(const float* X, std::size_t M, int D, int DP)
{
  ReferenceTiles t;
  t.order = orderReferences(X, M, D);
  tileBounds(X, M, D, DP, t.order, t.centroids, t.lo, t.hi);
  referenceNorms(X, M, D, t.order, t.norms, t.radius);
  t.centroidNorms.resize(t.tiles());
  for (std::size_t k = 0; k < t.tiles(); ++k)
  {
    double sum = 0.0;
    for (int c = 0; c < DP; ++c)
    {
      const double v = t.centroids[k * DP + c];
      sum += v * v;
    }
    t.centroidNorms[k] = static_cast<float>(sum);
  }
  return t;
}

} // namespace cuda
} // namespace mcv
