#include "OutOfSample.h"

#include <Eigen/Cholesky>

#include <algorithm>
#include <cmath>

namespace mcv
{

void placeOutOfSample(const RowMatrixF& refX, const RowMatrixF& refY, const float* rows, std::size_t n, int dim,
  const std::vector<int>& columns, float* out, const OutOfSampleOptions& options)
{
  const int D = static_cast<int>(refX.cols());
  const int d = static_cast<int>(refY.cols());
  const std::size_t M = static_cast<std::size_t>(refX.rows());
  const int k = static_cast<int>(std::min<std::size_t>(static_cast<std::size_t>(std::max(1, options.neighbors)), M));
  const KnnIndex index(refX.data(), M, D);
  const bool gather = !columns.empty();

  // Chunks so progress can be reported between them from the calling thread.
  const std::size_t chunk = std::max<std::size_t>(1 << 16, n / 50);
  for (std::size_t begin = 0; begin < n; begin += chunk)
  {
    const long long end = static_cast<long long>(std::min(n, begin + chunk));
#pragma omp parallel
    {
      std::vector<float> x(static_cast<std::size_t>(D));
      std::vector<std::uint32_t> idx(static_cast<std::size_t>(k));
      std::vector<float> d2(static_cast<std::size_t>(k));
      Eigen::MatrixXd Z(k, D);
      Eigen::MatrixXd G(k, k);
      Eigen::VectorXd w(k);
#pragma omp for schedule(dynamic, 1024)
      for (long long ii = static_cast<long long>(begin); ii < end; ++ii)
      {
        const float* row = rows + static_cast<std::size_t>(ii) * static_cast<std::size_t>(dim);
        const float* q = row;
        if (gather)
        {
          for (int c = 0; c < D; ++c)
          {
            x[static_cast<std::size_t>(c)] = row[columns[static_cast<std::size_t>(c)]];
          }
          q = x.data();
        }
        float* y = out + static_cast<std::size_t>(ii) * static_cast<std::size_t>(d);
        const int found = static_cast<int>(index.query(q, static_cast<std::size_t>(k), idx.data(), d2.data()));
        if (found == 1 || d2[0] == 0.f)
        {
          // An exact match (or a single reference point): its embedding, exactly.
          for (int c = 0; c < d; ++c)
          {
            y[c] = refY(idx[0], c);
          }
          continue;
        }
        for (int j = 0; j < found; ++j)
        {
          for (int c = 0; c < D; ++c)
          {
            Z(j, c) = static_cast<double>(refX(idx[static_cast<std::size_t>(j)], c)) - static_cast<double>(q[c]);
          }
        }
        const auto Zf = Z.topRows(found);
        G.topLeftCorner(found, found).noalias() = Zf * Zf.transpose();
        const double tr = G.topLeftCorner(found, found).trace();
        G.topLeftCorner(found, found).diagonal().array() += tr > 0 ? options.regularization * tr : options.regularization;
        w.head(found) = G.topLeftCorner(found, found).ldlt().solve(Eigen::VectorXd::Ones(found));
        double s = w.head(found).sum();
        if (!std::isfinite(s) || s == 0.0)
        {
          w.head(found).setConstant(1.0);
          s = found;
        }
        for (int c = 0; c < d; ++c)
        {
          double v = 0;
          for (int j = 0; j < found; ++j)
          {
            v += w[j] * static_cast<double>(refY(idx[static_cast<std::size_t>(j)], c));
          }
          y[c] = static_cast<float>(v / s);
        }
      }
    }
    if (options.progress)
    {
      options.progress("Out-of-sample placement", static_cast<double>(end) / static_cast<double>(n));
    }
  }
}

} // namespace mcv
