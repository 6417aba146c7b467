#include "UMAPGraph.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <utility>

namespace mcv
{

namespace
{
// umap-learn's constants (umap_.py).
constexpr int kSmoothKIterations = 64;
constexpr double kSmoothKTolerance = 1e-5;
constexpr double kMinKDistScale = 1e-3;

// Compressed rows of (neighbour, value) pairs.
struct Rows
{
  std::vector<std::size_t> start;
  std::vector<std::pair<std::uint32_t, float>> entries;
};

// The directed memberships p_(j|i), each row sorted by neighbour, zeros left out.
Rows directedMemberships(const KnnGraph& knn, const std::vector<float>& sigma, const std::vector<float>& rho)
{
  const std::size_t n = knn.n;
  const int K = knn.k;
  Rows p;
  p.start.resize(n + 1);
  p.entries.resize(n * static_cast<std::size_t>(K));
  std::vector<int> kept(n);
#pragma omp parallel for schedule(static)
  for (long long ii = 0; ii < static_cast<long long>(n); ++ii)
  {
    const std::size_t i = static_cast<std::size_t>(ii);
    auto* row = p.entries.data() + i * K;
    int m = 0;
    for (int j = 0; j < K; ++j)
    {
      const float d = knn.distances[i * K + j] - rho[i];
      const float v = (d <= 0.f || sigma[i] == 0.f) ? 1.f : static_cast<float>(std::exp(-(d / sigma[i])));
      if (v > 0.f)
      {
        row[m++] = { knn.neighbors[i * K + j], v };
      }
    }
    std::sort(row, row + m);
    kept[i] = m;
  }
  // Compact the rows (most are full).
  std::size_t at = 0;
  for (std::size_t i = 0; i < n; ++i)
  {
    p.start[i] = at;
    std::copy(p.entries.begin() + static_cast<std::ptrdiff_t>(i * K),
      p.entries.begin() + static_cast<std::ptrdiff_t>(i * K + kept[i]), p.entries.begin() + static_cast<std::ptrdiff_t>(at));
    at += static_cast<std::size_t>(kept[i]);
  }
  p.start[n] = at;
  p.entries.resize(at);
  return p;
}

Rows transposed(const Rows& p, std::size_t n)
{
  Rows t;
  t.start.assign(n + 1, 0);
  for (const auto& e : p.entries)
  {
    ++t.start[e.first + 1];
  }
  for (std::size_t i = 0; i < n; ++i)
  {
    t.start[i + 1] += t.start[i];
  }
  t.entries.resize(p.entries.size());
  std::vector<std::size_t> fill(t.start.begin(), t.start.end() - 1);
  for (std::size_t i = 0; i < n; ++i) // rows in order: every transposed row comes out sorted
  {
    for (std::size_t e = p.start[i]; e < p.start[i + 1]; ++e)
    {
      t.entries[fill[p.entries[e].first]++] = { static_cast<std::uint32_t>(i), p.entries[e].second };
    }
  }
  return t;
}

// Row i of the fuzzy union a + b - a b of two row-sorted matrices, handed to emit(j, w).
template <class Emit>
void unionRow(const Rows& a, const Rows& b, std::size_t i, Emit emit)
{
  std::size_t x = a.start[i], y = b.start[i];
  const std::size_t xEnd = a.start[i + 1], yEnd = b.start[i + 1];
  while (x < xEnd || y < yEnd)
  {
    if (y == yEnd || (x < xEnd && a.entries[x].first < b.entries[y].first))
    {
      emit(a.entries[x].first, a.entries[x].second);
      ++x;
    }
    else if (x == xEnd || b.entries[y].first < a.entries[x].first)
    {
      emit(b.entries[y].first, b.entries[y].second);
      ++y;
    }
    else
    {
      const float u = a.entries[x].second, v = b.entries[y].second;
      emit(a.entries[x].first, u + v - u * v);
      ++x;
      ++y;
    }
  }
}
} // namespace

void smoothKnnDistances(const float* distances, std::size_t n, int K, float* sigma, float* rho)
{
  // umap-learn's rows hold the point itself first (distance 0): K + 1 "neighbours".
  const double target = std::log2(static_cast<double>(K) + 1.0);
  double total = 0;
  for (std::size_t e = 0; e < n * static_cast<std::size_t>(K); ++e)
  {
    total += distances[e];
  }
  const double meanDistance = n > 0 ? total / (static_cast<double>(n) * (K + 1)) : 0.0;
#pragma omp parallel for schedule(static)
  for (long long ii = 0; ii < static_cast<long long>(n); ++ii)
  {
    const std::size_t i = static_cast<std::size_t>(ii);
    const float* d = distances + i * static_cast<std::size_t>(K);
    // local_connectivity = 1: rho is the nearest non-zero distance (duplicates skipped).
    float r = 0.f;
    double rowSum = 0;
    for (int j = 0; j < K; ++j)
    {
      rowSum += d[j];
      if (r == 0.f && d[j] > 0.f)
      {
        r = d[j];
      }
    }
    double lo = 0.0, hi = std::numeric_limits<double>::infinity(), mid = 1.0;
    for (int it = 0; it < kSmoothKIterations; ++it)
    {
      double psum = 0;
      for (int j = 0; j < K; ++j)
      {
        const double x = static_cast<double>(d[j] - r);
        psum += x > 0 ? std::exp(-(x / mid)) : 1.0;
      }
      if (std::abs(psum - target) < kSmoothKTolerance)
      {
        break;
      }
      if (psum > target)
      {
        hi = mid;
        mid = 0.5 * (lo + hi);
      }
      else
      {
        lo = mid;
        mid = std::isinf(hi) ? 2.0 * mid : 0.5 * (lo + hi);
      }
    }
    // A floor against a collapse of sigma where nearly all neighbours sit at rho.
    const double floorScale = r > 0.f ? rowSum / (K + 1) : meanDistance;
    sigma[i] = static_cast<float>(std::max(mid, kMinKDistScale * floorScale));
    rho[i] = r;
  }
}

FuzzyGraph fuzzySimplicialSet(const KnnGraph& knn)
{
  const std::size_t n = knn.n;
  std::vector<float> sigma(n), rho(n);
  smoothKnnDistances(knn.distances.data(), n, knn.k, sigma.data(), rho.data());
  const Rows p = directedMemberships(knn, sigma, rho);
  const Rows pt = transposed(p, n);

  FuzzyGraph g;
  g.n = n;
  g.start.assign(n + 1, 0);
#pragma omp parallel for schedule(static)
  for (long long i = 0; i < static_cast<long long>(n); ++i)
  {
    std::size_t count = 0;
    unionRow(p, pt, static_cast<std::size_t>(i), [&](std::uint32_t, float) { ++count; });
    g.start[static_cast<std::size_t>(i) + 1] = count;
  }
  for (std::size_t i = 0; i < n; ++i)
  {
    g.start[i + 1] += g.start[i];
  }
  g.to.resize(g.start[n]);
  g.weight.resize(g.start[n]);
#pragma omp parallel for schedule(static)
  for (long long i = 0; i < static_cast<long long>(n); ++i)
  {
    std::size_t at = g.start[static_cast<std::size_t>(i)];
    unionRow(p, pt, static_cast<std::size_t>(i), [&](std::uint32_t j, float w) {
      g.to[at] = j;
      g.weight[at++] = w;
    });
  }
  return g;
}

void dropWeakEdges(FuzzyGraph& g, float threshold)
{
  std::size_t kept = 0, rowBegin = 0;
  for (std::size_t i = 0; i < g.n; ++i)
  {
    const std::size_t rowEnd = g.start[i + 1];
    g.start[i] = kept;
    for (std::size_t e = rowBegin; e < rowEnd; ++e)
    {
      if (g.weight[e] >= threshold)
      {
        g.to[kept] = g.to[e];
        g.weight[kept++] = g.weight[e];
      }
    }
    rowBegin = rowEnd;
  }
  g.start[g.n] = kept;
  g.to.resize(kept);
  g.weight.resize(kept);
}

std::size_t connectedComponents(const FuzzyGraph& g, std::vector<std::uint32_t>& label)
{
  constexpr std::uint32_t kUnseen = std::numeric_limits<std::uint32_t>::max();
  label.assign(g.n, kUnseen);
  std::vector<std::uint32_t> stack;
  std::uint32_t count = 0;
  for (std::size_t s = 0; s < g.n; ++s)
  {
    if (label[s] != kUnseen)
    {
      continue;
    }
    label[s] = count;
    stack.assign(1, static_cast<std::uint32_t>(s));
    while (!stack.empty())
    {
      const std::uint32_t u = stack.back();
      stack.pop_back();
      for (std::size_t e = g.start[u]; e < g.start[u + 1]; ++e)
      {
        if (label[g.to[e]] == kUnseen)
        {
          label[g.to[e]] = count;
          stack.push_back(g.to[e]);
        }
      }
    }
    ++count;
  }
  return count;
}

} // namespace mcv
