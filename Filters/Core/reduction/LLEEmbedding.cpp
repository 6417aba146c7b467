#include "LLEEmbedding.h"

#include "BarycentricWeights.h"
#include "ExactKnn.h"
#include "FeatureKnn.h"
#include "LLELandmarks.h"
#include "ReferenceSample.h"

#include <algorithm>
#include <cmath>
#include <utility>

namespace mcv
{

namespace
{
// A row-major sparse matrix from rows of (column, value) entries, entries[start[i] ..
// start[i + 1]) for row i: each row sorted by column, zero values dropped, a repeated column
// summed. Written straight into the compressed arrays (a triplet list would sort every
// entry globally: ~1 ms per matrix at n = 5000); the rows are compacted in place, then
// copied, both split over the threads.
LLESparseRows sparseFromRows(Eigen::Index rows, Eigen::Index cols, const std::vector<std::size_t>& start,
  std::vector<std::pair<int, double>>& entries)
{
  std::vector<int> rowStart(static_cast<std::size_t>(rows) + 1, 0); // kept entries, then offsets
#pragma omp parallel for schedule(static)
  for (Eigen::Index i = 0; i < rows; ++i)
  {
    const auto first = entries.begin() + static_cast<std::ptrdiff_t>(start[static_cast<std::size_t>(i)]);
    const auto last = entries.begin() + static_cast<std::ptrdiff_t>(start[static_cast<std::size_t>(i) + 1]);
    std::sort(first, last);
    auto kept = first;
    for (auto e = first; e != last; ++e)
    {
      if (e->second == 0.0)
      {
        continue;
      }
      if (kept != first && (kept - 1)->first == e->first)
      {
        (kept - 1)->second += e->second;
        continue;
      }
      *kept++ = *e;
    }
    rowStart[static_cast<std::size_t>(i) + 1] = static_cast<int>(kept - first);
  }
  for (std::size_t i = 0; i < static_cast<std::size_t>(rows); ++i)
  {
    rowStart[i + 1] += rowStart[i];
  }
  LLESparseRows S(rows, cols);
  S.resizeNonZeros(rowStart.back());
  std::copy(rowStart.begin(), rowStart.end(), S.outerIndexPtr());
#pragma omp parallel for schedule(static)
  for (Eigen::Index i = 0; i < rows; ++i)
  {
    const std::pair<int, double>* row = entries.data() + start[static_cast<std::size_t>(i)];
    for (int e = rowStart[static_cast<std::size_t>(i)]; e < rowStart[static_cast<std::size_t>(i) + 1]; ++e, ++row)
    {
      S.innerIndexPtr()[e] = row->first;
      S.valuePtr()[e] = row->second;
    }
  }
  return S;
}

// Row i: the barycentric weights of point i from its k nearest landmarks. A landmark takes
// weight 1 on itself without a search (each landmark then reconstructs itself, as the
// pencil needs, and a quarter of the queries go at N = 2000, L = 500); so does a point
// with a landmark at distance 0.
LandmarkWeights landmarkWeights(const RowMatrixF& X, const std::vector<std::uint32_t>& landmarks, int k,
  double regularization)
{
  const Eigen::Index n = X.rows();
  const Eigen::Index D = X.cols();
  const Eigen::Index L = static_cast<Eigen::Index>(landmarks.size());
  RowMatrixF landmarkX(L, D);
  std::vector<int> landmarkOf(static_cast<std::size_t>(n), -1);
  for (Eigen::Index l = 0; l < L; ++l)
  {
    landmarkX.row(l) = X.row(landmarks[static_cast<std::size_t>(l)]);
    landmarkOf[landmarks[static_cast<std::size_t>(l)]] = static_cast<int>(l);
  }
  // Row i's entries at start[i] .. start[i + 1]: one for a landmark, k for any other point.
  std::vector<std::size_t> start(static_cast<std::size_t>(n) + 1, 0);
  std::vector<std::uint32_t> others; // the points that are not landmarks
  others.reserve(static_cast<std::size_t>(n - L));
  for (Eigen::Index i = 0; i < n; ++i)
  {
    const bool isLandmark = landmarkOf[static_cast<std::size_t>(i)] >= 0;
    start[static_cast<std::size_t>(i) + 1] = start[static_cast<std::size_t>(i)] + (isLandmark ? 1 : k);
    if (!isLandmark)
    {
      others.push_back(static_cast<std::uint32_t>(i));
    }
  }
  std::vector<std::pair<int, double>> entries(start.back());
  // ExactKnn: the tiled brute force in high dimension, where a kd-tree visits most leaves.
  const ExactKnn index(landmarkX.data(), static_cast<std::size_t>(L), static_cast<int>(D));
  const long long queries = static_cast<long long>(others.size());
  const long long block = static_cast<long long>(kKnnQueryBlock);
  const long long blocks = (queries + block - 1) / block;
#pragma omp parallel
  {
    RowMatrixF queryX(block, D);
    std::vector<std::uint32_t> nearest(kKnnQueryBlock * k);
    std::vector<double> d2(kKnnQueryBlock * k);
    Eigen::MatrixXd Zi(k, D), G;
    Eigen::VectorXd w;
#pragma omp for schedule(static)
    for (Eigen::Index i = 0; i < n; ++i)
    {
      if (landmarkOf[static_cast<std::size_t>(i)] >= 0)
      {
        entries[start[static_cast<std::size_t>(i)]] = { landmarkOf[static_cast<std::size_t>(i)], 1.0 };
      }
    }
#pragma omp for schedule(dynamic, 1)
    for (long long b = 0; b < blocks; ++b)
    {
      const long long first = b * block;
      const long long count = std::min(block, queries - first);
      for (long long r = 0; r < count; ++r)
      {
        queryX.row(r) = X.row(others[static_cast<std::size_t>(first + r)]);
      }
      index.query(queryX.data(), static_cast<std::size_t>(count), k, nearest.data(), d2.data());
      for (long long r = 0; r < count; ++r)
      {
        const std::uint32_t* nb = nearest.data() + r * k;
        std::pair<int, double>* row = entries.data() + start[others[static_cast<std::size_t>(first + r)]];
        if (d2[static_cast<std::size_t>(r * k)] == 0.0)
        {
          row[0] = { static_cast<int>(nb[0]), 1.0 };
          for (int j = 1; j < k; ++j)
          {
            row[j] = { static_cast<int>(nb[j]), 0.0 }; // dropped
          }
          continue;
        }
        for (int j = 0; j < k; ++j)
        {
          Zi.row(j) = (landmarkX.row(nb[j]) - queryX.row(r)).cast<double>();
        }
        barycentricWeights(Zi, regularization, G, w);
        for (int j = 0; j < k; ++j)
        {
          row[j] = { static_cast<int>(nb[j]), w[j] };
        }
      }
    }
  }
  return sparseFromRows(n, L, start, entries);
}
} // namespace

Embedding fitLLE(const RowMatrixF& X, const LLEOptions& options)
{
  Embedding e;
  const Eigen::Index n = X.rows();
  const Eigen::Index D = X.cols();
  const int d = options.outputDimension;
  const int K = options.numberOfNeighbors;
  auto report = [&](const char* stage, double f) { reportStage(options.progress, stage, f); };
  e.error = neighboursError("LLE", K, static_cast<std::size_t>(n));
  if (!e.error.empty())
  {
    return e;
  }
  if (n < d + 2)
  {
    e.error = "LLE: at least " + std::to_string(d + 2) + " distinct reference points are needed.";
    return e;
  }
  report("LLE: neighbours", 0.0);
  const KnnGraph knn = buildKnnGraph(X.data(), static_cast<std::size_t>(n), static_cast<int>(D), K);
  report("LLE: weights", 0.2);

  // A disconnected graph makes M's null space as large as the number of components
  // (any per-component constant): join them by their closest pairs, as Isomap does, each
  // pair's points becoming neighbours of each other.
  std::size_t components = 1;
  const std::vector<GraphEdge> joins = joinKnnComponents(X.data(), static_cast<std::size_t>(n), static_cast<int>(D), knn, &components);
  std::vector<std::vector<std::uint32_t>> extra(static_cast<std::size_t>(n));
  for (const GraphEdge& j : joins)
  {
    extra[j.a].push_back(j.b);
    extra[j.b].push_back(j.a);
  }
  if (components > 1)
  {
    e.warnings.push_back("LLE: the " + std::to_string(K) + "-neighbour graph has " + std::to_string(components) +
      " connected components; they were joined by their closest pairs of points (" + std::to_string(joins.size()) +
      " links). A larger NumberOfNeighbors avoids this.");
  }

  // A = I - W by rows: row i at entryStart[i] .. entryStart[i + 1] holds the diagonal 1, then
  // minus the local reconstruction weights of its K nearest and any join links (one small
  // K x K system per point).
  std::vector<std::size_t> entryStart(static_cast<std::size_t>(n) + 1, 0);
  for (Eigen::Index i = 0; i < n; ++i)
  {
    entryStart[i + 1] = entryStart[i] + 1 + K + extra[static_cast<std::size_t>(i)].size();
  }
  std::vector<std::pair<int, double>> entries(entryStart.back());
#pragma omp parallel
  {
    std::vector<std::uint32_t> nb;
    Eigen::MatrixXd Z, G;
    Eigen::VectorXd w;
#pragma omp for schedule(static)
    for (Eigen::Index i = 0; i < n; ++i)
    {
      nb.assign(knn.neighbors.begin() + i * K, knn.neighbors.begin() + (i + 1) * K);
      nb.insert(nb.end(), extra[static_cast<std::size_t>(i)].begin(), extra[static_cast<std::size_t>(i)].end());
      const int k = static_cast<int>(nb.size());
      Z.resize(k, D);
      for (int j = 0; j < k; ++j)
      {
        Z.row(j) = (X.row(nb[static_cast<std::size_t>(j)]) - X.row(i)).cast<double>();
      }
      barycentricWeights(Z, options.regularization, G, w);
      std::pair<int, double>* row = entries.data() + entryStart[i];
      row[0] = { static_cast<int>(i), 1.0 };
      for (int j = 0; j < k; ++j)
      {
        row[1 + j] = { static_cast<int>(nb[static_cast<std::size_t>(j)]), -w[j] };
      }
    }
  }
  const LLESparseRows A = sparseFromRows(n, n, entryStart, entries);

  // Landmarks: enough for the Lanczos step (2 nev + 1 vectors), fewer than the points.
  const int landmarks = std::max(options.numberOfLandmarks, 2 * (d + 4) + 1);
  if (options.numberOfLandmarks > 0 && landmarks != options.numberOfLandmarks)
  {
    // Said, as Isomap says its own minimum: otherwise 1, 2 or 15 landmarks look alike.
    e.warnings.push_back("LLE: " + std::to_string(options.numberOfLandmarks) + " landmarks asked for, " +
      (landmarks < n ? std::to_string(landmarks) + " used" : "exact LLE on the " + std::to_string(n) + " reference points") +
      " (at least 2(d+4)+1 = " + std::to_string(landmarks) + " for a " + std::to_string(d) + "D embedding).");
  }
  LLEBottomEigen bottom;
  if (options.numberOfLandmarks > 0 && landmarks < n)
  {
    report("LLE: landmark weights", 0.3);
    const LandmarkWeights Z = landmarkWeights(X, uniformLandmarks(static_cast<std::size_t>(n), landmarks, options.seed),
      std::min(options.landmarkNeighbors, landmarks), options.regularization);
    report("LLE: eigenvectors", 0.5);
    bottom = lleLandmarkEigenvectors(A, Z, d);
    if (!bottom.error.empty())
    {
      e.warnings.push_back("LLE: locally linear landmarks failed (" + bottom.error + "); exact LLE was used.");
    }
  }
  if (bottom.vectors.size() == 0)
  {
    report("LLE: eigenvectors", 0.5);
    bottom = lleBottomEigenvectors(LLESparse(A), d, options.solver);
  }
  if (!bottom.error.empty())
  {
    e.error = "LLE: the eigenvectors of (I-W)^T(I-W) could not be computed (" + bottom.error +
      "). Try more neighbours or a different reference sample.";
    return e;
  }
  // Unit mean square coordinates.
  Eigen::MatrixXd Y = bottom.vectors * std::sqrt(static_cast<double>(n));
  e.eigenvalues.assign(bottom.values.data(), bottom.values.data() + d);
  fixColumnSigns(Y);
  e.coordinates = Y.cast<float>();
  report("LLE: done", 1.0);
  return e;
}

} // namespace mcv
