#include "LLEEmbedding.h"

#include "FeatureKnn.h"

#include <Eigen/Cholesky>

#include <algorithm>
#include <cmath>

namespace mcv
{

Embedding fitLLE(const RowMatrixF& X, const LLEOptions& options)
{
  Embedding e;
  const Eigen::Index n = X.rows();
  const Eigen::Index D = X.cols();
  const int d = options.outputDimension;
  const int K = options.numberOfNeighbors;
  auto report = [&](const char* stage, double f) {
    if (options.progress)
    {
      options.progress(stage, f);
    }
  };
  if (K < 1 || K >= n)
  {
    e.error = "LLE: the number of neighbours (" + std::to_string(K) +
      ") must be at least 1 and less than the number of reference points (" + std::to_string(n) + ").";
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

  // Local reconstruction weights, one small K x K system per point.
  std::vector<std::vector<std::pair<std::uint32_t, double>>> weights(static_cast<std::size_t>(n));
#pragma omp parallel
  {
    std::vector<std::uint32_t> nb;
    Eigen::MatrixXd Z, G;
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
      G.noalias() = Z * Z.transpose();
      const double tr = G.trace();
      const double R = tr > 0 ? options.regularization * tr : options.regularization;
      G.diagonal().array() += R;
      Eigen::VectorXd w = G.ldlt().solve(Eigen::VectorXd::Ones(k));
      const double s = w.sum();
      if (!(std::isfinite(s)) || s == 0.0)
      {
        w.setConstant(1.0 / k);
      }
      else
      {
        w /= s;
      }
      auto& out = weights[static_cast<std::size_t>(i)];
      for (int j = 0; j < k; ++j)
      {
        out.emplace_back(nb[static_cast<std::size_t>(j)], w[j]);
      }
    }
  }

  // A = I - W.
  std::vector<Eigen::Triplet<double, int>> trip;
  trip.reserve(static_cast<std::size_t>(n) * (K + 1) + 2 * joins.size());
  for (Eigen::Index i = 0; i < n; ++i)
  {
    trip.emplace_back(static_cast<int>(i), static_cast<int>(i), 1.0);
    for (const auto& [j, w] : weights[static_cast<std::size_t>(i)])
    {
      trip.emplace_back(static_cast<int>(i), static_cast<int>(j), -w);
    }
  }
  LLESparse A(n, n);
  A.setFromTriplets(trip.begin(), trip.end());
  report("LLE: eigenvectors", 0.3);

  const LLEBottomEigen bottom = lleBottomEigenvectors(A, d, options.solver);
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
