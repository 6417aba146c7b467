#include "PCAEmbedding.h"

#include <Eigen/Eigenvalues>

#include <algorithm>
#include <numeric>

namespace mcv
{

void fixColumnSigns(Eigen::MatrixXd& columns)
{
  for (Eigen::Index c = 0; c < columns.cols(); ++c)
  {
    Eigen::Index at = 0;
    columns.col(c).cwiseAbs().maxCoeff(&at);
    if (columns(at, c) < 0)
    {
      columns.col(c) *= -1.0;
    }
  }
}

void toPrincipalAxes(Eigen::MatrixXd& Y)
{
  Y.rowwise() -= Y.colwise().mean();
  Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> axesEig(Y.transpose() * Y);
  const Eigen::MatrixXd axes = axesEig.eigenvectors().rowwise().reverse();
  Y = Y * axes;
  fixColumnSigns(Y); // each axis points to the embedding's own largest coordinate
}

Embedding fitPCA(const float* rows, std::size_t n, int dim, const std::vector<std::int64_t>& sampleIn,
  const std::vector<int>& columnsIn, int d, PCAModel* model)
{
  Embedding e;
  std::vector<int> columns = columnsIn;
  if (columns.empty())
  {
    columns.resize(static_cast<std::size_t>(dim));
    std::iota(columns.begin(), columns.end(), 0);
  }
  std::vector<std::int64_t> sample = sampleIn;
  if (sample.empty())
  {
    sample.resize(n);
    std::iota(sample.begin(), sample.end(), std::int64_t(0));
  }
  const Eigen::Index D = static_cast<Eigen::Index>(columns.size());
  const Eigen::Index m = static_cast<Eigen::Index>(sample.size());
  if (m < 2)
  {
    e.error = "PCA needs at least 2 points.";
    return e;
  }
  // Mean and covariance in double, accumulated in fixed blocks combined in order, so the
  // result does not depend on the number of threads.
  const Eigen::Index blockSize = 4096;
  const Eigen::Index blocks = (m + blockSize - 1) / blockSize;
  std::vector<Eigen::VectorXd> sums(static_cast<std::size_t>(blocks), Eigen::VectorXd::Zero(D));
  auto gather = [&](Eigen::Index r, Eigen::VectorXd& x) {
    const float* row = rows + static_cast<std::size_t>(sample[static_cast<std::size_t>(r)]) * static_cast<std::size_t>(dim);
    for (Eigen::Index k = 0; k < D; ++k)
    {
      x[k] = row[columns[static_cast<std::size_t>(k)]];
    }
  };
#pragma omp parallel for schedule(static)
  for (Eigen::Index b = 0; b < blocks; ++b)
  {
    Eigen::VectorXd x(D);
    for (Eigen::Index r = b * blockSize; r < std::min(m, (b + 1) * blockSize); ++r)
    {
      gather(r, x);
      sums[static_cast<std::size_t>(b)] += x;
    }
  }
  Eigen::VectorXd mean = Eigen::VectorXd::Zero(D);
  for (const auto& s : sums)
  {
    mean += s;
  }
  mean /= static_cast<double>(m);
  std::vector<Eigen::MatrixXd> covs(static_cast<std::size_t>(blocks), Eigen::MatrixXd::Zero(D, D));
#pragma omp parallel for schedule(static)
  for (Eigen::Index b = 0; b < blocks; ++b)
  {
    Eigen::VectorXd x(D);
    for (Eigen::Index r = b * blockSize; r < std::min(m, (b + 1) * blockSize); ++r)
    {
      gather(r, x);
      x -= mean;
      covs[static_cast<std::size_t>(b)].selfadjointView<Eigen::Lower>().rankUpdate(x);
    }
  }
  Eigen::MatrixXd cov = Eigen::MatrixXd::Zero(D, D);
  for (const auto& c : covs)
  {
    cov += c;
  }
  cov = cov.selfadjointView<Eigen::Lower>();
  cov /= static_cast<double>(m - 1);

  Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig(cov);
  if (eig.info() != Eigen::Success)
  {
    e.error = "PCA: the eigen-decomposition of the covariance failed.";
    return e;
  }
  // Eigen sorts ascending; we want descending.
  const Eigen::VectorXd values = eig.eigenvalues().reverse();
  Eigen::MatrixXd vectors = eig.eigenvectors().rowwise().reverse();
  fixColumnSigns(vectors);
  double positive = 0, top = 0;
  for (Eigen::Index k = 0; k < D; ++k)
  {
    e.eigenvalues.push_back(values[k]);
    if (values[k] > 0)
    {
      positive += values[k];
      if (k < d)
      {
        top += values[k];
      }
    }
  }
  e.varianceRetained = positive > 0 ? top / positive : 0.0;

  // With fewer features than output dimensions the extra axes are zero.
  PCAModel local;
  PCAModel& pm = model ? *model : local;
  pm.mean = mean;
  pm.axes = Eigen::MatrixXd::Zero(D, d);
  const Eigen::Index kept = std::min<Eigen::Index>(D, d);
  pm.axes.leftCols(kept) = vectors.leftCols(kept);
  if (D < d)
  {
    e.warnings.push_back("PCA: only " + std::to_string(D) + " features for " + std::to_string(d) +
      " output dimensions; the extra coordinates are 0.");
  }

  e.coordinates.resize(m, d);
  std::vector<float> tmp(static_cast<std::size_t>(m) * static_cast<std::size_t>(d));
  // Project the sample rows (gathered so projectPCA's row indexing applies).
  RowMatrixF sampleRows(m, D);
  for (Eigen::Index r = 0; r < m; ++r)
  {
    const float* row = rows + static_cast<std::size_t>(sample[static_cast<std::size_t>(r)]) * static_cast<std::size_t>(dim);
    for (Eigen::Index k = 0; k < D; ++k)
    {
      sampleRows(r, k) = row[columns[static_cast<std::size_t>(k)]];
    }
  }
  projectPCA(pm, sampleRows.data(), static_cast<std::size_t>(m), static_cast<int>(D), {}, e.coordinates.data());
  return e;
}

void projectPCA(const PCAModel& model, const float* rows, std::size_t n, int dim, const std::vector<int>& columnsIn,
  float* out)
{
  std::vector<int> columns = columnsIn;
  if (columns.empty())
  {
    columns.resize(static_cast<std::size_t>(dim));
    std::iota(columns.begin(), columns.end(), 0);
  }
  const Eigen::Index D = static_cast<Eigen::Index>(columns.size());
  const Eigen::Index d = model.axes.cols();
  // Centre first, then project (no cancellation of large means in float).
  const Eigen::MatrixXf A = model.axes.cast<float>();
  const Eigen::VectorXf mean = model.mean.cast<float>();
  const long long count = static_cast<long long>(n);
#pragma omp parallel
  {
    Eigen::RowVectorXf x(D);
#pragma omp for schedule(static)
    for (long long ii = 0; ii < count; ++ii)
    {
      const float* row = rows + static_cast<std::size_t>(ii) * static_cast<std::size_t>(dim);
      for (Eigen::Index k = 0; k < D; ++k)
      {
        x[k] = row[columns[static_cast<std::size_t>(k)]] - mean[k];
      }
      Eigen::Map<Eigen::RowVectorXf> y(out + static_cast<std::size_t>(ii) * static_cast<std::size_t>(d), d);
      y.noalias() = x * A;
    }
  }
}

} // namespace mcv
