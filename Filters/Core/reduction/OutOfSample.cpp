#include "OutOfSample.h"

#ifdef MCV_HAS_CUDA
#include "cuda/OutOfSampleCuda.h"
#endif

#include "BarycentricWeights.h"

#include <Eigen/Cholesky>

#include <algorithm>
#include <cmath>

namespace mcv
{

namespace
{

// y = sum w_j Y_(j) with the barycentric weights of the k neighbours (see the header).
void placeRow(const RowMatrixF& refX, const RowMatrixF& refY, const float* q, const std::uint32_t* idx,
  const double* d2, int k, double regularization, Eigen::MatrixXd& Z, Eigen::MatrixXd& G, Eigen::VectorXd& w,
  float* y)
{
  const int D = static_cast<int>(refX.cols());
  const int d = static_cast<int>(refY.cols());
  if (k == 1 || d2[0] == 0.0)
  {
    // An exact match (or a single reference point): its embedding, exactly.
    for (int c = 0; c < d; ++c)
    {
      y[c] = refY(idx[0], c);
    }
    return;
  }
  for (int j = 0; j < k; ++j)
  {
    for (int c = 0; c < D; ++c)
    {
      Z(j, c) = static_cast<double>(refX(idx[j], c)) - static_cast<double>(q[c]);
    }
  }
  barycentricWeights(Z.topRows(k), regularization, G, w);
  for (int c = 0; c < d; ++c)
  {
    double v = 0;
    for (int j = 0; j < k; ++j)
    {
      v += w[j] * static_cast<double>(refY(idx[j], c));
    }
    y[c] = static_cast<float>(v);
  }
}

#ifdef MCV_HAS_CUDA
bool placeOnGpu(const RowMatrixF& refX, const RowMatrixF& refY, const float* rows, std::size_t n, int dim,
  const std::vector<int>& columns, float* out, const OutOfSampleOptions& options, std::uint32_t* neighbors,
  OutOfSampleReport& report, std::string* error)
{
  cuda::PlacementInput in;
  in.refX = refX.data();
  in.refY = refY.data();
  in.M = static_cast<std::size_t>(refX.rows());
  in.D = static_cast<int>(refX.cols());
  in.d = static_cast<int>(refY.cols());
  in.rows = rows;
  in.n = n;
  in.dim = dim;
  in.columns = columns.empty() ? nullptr : columns.data();
  in.neighbors = options.neighbors;
  in.regularization = options.regularization;
  in.distanceMargin = floatDistanceMargin(in.D);
  std::function<void(double)> progress;
  if (options.progress)
  {
    progress = [&](double f) { options.progress("Out-of-sample placement (GPU)", f); };
    progress(0.0); // the stage starts now, not when its first chunk is done
  }
  cuda::PlacementStats stats;
  if (!cuda::placeOutOfSample(in, out, neighbors, progress, &stats, error))
  {
    return false;
  }
  report.deviceUsed = Device::GPU;
  report.radiusScans = stats.radiusScans;
  report.uploadMs = stats.uploadMs;
  report.computeMs = stats.computeMs;
  report.downloadMs = stats.downloadMs;
  return true;
}
#endif
} // namespace

OutOfSampleReport placeOutOfSample(const RowMatrixF& refX, const RowMatrixF& refY, const float* rows, std::size_t n,
  int dim, const std::vector<int>& columns, float* out, const OutOfSampleOptions& options, std::uint32_t* neighbors)
{
  OutOfSampleReport report;
  const int D = static_cast<int>(refX.cols());
  const std::size_t M = static_cast<std::size_t>(refX.rows());
  const int k = static_cast<int>(std::min<std::size_t>(static_cast<std::size_t>(std::max(1, options.neighbors)), M));
  if (n == 0 || M == 0)
  {
    return report;
  }

  if (options.device == Device::GPU)
  {
#ifdef MCV_HAS_CUDA
    std::string error;
    if (placeOnGpu(refX, refY, rows, n, dim, columns, out, options, neighbors, report, &error))
    {
      return report;
    }
    report.warnings.push_back("The GPU out-of-sample placement failed (" + error + "); it ran on the CPU.");
#else
    report.warnings.push_back("This build has no CUDA: the out-of-sample placement ran on the CPU.");
#endif
  }

  const ExactKnn knn(refX.data(), M, D, options.knn);
  report.knnUsed = knn.method();
  const bool gather = !columns.empty();
  const int d = static_cast<int>(refY.cols());
  std::size_t scans = 0;

  // Chunks so progress can be reported between them from the calling thread: at least
  // every 2% of the rows (and at the start, so the stage is named while its first chunk runs).
  if (options.progress)
  {
    options.progress("Out-of-sample placement", 0.0);
  }
  const std::size_t chunk = std::max<std::size_t>(1 << 16, n / 50);
  for (std::size_t begin = 0; begin < n; begin += chunk)
  {
    const std::size_t end = std::min(n, begin + chunk);
    const long long blocks = static_cast<long long>((end - begin + kKnnQueryBlock - 1) / kKnnQueryBlock);
#pragma omp parallel reduction(+ : scans)
    {
      std::vector<float> x(kKnnQueryBlock * static_cast<std::size_t>(D));
      std::vector<std::size_t> same(kKnnQueryBlock);
      std::vector<std::uint32_t> idx(kKnnQueryBlock * static_cast<std::size_t>(k));
      std::vector<double> d2(kKnnQueryBlock * static_cast<std::size_t>(k));
      std::vector<float> y(kKnnQueryBlock * static_cast<std::size_t>(d));
      Eigen::MatrixXd Z(k, D);
      Eigen::MatrixXd G(k, k);
      Eigen::VectorXd w(k);
#pragma omp for schedule(dynamic, 1)
      for (long long b = 0; b < blocks; ++b)
      {
        const std::size_t first = begin + static_cast<std::size_t>(b) * kKnnQueryBlock;
        const std::size_t count = std::min(kKnnQueryBlock, end - first);
        // The used features of the block's rows, a run of equal rows kept once: voxels in a
        // row of the volume often share their features (the background around an object:
        // 40% of the brain's voxels), and equal rows have equal neighbours and coordinates.
        std::size_t distinct = 0;
        for (std::size_t r = 0; r < count; ++r)
        {
          const float* row = rows + (first + r) * static_cast<std::size_t>(dim);
          float* to = x.data() + distinct * D;
          for (int c = 0; c < D; ++c)
          {
            to[c] = row[gather ? columns[static_cast<std::size_t>(c)] : c];
          }
          if (options.mergeEqualRows && distinct > 0 && std::equal(to, to + D, to - D))
          {
            same[r] = distinct - 1;
            continue;
          }
          same[r] = distinct++;
        }
        scans += knn.query(x.data(), distinct, k, idx.data(), d2.data());
        for (std::size_t u = 0; u < distinct; ++u)
        {
          placeRow(refX, refY, x.data() + u * D, idx.data() + u * k, d2.data() + u * k, k, options.regularization, Z, G,
            w, y.data() + u * d);
        }
        for (std::size_t r = 0; r < count; ++r)
        {
          std::copy(y.data() + same[r] * d, y.data() + (same[r] + 1) * d, out + (first + r) * static_cast<std::size_t>(d));
          if (neighbors)
          {
            std::copy(idx.data() + same[r] * k, idx.data() + (same[r] + 1) * k, neighbors + (first + r) * k);
          }
        }
      }
    }
    if (options.progress)
    {
      options.progress("Out-of-sample placement", static_cast<double>(end) / static_cast<double>(n));
    }
  }
  report.radiusScans = scans;
  return report;
}

} // namespace mcv
