#include "IsomapEmbedding.h"

#include "FeatureKnn.h"
#include "ReferenceSample.h"
#include "SymmetricEigenvalues.h"

#ifdef MCV_HAS_CUDA
#include "cuda/GeodesicsCuda.h"
#endif

#include <Eigen/Eigenvalues>
#include <Spectra/MatOp/DenseSymMatProd.h>
#include <Spectra/SymEigsSolver.h>
#include <boost/graph/compressed_sparse_row_graph.hpp>
#include <boost/graph/dijkstra_shortest_paths_no_color_map.hpp>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <limits>
#include <numeric>

#ifdef _OPENMP
#include <omp.h>
#endif

namespace mcv
{

namespace
{

// Symmetric weighted graph in compressed rows.
struct Graph
{
  std::vector<std::size_t> start; // n + 1
  std::vector<std::uint32_t> to;
  std::vector<float> weight;
};

// Keeps one copy of every edge (mutual neighbours and joins arrive twice). Dijkstra would
// give the same distances with the copies, but relaxes every one of them from every landmark.
// Each row is sorted on its own (in parallel: a serial pass over the 10000 rows of a 50-
// neighbour graph cost ~15 ms, the thread count times what the kNN search itself takes),
// then the rows are packed in order; a row's edges do not depend on the order they came in.
void dropDuplicateEdges(Graph& g)
{
  const std::size_t n = g.start.size() - 1;
  std::vector<std::size_t> kept(n, 0);
  const long long rows = static_cast<long long>(n);
#pragma omp parallel
  {
    std::vector<std::pair<std::uint32_t, float>> row;
#pragma omp for schedule(dynamic, 64)
    for (long long ii = 0; ii < rows; ++ii)
    {
      const std::size_t i = static_cast<std::size_t>(ii);
      row.clear();
      for (std::size_t e = g.start[i]; e < g.start[i + 1]; ++e)
      {
        row.emplace_back(g.to[e], g.weight[e]);
      }
      std::sort(row.begin(), row.end()); // equal targets: the shorter copy first
      std::size_t at = g.start[i];
      for (std::size_t r = 0; r < row.size(); ++r)
      {
        if (r == 0 || row[r].first != row[r - 1].first)
        {
          g.to[at] = row[r].first;
          g.weight[at++] = row[r].second;
        }
      }
      kept[i] = at - g.start[i];
    }
  }
  std::size_t packed = 0;
  for (std::size_t i = 0; i < n; ++i)
  {
    const std::size_t from = g.start[i];
    g.start[i] = packed;
    if (packed != from)
    {
      std::copy(g.to.begin() + static_cast<std::ptrdiff_t>(from), g.to.begin() + static_cast<std::ptrdiff_t>(from + kept[i]),
        g.to.begin() + static_cast<std::ptrdiff_t>(packed));
      std::copy(g.weight.begin() + static_cast<std::ptrdiff_t>(from),
        g.weight.begin() + static_cast<std::ptrdiff_t>(from + kept[i]), g.weight.begin() + static_cast<std::ptrdiff_t>(packed));
    }
    packed += kept[i];
  }
  g.start[n] = packed;
  g.to.resize(packed);
  g.weight.resize(packed);
}

Graph buildGraph(std::size_t n, const KnnGraph& knn, const std::vector<GraphEdge>& extra)
{
  const int K = knn.k;
  std::vector<std::size_t> degree(n, 0);
  for (std::size_t i = 0; i < n; ++i)
  {
    for (int j = 0; j < K; ++j)
    {
      ++degree[i];
      ++degree[knn.neighbors[i * K + j]];
    }
  }
  for (const GraphEdge& e : extra)
  {
    ++degree[e.a];
    ++degree[e.b];
  }
  Graph g;
  g.start.assign(n + 1, 0);
  for (std::size_t i = 0; i < n; ++i)
  {
    g.start[i + 1] = g.start[i] + degree[i];
  }
  g.to.resize(g.start[n]);
  g.weight.resize(g.start[n]);
  std::vector<std::size_t> fill(g.start.begin(), g.start.end() - 1);
  auto add = [&](std::uint32_t a, std::uint32_t b, float w) {
    g.to[fill[a]] = b;
    g.weight[fill[a]++] = w;
    g.to[fill[b]] = a;
    g.weight[fill[b]++] = w;
  };
  for (std::size_t i = 0; i < n; ++i)
  {
    for (int j = 0; j < K; ++j)
    {
      add(static_cast<std::uint32_t>(i), knn.neighbors[i * K + j], knn.distances[i * K + j]);
    }
  }
  for (const GraphEdge& e : extra)
  {
    add(e.a, e.b, e.length);
  }
  dropDuplicateEdges(g);
  return g;
}

// The same graph for Boost.Graph's Dijkstra (edges in CSR order; lengths in double, as the
// sums are). Its 4-ary indirect heap with decrease-key ties the hand-written one this replaced
// (docs/benchmarks.md, section 9) and gives bitwise the same distances.
struct EdgeLength
{
  double length;
};
using GeodesicGraph = boost::compressed_sparse_row_graph<boost::directedS, boost::no_property, EdgeLength,
  boost::no_property, std::uint32_t>;

GeodesicGraph geodesicGraph(const Graph& g)
{
  const std::size_t n = g.start.size() - 1;
  std::vector<std::pair<std::uint32_t, std::uint32_t>> edges;
  std::vector<EdgeLength> lengths;
  edges.reserve(g.to.size());
  lengths.reserve(g.to.size());
  for (std::size_t u = 0; u < n; ++u)
  {
    for (std::size_t e = g.start[u]; e < g.start[u + 1]; ++e)
    {
      edges.emplace_back(static_cast<std::uint32_t>(u), g.to[e]);
      lengths.push_back({ static_cast<double>(g.weight[e]) });
    }
  }
  return GeodesicGraph(boost::edges_are_sorted, edges.begin(), edges.end(), lengths.begin(), n);
}

// Single-source shortest paths; unreachable points stay at +inf.
void dijkstra(const GeodesicGraph& g, std::uint32_t source, double* dist)
{
  boost::dijkstra_shortest_paths_no_color_map(g, source,
    boost::weight_map(boost::get(&EdgeLength::length, g))
      .distance_map(boost::make_iterator_property_map(dist, boost::get(boost::vertex_index, g)))
      .distance_inf(std::numeric_limits<double>::infinity()));
}

// The geodesic distances from every landmark (rows of dist, L x n) on the GPU: the same bits
// as Dijkstra (cuda/GeodesicsCuda.h). False, to run Dijkstra on the host, off the GPU, for a
// graph larger than the device's shared memory holds, or on a failure (with a warning).
bool geodesicsOnDevice(Device device, const Graph& g, const std::vector<std::uint32_t>& landmarks, double* dist,
  std::vector<std::string>& warnings)
{
#ifdef MCV_HAS_CUDA
  const std::size_t n = g.start.size() - 1;
  if (device != Device::GPU || n > cuda::geodesicMaxVertices())
  {
    return false;
  }
  std::string error;
  if (cuda::geodesicDistances(n, g.start.data(), g.to.data(), g.weight.data(), landmarks.data(),
        static_cast<int>(landmarks.size()), dist, &error))
  {
    return true;
  }
  warnings.push_back("Isomap: the shortest paths on the GPU failed (" + error + "); they ran on the CPU.");
  return false;
#else
  (void)device;
  (void)g;
  (void)landmarks;
  (void)dist;
  (void)warnings;
  return false;
#endif
}

// Every eigenvalue of the symmetric B, descending, values only: on the GPU by cuSOLVER where
// the build links it (MCV_USE_CUSOLVER; the one O(L^3) step of the fit, ~100 ms on one host
// thread at L = 500; the same values to rounding), else, or if that fails, on the host's
// threads (SymmetricEigenvalues.h).
bool allEigenvalues(const Eigen::MatrixXd& B, Device device, Eigen::VectorXd& values, std::vector<std::string>& warnings)
{
#if defined(MCV_HAS_CUDA) && defined(MCV_HAS_CUSOLVER)
  if (device == Device::GPU)
  {
    Eigen::VectorXd ascending(B.rows());
    std::string error;
    if (cuda::symmetricEigenvalues(B.data(), static_cast<int>(B.rows()), ascending.data(), &error))
    {
      values = ascending.reverse();
      return true;
    }
    warnings.push_back("Isomap: the landmark MDS eigenvalues on the GPU failed (" + error + "); they were computed on the CPU.");
  }
#else
  (void)device;
  (void)warnings;
#endif
  Eigen::VectorXd ascending;
  if (!symmetricEigenvalues(B, ascending))
  {
    return false;
  }
  values = ascending.reverse();
  return true;
}

// Every eigenvalue of the symmetric B (descending; the spectrum and the variance retained
// need them all) and the eigenvectors of the top d (with their values). Only d vectors are
// used, so they come from Lanczos (Spectra) and the full spectrum from a values-only solve:
// 6x faster than the full decomposition at L = 500, 60x at L = 2000 (measured on the dev
// machine).
bool topEigenpairs(const Eigen::MatrixXd& B, int d, Device device, Eigen::VectorXd& values, Eigen::MatrixXd& vectors,
  std::vector<std::string>& warnings)
{
  const Eigen::Index L = B.rows();
  constexpr Eigen::Index kSmallForLanczos = 64;
  if (L > kSmallForLanczos)
  {
    if (!allEigenvalues(B, device, values, warnings))
    {
      return false;
    }
    Spectra::DenseSymMatProd<double> op(B);
    Spectra::SymEigsSolver<Spectra::DenseSymMatProd<double>> top(op, d, std::min<Eigen::Index>(L, std::max(2 * d + 1, 20)));
    top.init();
    top.compute(Spectra::SortRule::LargestAlge, 1000, 1e-10);
    const bool agrees = top.info() == Spectra::CompInfo::Successful &&
      (top.eigenvalues() - values.head(d)).cwiseAbs().maxCoeff() <= 1e-8 * std::max(1.0, std::abs(values[0]));
    if (agrees)
    {
      // The top d values with their vectors from the same solve: the embedding then depends
      // only on Lanczos on the host, so the GPU's spectrum (equal to rounding) leaves the
      // coordinates the CPU's, bit for bit.
      values.head(d) = top.eigenvalues();
      vectors = top.eigenvectors(); // descending, as values
      return true;
    }
    // Lanczos can stall, or miss a vector, on a degenerate top of the spectrum; the dense
    // solver below cannot.
  }
  Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig(B);
  if (eig.info() != Eigen::Success)
  {
    return false;
  }
  values = eig.eigenvalues().reverse();
  vectors = eig.eigenvectors().rowwise().reverse().leftCols(d);
  return true;
}

} // namespace

Embedding fitIsomap(const RowMatrixF& X, const IsomapOptions& options)
{
  Embedding e;
  const std::size_t n = static_cast<std::size_t>(X.rows());
  const int d = options.outputDimension;
  const int K = options.numberOfNeighbors;
  auto report = [&](const char* stage, double f) { reportStage(options.progress, stage, f); };
  e.error = neighboursError("Isomap", K, n);
  if (!e.error.empty())
  {
    return e;
  }
  if (n < static_cast<std::size_t>(d) + 1)
  {
    e.error = "Isomap: at least " + std::to_string(d + 1) + " distinct reference points are needed.";
    return e;
  }

  report("Isomap: neighbour graph", 0.0);
  std::string graphError;
  const KnnGraph knn =
    buildReferenceGraph(X.data(), n, static_cast<int>(X.cols()), K, &e.referenceRadius, options.device, &graphError);
  if (!graphError.empty())
  {
    e.warnings.push_back("Isomap: the neighbour search on the GPU failed (" + graphError + "); it ran on the CPU.");
  }
  report("Isomap: neighbour graph", 0.15);
  std::size_t components = 1;
  const std::vector<GraphEdge> joins = joinKnnComponents(X.data(), n, static_cast<int>(X.cols()), knn, &components);
  if (components > 1)
  {
    e.warnings.push_back("Isomap: the " + std::to_string(K) + "-neighbour graph has " + std::to_string(components) +
      " connected components; they were joined by their closest pairs of points (" + std::to_string(joins.size()) +
      " edges added). A larger NumberOfNeighbors avoids this.");
  }
  const Graph graph = buildGraph(n, knn, joins);
  report("Isomap: landmarks", 0.2);

  int L = std::max(d + 1, std::min<int>(options.numberOfLandmarks, static_cast<int>(n)));
  if (L != options.numberOfLandmarks)
  {
    e.warnings.push_back("Isomap: " + std::to_string(options.numberOfLandmarks) + " landmarks asked for, " +
      std::to_string(L) + " used (at least d+1, at most the reference points).");
  }
  const std::vector<std::uint32_t> landmarks = uniformLandmarks(n, L, options.seed);

  // Geodesic distances from every landmark: L x n, row-major.
  Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor> geo(L, static_cast<Eigen::Index>(n));
  report("Isomap: shortest paths", 0.2);
  if (!geodesicsOnDevice(options.device, graph, landmarks, geo.data(), e.warnings))
  {
    std::atomic<int> doneCount{ 0 };
    const GeodesicGraph geodesic = geodesicGraph(graph);
#pragma omp parallel for schedule(dynamic, 1)
    for (int l = 0; l < L; ++l)
    {
      dijkstra(geodesic, landmarks[static_cast<std::size_t>(l)], geo.row(l).data());
      const int done = ++doneCount;
#ifdef _OPENMP
      if (omp_get_thread_num() == 0)
#endif
      {
        report("Isomap: shortest paths", 0.2 + 0.7 * done / L);
      }
    }
  }
  if (!geo.allFinite())
  {
    e.error = "Isomap: internal error, unreachable points after joining the graph's components.";
    return e;
  }

  // Landmark MDS.
  report("Isomap: landmark MDS", 0.9);
  Eigen::MatrixXd delta(L, L);
  for (int a = 0; a < L; ++a)
  {
    for (int b = 0; b < L; ++b)
    {
      const double g1 = geo(a, landmarks[static_cast<std::size_t>(b)]);
      const double g2 = geo(b, landmarks[static_cast<std::size_t>(a)]);
      const double g = 0.5 * (g1 + g2);
      delta(a, b) = g * g;
    }
  }
  const Eigen::VectorXd deltaMean = delta.rowwise().mean(); // column means (delta is symmetric)
  Eigen::MatrixXd B = delta;
  B.rowwise() -= delta.colwise().mean();
  B.colwise() -= B.rowwise().mean();
  B *= -0.5;
  Eigen::VectorXd values;
  Eigen::MatrixXd vectors;
  if (!topEigenpairs(B, d, options.device, values, vectors, e.warnings))
  {
    e.error = "Isomap: the landmark MDS eigen-decomposition failed.";
    return e;
  }
  double positive = 0, top = 0;
  for (int k = 0; k < L; ++k)
  {
    e.eigenvalues.push_back(values[k]);
    if (values[k] > 0)
    {
      positive += values[k];
      top += k < d ? values[k] : 0.0;
    }
  }
  e.varianceRetained = positive > 0 ? top / positive : 0.0;

  // L# (d x L): rows v_k / sqrt(lambda_k); a non-positive lambda gives a zero coordinate.
  Eigen::MatrixXd pinv = Eigen::MatrixXd::Zero(d, L);
  for (int k = 0; k < d; ++k)
  {
    if (values[k] > 1e-12 * std::max(1.0, values[0]))
    {
      pinv.row(k) = vectors.col(k).transpose() / std::sqrt(values[k]);
    }
    else
    {
      e.warnings.push_back("Isomap: MDS eigenvalue " + std::to_string(k + 1) +
        " is not positive; that coordinate is 0 (the data has too few dimensions).");
    }
  }
  // y_i = -1/2 L# (delta_i - delta_mean), all points at once.
  Eigen::MatrixXd sq = geo.array().square().matrix();
  sq.colwise() -= deltaMean;
  Eigen::MatrixXd Y = (-0.5 * (pinv * sq)).transpose(); // n x d

  toPrincipalAxes(Y);
  e.coordinates = Y.cast<float>();
  report("Isomap: done", 1.0);
  return e;
}

} // namespace mcv
