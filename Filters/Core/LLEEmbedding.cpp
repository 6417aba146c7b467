#include "LLEEmbedding.h"

#include "FeatureKnn.h"

#include <Eigen/Cholesky>
#include <Eigen/SparseCholesky>
#include <Eigen/SparseCore>
#include <Spectra/SymEigsShiftSolver.h>
#include <Spectra/SymEigsSolver.h>

#include <algorithm>
#include <cmath>

namespace mcv
{

namespace
{
using SparseD = Eigen::SparseMatrix<double, Eigen::ColMajor, std::int64_t>;

// (M - sigma I)^{-1} x through a sparse LDLT (Spectra's own SparseSymShiftSolve uses a
// sparse LU, twice the work for a symmetric matrix).
class LDLTShiftInvert
{
public:
  using Scalar = double;
  explicit LDLTShiftInvert(const SparseD& M)
    : M_(M)
  {
  }
  Eigen::Index rows() const { return M_.rows(); }
  Eigen::Index cols() const { return M_.cols(); }
  void set_shift(double sigma)
  {
    SparseD A = M_;
    for (Eigen::Index i = 0; i < A.rows(); ++i)
    {
      A.coeffRef(i, i) -= sigma;
    }
    ldlt_.compute(A);
    ok_ = ldlt_.info() == Eigen::Success;
  }
  bool ok() const { return ok_; }
  void perform_op(const double* x, double* y) const
  {
    Eigen::Map<const Eigen::VectorXd> in(x, M_.rows());
    Eigen::Map<Eigen::VectorXd> out(y, M_.rows());
    out = ldlt_.solve(in);
  }

private:
  const SparseD& M_;
  Eigen::SimplicialLDLT<SparseD, Eigen::Lower, Eigen::AMDOrdering<std::int64_t>> ldlt_;
  bool ok_ = false;
};

// (c I - M) x with M = A^T A, A = I - W applied as two sparse products (never formed).
class ShiftedProduct
{
public:
  using Scalar = double;
  ShiftedProduct(const SparseD& A, double c)
    : A_(A)
    , c_(c)
  {
  }
  Eigen::Index rows() const { return A_.cols(); }
  Eigen::Index cols() const { return A_.cols(); }
  void perform_op(const double* x, double* y) const
  {
    Eigen::Map<const Eigen::VectorXd> in(x, A_.cols());
    Eigen::Map<Eigen::VectorXd> out(y, A_.cols());
    const Eigen::VectorXd t = A_ * in;
    out = c_ * in - A_.transpose() * t;
  }

private:
  const SparseD& A_;
  double c_;
};
} // namespace

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
  std::vector<Eigen::Triplet<double, std::int64_t>> trip;
  trip.reserve(static_cast<std::size_t>(n) * (K + 1) + 2 * joins.size());
  for (Eigen::Index i = 0; i < n; ++i)
  {
    trip.emplace_back(i, i, 1.0);
    for (const auto& [j, w] : weights[static_cast<std::size_t>(i)])
    {
      trip.emplace_back(i, j, -w);
    }
  }
  SparseD A(n, n);
  A.setFromTriplets(trip.begin(), trip.end());
  report("LLE: eigenvectors", 0.3);

  const int nev = d + 1;
  const int ncv = std::min<int>(static_cast<int>(n), std::max(2 * nev + 1, 20));
  Eigen::VectorXd values;
  Eigen::MatrixXd vectors;
  bool solved = false;
  std::string why;
  LLESolver solver = options.solver;
  SparseD M;
  if (solver != LLESolver::Lanczos)
  {
    M = SparseD(A.transpose()) * A;
    // Auto: the LDLT factor of M (a 2-hop neighbourhood pattern) fills in; past a few
    // hundred non-zeros per row the Lanczos iteration is cheaper.
    if (solver == LLESolver::Auto && M.nonZeros() > 400 * n)
    {
      solver = LLESolver::Lanczos;
    }
  }
  if (solver != LLESolver::Lanczos)
  {
    // sigma slightly below 0 keeps M - sigma I positive definite (M is PSD and singular).
    const double sigma = -1e-9 * std::max(1e-300, M.diagonal().maxCoeff());
    LDLTShiftInvert op(M);
    Spectra::SymEigsShiftSolver<LDLTShiftInvert> eigs(op, nev, ncv, sigma);
    if (op.ok())
    {
      eigs.init();
      eigs.compute(Spectra::SortRule::LargestMagn, 300, 1e-8);
      if (eigs.info() == Spectra::CompInfo::Successful)
      {
        values = eigs.eigenvalues();
        vectors = eigs.eigenvectors();
        solved = true;
      }
      else
      {
        why = "shift-invert did not converge";
      }
    }
    else
    {
      why = "the sparse factorisation failed";
    }
  }
  if (!solved)
  {
    // c >= lambda_max(M) = ||A||_2^2 <= ||A||_1 ||A||_inf.
    const double norm1 = Eigen::RowVectorXd(Eigen::RowVectorXd::Ones(n) * A.cwiseAbs()).maxCoeff();
    const double normInf = Eigen::VectorXd(A.cwiseAbs() * Eigen::VectorXd::Ones(n)).maxCoeff();
    const double c = norm1 * normInf;
    ShiftedProduct op(A, c);
    const int ncvL = std::min<int>(static_cast<int>(n), std::max(4 * nev, 40));
    Spectra::SymEigsSolver<ShiftedProduct> eigs(op, nev, ncvL);
    eigs.init();
    eigs.compute(Spectra::SortRule::LargestAlge, 3000, 1e-8);
    if (eigs.info() == Spectra::CompInfo::Successful)
    {
      values = (c - eigs.eigenvalues().array()).matrix();
      vectors = eigs.eigenvectors();
      solved = true;
    }
    else
    {
      why += std::string(why.empty() ? "" : "; ") + "Lanczos did not converge";
    }
  }
  if (!solved)
  {
    e.error = "LLE: the eigenvectors of (I-W)^T(I-W) could not be computed (" + why +
      "). Try more neighbours or a different reference sample.";
    return e;
  }
  // Ascending by eigenvalue; the first is the constant vector.
  std::vector<int> order(static_cast<std::size_t>(values.size()));
  for (int k = 0; k < static_cast<int>(order.size()); ++k)
  {
    order[static_cast<std::size_t>(k)] = k;
  }
  std::sort(order.begin(), order.end(), [&](int a, int b) { return values[a] < values[b]; });
  Eigen::MatrixXd Y(n, d);
  for (int k = 0; k < d; ++k)
  {
    const int c = order[static_cast<std::size_t>(k) + 1];
    Y.col(k) = vectors.col(c) * std::sqrt(static_cast<double>(n));
    e.eigenvalues.push_back(values[c]);
  }
  fixColumnSigns(Y);
  e.coordinates = Y.cast<float>();
  report("LLE: done", 1.0);
  return e;
}

} // namespace mcv
