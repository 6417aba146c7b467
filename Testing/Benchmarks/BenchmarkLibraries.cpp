// mcvBenchmarkLibraries: the core's hand-written parts against well-kept libraries, on the
// real brain features, the queries the reduction really issues, the same thread count.
//
//   1. kNN: ExactKnn's tiled brute force (TiledKnn) vs FAISS IndexFlatL2 (exact) and
//      IndexHNSWFlat (approximate): the kNN graph of the sample (k = 10, + the point itself)
//      and the out-of-sample 3-NN of many voxels against a 10000-vector reference sample.
//   2. Isomap's geodesic stage (L Dijkstras over the symmetric kNN graph): the former
//      hand-written IndexedMinHeap
//      vs std::priority_queue with lazy deletion vs Boost.Graph dijkstra_shortest_paths (and
//      its _no_color_map variant).
//   (3. the SIMD Cholesky builds were measured on the whole LLE fit with mcvReduceCLI:
//      benchmark_cholesky.py, docs/benchmarks.md, section 9.)
//
// Input: the float32 files of dump_brain_samples.py (same samples as compare_sklearn.py).
//   dump_brain_samples.py --out /tmp/mcv_libbench
//   OPENBLAS_NUM_THREADS=2 mcvBenchmarkLibraries --data /tmp/mcv_libbench [--threads 2]
//       [--rounds 7] [--sizes 2000,5000,10000] [--parts knn,oos,dijkstra] [--queries 200000]
//       [--dijkstra-neighbors 10,50]   (K of the Isomap graph: compare_sklearn's 10, the filter's 50)
// Every variant of a row runs once per round, in rotating order, and the minimum over the
// rounds is reported: the 2-core machine is shared with other builds, minima of alternating
// runs are what survives that noise.
#include "ExactKnn.h"
#include "FeatureKnn.h"
#include "ReferenceSample.h"
#include "TiledKnn.h"

#include <faiss/IndexFlat.h>
#include <faiss/IndexHNSW.h>

#include <boost/graph/compressed_sparse_row_graph.hpp>
#include <boost/graph/dijkstra_shortest_paths.hpp>
#include <boost/graph/dijkstra_shortest_paths_no_color_map.hpp>

#include <omp.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <functional>
#include <limits>
#include <map>
#include <memory>
#include <queue>
#include <string>
#include <vector>

namespace
{
using Clock = std::chrono::steady_clock;

double msSince(Clock::time_point t0)
{
  return std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
}

std::vector<float> readRows(const std::string& path, int D, std::size_t* rows)
{
  std::ifstream in(path, std::ios::binary | std::ios::ate);
  if (!in)
  {
    std::fprintf(stderr, "cannot read %s (run Testing/Benchmarks/dump_brain_samples.py)\n", path.c_str());
    std::exit(2);
  }
  const std::size_t bytes = static_cast<std::size_t>(in.tellg());
  *rows = bytes / (sizeof(float) * static_cast<std::size_t>(D));
  std::vector<float> v(*rows * static_cast<std::size_t>(D));
  in.seekg(0);
  in.read(reinterpret_cast<char*>(v.data()), static_cast<std::streamsize>(v.size() * sizeof(float)));
  return v;
}

// Runs every variant once per round, rotating the order, and returns the minima (ms).
std::vector<double> alternate(int rounds, const std::vector<std::function<void()>>& variants)
{
  std::vector<double> best(variants.size(), std::numeric_limits<double>::infinity());
  for (int r = 0; r < rounds; ++r)
  {
    for (std::size_t s = 0; s < variants.size(); ++s)
    {
      const std::size_t v = (s + static_cast<std::size_t>(r)) % variants.size();
      const auto t0 = Clock::now();
      variants[v]();
      best[v] = std::min(best[v], msSince(t0));
    }
  }
  return best;
}

// ---- 1. kNN ------------------------------------------------------------------------------

// k exact neighbours per row from float candidates (kp per row, any order) by the canonical
// rule (ExactKnn.h); no proof of exactness: that would need a bound on FAISS's distances.
void rerank(const float* queries, std::size_t count, const float* refs, int D, const faiss::Index::idx_t* cand,
  int kp, int k, std::uint32_t* idx, double* d2)
{
#pragma omp parallel for schedule(static)
  for (long long r = 0; r < static_cast<long long>(count); ++r)
  {
    std::pair<double, std::uint32_t> p[64];
    int valid = 0;
    for (int s = 0; s < kp; ++s)
    {
      const auto c = cand[r * kp + s];
      if (c < 0)
      {
        continue;
      }
      p[valid++] = { mcv::canonicalSquaredDistance(queries + r * D, refs + c * D, D), static_cast<std::uint32_t>(c) };
    }
    std::sort(p, p + valid);
    for (int j = 0; j < k; ++j)
    {
      idx[r * k + j] = j < valid ? p[j].second : 0xffffffffu;
      d2[r * k + j] = j < valid ? p[j].first : INFINITY;
    }
  }
}

// Rows whose neighbour lists differ from the reference answer, and of those how many
// differ only by a permutation of exactly equal canonical distances (ties).
struct Agreement
{
  std::size_t rows = 0, differ = 0, tiesOnly = 0, recallHits = 0;
};
Agreement agree(const std::vector<std::uint32_t>& ref, const std::vector<double>& refD2,
  const std::vector<std::uint32_t>& got, const std::vector<double>& gotD2, int k)
{
  Agreement a;
  a.rows = ref.size() / k;
  for (std::size_t r = 0; r < a.rows; ++r)
  {
    bool same = true, tie = true;
    for (int j = 0; j < k; ++j)
    {
      const std::size_t i = r * k + j;
      same = same && ref[i] == got[i];
      tie = tie && refD2[i] == gotD2[i];
      for (int m = 0; m < k; ++m)
      {
        a.recallHits += got[r * k + m] == ref[i];
      }
    }
    a.differ += !same;
    a.tiesOnly += !same && tie;
  }
  return a;
}

std::string agreementText(const Agreement& a, int k)
{
  char s[160];
  std::snprintf(s, sizeof s, "%zu/%zu rows differ (%zu ties only), recall %.4f", a.differ, a.rows, a.tiesOnly,
    static_cast<double>(a.recallHits) / (static_cast<double>(a.rows) * k));
  return s;
}

// The kNN graph query of buildKnnGraph: every sample point against the sample, k + 1.
void benchKnnGraph(const std::string& dir, const std::vector<int>& sizes, int rounds)
{
  const int D = 24, K = 10, k1 = K + 1, kp = k1 + mcv::kKnnCandidateMargin;
  std::printf("\n== 1a. kNN graph of the 24D sample (k = %d + self; %d candidates for the canonical rule), "
              "%d threads, min of %d alternating rounds\n",
    K, kp, omp_get_max_threads(), rounds);
  std::printf("%6s | %10s %10s %10s %10s | %8s %8s | %s\n", "N", "tiled ms", "faissFl ms", "tiledC ms", "faissC ms",
    "fl/tiled", "hnsw ms", "agreement");
  for (int n : sizes)
  {
    std::size_t N = 0;
    const std::vector<float> X = readRows(dir + "/24D_N" + std::to_string(n) + ".f32", D, &N);
    // Hand-written: ExactKnn (tiled candidates + canonical rule + proof), blocks of 256 as
    // buildKnnGraph issues them.
    std::vector<std::uint32_t> tIdx(N * k1);
    std::vector<double> tD2(N * k1);
    auto tiled = [&] {
      const mcv::ExactKnn knn(X.data(), N, D, mcv::KnnMethod::BruteForce);
      const long long blocks = static_cast<long long>((N + mcv::kKnnQueryBlock - 1) / mcv::kKnnQueryBlock);
#pragma omp parallel for schedule(dynamic, 1)
      for (long long b = 0; b < blocks; ++b)
      {
        const std::size_t first = static_cast<std::size_t>(b) * mcv::kKnnQueryBlock;
        const std::size_t count = std::min(mcv::kKnnQueryBlock, N - first);
        knn.query(X.data() + first * D, count, k1, tIdx.data() + first * k1, tD2.data() + first * k1);
      }
    };
    // The float candidate pass alone (what FAISS would replace).
    std::vector<std::uint32_t> cIdx(N * kp);
    std::vector<float> cF(N * kp);
    auto tiledCandidates = [&] {
      const mcv::TiledKnn t(X.data(), N, D);
      const long long blocks = static_cast<long long>((N + mcv::kKnnQueryBlock - 1) / mcv::kKnnQueryBlock);
#pragma omp parallel for schedule(dynamic, 1)
      for (long long b = 0; b < blocks; ++b)
      {
        const std::size_t first = static_cast<std::size_t>(b) * mcv::kKnnQueryBlock;
        const std::size_t count = std::min(mcv::kKnnQueryBlock, N - first);
        t.candidates(X.data() + first * D, count, kp, cIdx.data() + first * kp, cF.data() + first * kp);
      }
    };
    // FAISS exact: one search of all rows (its best call: BLAS tiles, OpenMP over them),
    // then the same canonical re-ranking of its kp candidates.
    std::vector<faiss::Index::idx_t> fLab(N * kp);
    std::vector<float> fDist(N * kp);
    std::vector<std::uint32_t> fIdx(N * k1);
    std::vector<double> fD2(N * k1);
    auto faissCandidates = [&] {
      faiss::IndexFlatL2 index(D);
      index.add(static_cast<faiss::Index::idx_t>(N), X.data());
      index.search(static_cast<faiss::Index::idx_t>(N), X.data(), kp, fDist.data(), fLab.data());
    };
    auto faissFlat = [&] {
      faissCandidates();
      rerank(X.data(), N, X.data(), D, fLab.data(), kp, k1, fIdx.data(), fD2.data());
    };
    // FAISS HNSW (approximate): build + search k1 (no canonical re-ranking needed for timing).
    std::vector<faiss::Index::idx_t> hLab(N * k1);
    std::vector<float> hDist(N * k1);
    std::vector<std::uint32_t> hIdx(N * k1);
    std::vector<double> hD2(N * k1);
    auto hnsw = [&] {
      faiss::IndexHNSWFlat index(D, 32);
      index.hnsw.efConstruction = 40;
      index.hnsw.efSearch = 32;
      index.add(static_cast<faiss::Index::idx_t>(N), X.data());
      index.search(static_cast<faiss::Index::idx_t>(N), X.data(), k1, hDist.data(), hLab.data());
    };
    const std::vector<double> t = alternate(rounds, { tiled, faissFlat, tiledCandidates, faissCandidates, hnsw });
    rerank(X.data(), N, X.data(), D, hLab.data(), k1, k1, hIdx.data(), hD2.data());
    // FAISS's own order (float distances of its formula, its tie order) vs the canonical.
    std::vector<std::uint32_t> rawIdx(N * k1);
    std::vector<double> rawD2(N * k1);
    for (std::size_t r = 0; r < N; ++r)
    {
      for (int j = 0; j < k1; ++j)
      {
        rawIdx[r * k1 + j] = static_cast<std::uint32_t>(fLab[r * kp + j]);
        rawD2[r * k1 + j] = mcv::canonicalSquaredDistance(X.data() + r * D, X.data() + fLab[r * kp + j] * D, D);
      }
    }
    std::printf("%6d | %10.2f %10.2f %10.2f %10.2f | %7.2fx %8.2f | faiss flat+rerank: %s; faiss flat raw order: "
                "%s; hnsw: %s\n",
      n, t[0], t[1], t[2], t[3], t[1] / t[0], t[4], agreementText(agree(tIdx, tD2, fIdx, fD2, k1), k1).c_str(),
      agreementText(agree(tIdx, tD2, rawIdx, rawD2, k1), k1).c_str(),
      agreementText(agree(tIdx, tD2, hIdx, hD2, k1), k1).c_str());
    std::fflush(stdout);
  }
}

// Out-of-sample: many voxels against the 10000-vector reference sample, k = 3.
void benchOutOfSample(const std::string& dir, int rounds, std::size_t maxQueries)
{
  const int D = 24, k = 3, kp = k + mcv::kKnnCandidateMargin;
  std::size_t M = 0, Q = 0;
  const std::vector<float> R = readRows(dir + "/24D_N10000.f32", D, &M);
  std::vector<float> V = readRows(dir + "/24D_voxels.f32", D, &Q);
  Q = std::min(Q, maxQueries);
  std::printf("\n== 1b. out-of-sample 3-NN of %zu real 24D voxels against the %zu-vector reference sample, "
              "%d threads, min of %d alternating rounds\n",
    Q, M, omp_get_max_threads(), rounds);
  std::vector<std::uint32_t> tIdx(Q * k);
  std::vector<double> tD2(Q * k);
  // As OutOfSample.cpp issues it: blocks of 256 rows, OpenMP over blocks, one index.
  auto tiled = [&] {
    const mcv::ExactKnn knn(R.data(), M, D, mcv::KnnMethod::BruteForce);
    const long long blocks = static_cast<long long>((Q + mcv::kKnnQueryBlock - 1) / mcv::kKnnQueryBlock);
#pragma omp parallel for schedule(dynamic, 1)
    for (long long b = 0; b < blocks; ++b)
    {
      const std::size_t first = static_cast<std::size_t>(b) * mcv::kKnnQueryBlock;
      const std::size_t count = std::min(mcv::kKnnQueryBlock, Q - first);
      knn.query(V.data() + first * D, count, k, tIdx.data() + first * k, tD2.data() + first * k);
    }
  };
  std::vector<faiss::Index::idx_t> fLab(Q * kp);
  std::vector<float> fDist(Q * kp);
  std::vector<std::uint32_t> fIdx(Q * k);
  std::vector<double> fD2(Q * k);
  auto faissFlat = [&] {
    faiss::IndexFlatL2 index(D);
    index.add(static_cast<faiss::Index::idx_t>(M), R.data());
    index.search(static_cast<faiss::Index::idx_t>(Q), V.data(), kp, fDist.data(), fLab.data());
    rerank(V.data(), Q, R.data(), D, fLab.data(), kp, k, fIdx.data(), fD2.data());
  };
  std::vector<faiss::Index::idx_t> hLab(Q * k);
  std::vector<float> hDist(Q * k);
  double hBuild = std::numeric_limits<double>::infinity(), hSearch = hBuild;
  auto hnsw = [&] {
    const auto t0 = Clock::now();
    faiss::IndexHNSWFlat index(D, 32);
    index.hnsw.efConstruction = 40;
    index.hnsw.efSearch = 32;
    index.add(static_cast<faiss::Index::idx_t>(M), R.data());
    hBuild = std::min(hBuild, msSince(t0));
    const auto t1 = Clock::now();
    index.search(static_cast<faiss::Index::idx_t>(Q), V.data(), k, hDist.data(), hLab.data());
    hSearch = std::min(hSearch, msSince(t1));
  };
  const std::vector<double> t = alternate(rounds, { tiled, faissFlat, hnsw });
  std::vector<std::uint32_t> hIdx(Q * k);
  std::vector<double> hD2(Q * k);
  rerank(V.data(), Q, R.data(), D, hLab.data(), k, k, hIdx.data(), hD2.data());
  std::printf("tiled %.1f ms | faiss flat + rerank %.1f ms (%.2fx the tiled time) | faiss hnsw (M 32, efC 40, "
              "efS 32) build + search %.1f ms (%.2fx)\n",
    t[0], t[1], t[1] / t[0], t[2], t[2] / t[0]);
  std::printf("  per query: tiled %.2f us, faiss flat %.2f us; hnsw build %.1f ms once, then %.2f us per query\n",
    1000 * t[0] / Q, 1000 * t[1] / Q, hBuild, 1000 * hSearch / Q);
  std::printf("  faiss flat + rerank: %s; hnsw: %s\n", agreementText(agree(tIdx, tD2, fIdx, fD2, k), k).c_str(),
    agreementText(agree(tIdx, tD2, hIdx, hD2, k), k).c_str());
  std::fflush(stdout);
}

// ---- 2. Dijkstra -------------------------------------------------------------------------

struct Csr
{
  std::vector<std::size_t> start;
  std::vector<std::uint32_t> to;
  std::vector<float> weight;
};

// IsomapEmbedding.cpp's buildGraph: both directions of every kNN edge and join, one copy
// of each (the shorter), rows sorted by target.
Csr isomapGraph(const float* X, std::size_t n, int D, int K)
{
  const mcv::KnnGraph knn = mcv::buildKnnGraph(X, n, D, K);
  std::size_t components = 0;
  const std::vector<mcv::GraphEdge> joins = mcv::joinKnnComponents(X, n, D, knn, &components);
  std::vector<std::vector<std::pair<std::uint32_t, float>>> rows(n);
  for (std::size_t i = 0; i < n; ++i)
  {
    for (int j = 0; j < K; ++j)
    {
      const std::uint32_t b = knn.neighbors[i * K + j];
      rows[i].emplace_back(b, knn.distances[i * K + j]);
      rows[b].emplace_back(static_cast<std::uint32_t>(i), knn.distances[i * K + j]);
    }
  }
  for (const auto& e : joins)
  {
    rows[e.a].emplace_back(e.b, e.length);
    rows[e.b].emplace_back(e.a, e.length);
  }
  Csr g;
  g.start.push_back(0);
  for (auto& row : rows)
  {
    std::sort(row.begin(), row.end());
    for (std::size_t r = 0; r < row.size(); ++r)
    {
      if (r == 0 || row[r].first != row[r - 1].first)
      {
        g.to.push_back(row[r].first);
        g.weight.push_back(row[r].second);
      }
    }
    g.start.push_back(g.to.size());
  }
  return g;
}

// The hand-written 4-ary min-heap with decrease-key that IsomapEmbedding.cpp used until
// Boost.Graph replaced it (Filters/Core/IndexedMinHeap.h before that commit), kept here as
// the baseline of this comparison.
class IndexedMinHeap
{
public:
  static constexpr std::uint32_t kAbsent = 0xffffffffu;

  // Empties the heap for items 0..n-1.
  void reset(std::size_t n)
  {
    heap_.clear();
    position_.assign(n, kAbsent);
  }
  bool empty() const { return heap_.empty(); }

  // Inserts item with key, or moves it up to its new, smaller key.
  void pushOrDecrease(std::uint32_t item, double key)
  {
    std::uint32_t at = position_[item];
    if (at == kAbsent)
    {
      at = static_cast<std::uint32_t>(heap_.size());
      heap_.push_back({ key, item });
    }
    siftUp(at, { key, item });
  }

  std::uint32_t popMin()
  {
    const std::uint32_t top = heap_.front().item;
    position_[top] = kAbsent;
    const Entry last = heap_.back();
    heap_.pop_back();
    if (!heap_.empty())
    {
      siftDown(0, last);
    }
    return top;
  }

private:
  struct Entry
  {
    double key;
    std::uint32_t item;
  };
  void place(std::uint32_t at, const Entry& entry)
  {
    heap_[at] = entry;
    position_[entry.item] = at;
  }
  void siftUp(std::uint32_t at, const Entry& entry)
  {
    while (at > 0)
    {
      const std::uint32_t parent = (at - 1) / 4;
      if (!(entry.key < heap_[parent].key))
      {
        break;
      }
      place(at, heap_[parent]);
      at = parent;
    }
    place(at, entry);
  }
  void siftDown(std::uint32_t at, const Entry& entry)
  {
    const std::size_t size = heap_.size();
    for (;;)
    {
      const std::size_t first = 4 * static_cast<std::size_t>(at) + 1;
      if (first >= size)
      {
        break;
      }
      std::size_t best = first;
      const std::size_t end = first + 4 < size ? first + 4 : size;
      for (std::size_t c = first + 1; c < end; ++c)
      {
        if (heap_[c].key < heap_[best].key)
        {
          best = c;
        }
      }
      if (!(heap_[best].key < entry.key))
      {
        break;
      }
      place(at, heap_[best]);
      at = static_cast<std::uint32_t>(best);
    }
    place(at, entry);
  }

  std::vector<Entry> heap_;
  std::vector<std::uint32_t> position_;
};

// IsomapEmbedding.cpp's former dijkstra (IndexedMinHeap, decrease-key).
void dijkstraIndexed(const Csr& g, std::uint32_t source, double* dist, IndexedMinHeap& heap)
{
  const std::size_t n = g.start.size() - 1;
  std::fill(dist, dist + n, std::numeric_limits<double>::infinity());
  heap.reset(n);
  dist[source] = 0;
  heap.pushOrDecrease(source, 0.0);
  while (!heap.empty())
  {
    const std::uint32_t u = heap.popMin();
    const double du = dist[u];
    for (std::size_t e = g.start[u]; e < g.start[u + 1]; ++e)
    {
      const std::uint32_t v = g.to[e];
      const double dv = du + static_cast<double>(g.weight[e]);
      if (dv < dist[v])
      {
        dist[v] = dv;
        heap.pushOrDecrease(v, dv);
      }
    }
  }
}

// std::priority_queue with lazy deletion: a new entry per improvement, stale ones skipped.
using LazyQueue = std::priority_queue<std::pair<double, std::uint32_t>, std::vector<std::pair<double, std::uint32_t>>,
  std::greater<std::pair<double, std::uint32_t>>>;
void dijkstraLazy(const Csr& g, std::uint32_t source, double* dist, LazyQueue& queue)
{
  const std::size_t n = g.start.size() - 1;
  std::fill(dist, dist + n, std::numeric_limits<double>::infinity());
  dist[source] = 0;
  queue.push({ 0.0, source });
  while (!queue.empty())
  {
    const auto [du, u] = queue.top();
    queue.pop();
    if (du > dist[u])
    {
      continue; // stale
    }
    for (std::size_t e = g.start[u]; e < g.start[u + 1]; ++e)
    {
      const std::uint32_t v = g.to[e];
      const double dv = du + static_cast<double>(g.weight[e]);
      if (dv < dist[v])
      {
        dist[v] = dv;
        queue.push({ dv, v });
      }
    }
  }
}

struct EdgeWeight
{
  double w;
};
using BoostGraph =
  boost::compressed_sparse_row_graph<boost::directedS, boost::no_property, EdgeWeight, boost::no_property, std::uint32_t>;

BoostGraph toBoost(const Csr& g)
{
  const std::size_t n = g.start.size() - 1;
  std::vector<std::pair<std::uint32_t, std::uint32_t>> edges;
  std::vector<EdgeWeight> w;
  edges.reserve(g.to.size());
  w.reserve(g.to.size());
  for (std::size_t u = 0; u < n; ++u)
  {
    for (std::size_t e = g.start[u]; e < g.start[u + 1]; ++e)
    {
      edges.emplace_back(static_cast<std::uint32_t>(u), g.to[e]);
      w.push_back({ static_cast<double>(g.weight[e]) });
    }
  }
  return BoostGraph(boost::edges_are_sorted, edges.begin(), edges.end(), w.begin(), n);
}

void benchDijkstra(const std::string& dir, const std::vector<int>& sizes, int rounds, int K)
{
  const int L = 500;
  std::printf("\n== 2. Isomap's geodesic stage: L = %d Dijkstras over the K = %d graph of the sample, %d threads, "
              "min of %d alternating rounds\n",
    L, K, omp_get_max_threads(), rounds);
  std::printf("%4s %6s %8s | %11s %11s %11s %11s | %9s %9s %9s | %s\n", "set", "N", "edges", "indexed ms",
    "lazy pq ms", "boost ms", "boost-nc ms", "lazy/idx", "boost/idx", "b-nc/idx", "same distances");
  for (int D : { 6, 24 })
  {
    for (int n : sizes)
    {
      std::size_t N = 0;
      const std::vector<float> X = readRows(dir + "/" + std::to_string(D) + "D_N" + std::to_string(n) + ".f32", D, &N);
      const Csr g = isomapGraph(X.data(), N, D, K);
      const std::vector<std::uint32_t> landmarks = mcv::uniformLandmarks(N, L, 0);
      std::vector<double> a(static_cast<std::size_t>(L) * N), b(a.size()), c(a.size());
      auto indexed = [&] {
#pragma omp parallel
        {
          IndexedMinHeap heap;
#pragma omp for schedule(dynamic, 1)
          for (int l = 0; l < L; ++l)
          {
            dijkstraIndexed(g, landmarks[l], a.data() + static_cast<std::size_t>(l) * N, heap);
          }
        }
      };
      auto lazy = [&] {
#pragma omp parallel
        {
          LazyQueue queue;
#pragma omp for schedule(dynamic, 1)
          for (int l = 0; l < L; ++l)
          {
            dijkstraLazy(g, landmarks[l], b.data() + static_cast<std::size_t>(l) * N, queue);
          }
        }
      };
      // Boost: its CSR graph built from ours (counted: a replacement would build it once
      // per fit), dijkstra_shortest_paths with its defaults (4-ary indirect heap, colour map).
      auto boostGraph = [&] {
        const BoostGraph bg = toBoost(g);
#pragma omp parallel for schedule(dynamic, 1)
        for (int l = 0; l < L; ++l)
        {
          double* dist = c.data() + static_cast<std::size_t>(l) * N;
          boost::dijkstra_shortest_paths(bg, landmarks[l],
            boost::weight_map(boost::get(&EdgeWeight::w, bg))
              .distance_map(boost::make_iterator_property_map(dist, boost::get(boost::vertex_index, bg))));
        }
      };
      // The same without the colour map (Boost's leaner variant).
      std::vector<double> e(a.size());
      auto boostNoColor = [&] {
        const BoostGraph bg = toBoost(g);
#pragma omp parallel for schedule(dynamic, 1)
        for (int l = 0; l < L; ++l)
        {
          double* dist = e.data() + static_cast<std::size_t>(l) * N;
          boost::dijkstra_shortest_paths_no_color_map(bg, landmarks[l],
            boost::weight_map(boost::get(&EdgeWeight::w, bg))
              .distance_map(boost::make_iterator_property_map(dist, boost::get(boost::vertex_index, bg)))
              .distance_inf(std::numeric_limits<double>::infinity()));
        }
      };
      const std::vector<double> t = alternate(rounds, { indexed, lazy, boostGraph, boostNoColor });
      const bool same = std::memcmp(a.data(), b.data(), a.size() * sizeof(double)) == 0 &&
        std::memcmp(a.data(), c.data(), a.size() * sizeof(double)) == 0 &&
        std::memcmp(a.data(), e.data(), a.size() * sizeof(double)) == 0;
      std::printf("%3dD %6d %8zu | %11.2f %11.2f %11.2f %11.2f | %8.2fx %8.2fx %8.2fx | %s\n", D, n, g.to.size(), t[0],
        t[1], t[2], t[3], t[1] / t[0], t[2] / t[0], t[3] / t[0], same ? "yes (bitwise)" : "NO");
      std::fflush(stdout);
    }
  }
}

std::vector<int> parseList(const std::string& s)
{
  std::vector<int> v;
  std::size_t p = 0;
  while (p < s.size())
  {
    const std::size_t q = s.find(',', p);
    v.push_back(std::stoi(s.substr(p, q - p)));
    p = q == std::string::npos ? s.size() : q + 1;
  }
  return v;
}
} // namespace

int main(int argc, char** argv)
{
  std::map<std::string, std::string> a{ { "data", "/tmp/mcv_libbench" }, { "threads", "2" }, { "rounds", "7" },
    { "sizes", "2000,5000,10000" }, { "parts", "knn,oos,dijkstra" }, { "queries", "200000" },
    { "dijkstra-neighbors", "10" } };
  for (int i = 1; i + 1 < argc; i += 2)
  {
    a[argv[i] + 2] = argv[i + 1];
  }
  omp_set_num_threads(std::stoi(a["threads"]));
#pragma omp parallel
  {
  }
  const int rounds = std::stoi(a["rounds"]);
  const std::vector<int> sizes = parseList(a["sizes"]);
  const std::string parts = a["parts"];
  const char* blas = std::getenv("OPENBLAS_NUM_THREADS");
  std::printf("mcvBenchmarkLibraries: %d OpenMP threads, CPU kNN kernel %s, OPENBLAS_NUM_THREADS=%s\n",
    omp_get_max_threads(), mcv::TiledKnn::vectorKernel() ? "AVX2+FMA" : "portable", blas ? blas : "(unset)");
  if (parts.find("knn") != std::string::npos)
  {
    benchKnnGraph(a["data"], sizes, rounds);
  }
  if (parts.find("oos") != std::string::npos)
  {
    benchOutOfSample(a["data"], rounds, std::stoull(a["queries"]));
  }
  if (parts.find("dijkstra") != std::string::npos)
  {
    for (int K : parseList(a["dijkstra-neighbors"]))
    {
      benchDijkstra(a["data"], sizes, rounds, K);
    }
  }
  return 0;
}
