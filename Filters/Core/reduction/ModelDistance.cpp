#include "ModelDistance.h"

#include "ReductionModel.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace mcv
{

double referenceRadius(const RowMatrixF& refX)
{
  const std::size_t M = static_cast<std::size_t>(refX.rows());
  const int D = static_cast<int>(refX.cols());
  constexpr int k = 4; // the reference itself (distance 0: the rows are distinct) and 3 others
  if (M < static_cast<std::size_t>(k))
  {
    return 0.0;
  }
  const ExactKnn index(refX.data(), M, D);
  const long long blocks = static_cast<long long>((M + kKnnQueryBlock - 1) / kKnnQueryBlock);
  double largest = 0.0;
#pragma omp parallel
  {
    std::vector<std::uint32_t> idx(kKnnQueryBlock * k);
    std::vector<double> d2(kKnnQueryBlock * k);
    double mine = 0.0;
#pragma omp for schedule(dynamic)
    for (long long b = 0; b < blocks; ++b)
    {
      const std::size_t first = static_cast<std::size_t>(b) * kKnnQueryBlock;
      const std::size_t count = std::min(kKnnQueryBlock, M - first);
      index.query(refX.data() + first * static_cast<std::size_t>(D), count, k, idx.data(), d2.data());
      for (std::size_t r = 0; r < count; ++r)
      {
        mine = std::max(mine, d2[r * k + k - 1]);
      }
    }
#pragma omp critical(mcvReferenceRadius)
    largest = std::max(largest, mine);
  }
  return std::sqrt(largest);
}

std::size_t modelDistances(const RowMatrixF& refX, const ExactKnn* index, double radius, const float* rows,
  std::size_t n, int dim, const std::vector<int>& columns, const std::uint32_t* nearest, std::size_t nearestStride,
  float* out)
{
  const int D = static_cast<int>(refX.cols());
  const long long blocks = static_cast<long long>((n + kKnnQueryBlock - 1) / kKnnQueryBlock);
  std::size_t beyond = 0;
#pragma omp parallel reduction(+ : beyond)
  {
    std::vector<float> q(kKnnQueryBlock * static_cast<std::size_t>(D));
    std::vector<std::uint32_t> idx(kKnnQueryBlock);
    std::vector<double> d2(kKnnQueryBlock);
#pragma omp for schedule(dynamic)
    for (long long b = 0; b < blocks; ++b)
    {
      const std::size_t first = static_cast<std::size_t>(b) * kKnnQueryBlock;
      const std::size_t count = std::min(kKnnQueryBlock, n - first);
      for (std::size_t r = 0; r < count; ++r)
      {
        const float* row = rows + (first + r) * static_cast<std::size_t>(dim);
        for (int c = 0; c < D; ++c)
        {
          q[r * D + c] = row[columns.empty() ? c : columns[static_cast<std::size_t>(c)]];
        }
      }
      if (nearest)
      {
        for (std::size_t r = 0; r < count; ++r)
        {
          idx[r] = nearest[(first + r) * nearestStride];
          d2[r] = canonicalSquaredDistance(q.data() + r * D, refX.data() + static_cast<std::size_t>(idx[r]) * D, D);
        }
      }
      else
      {
        index->query(q.data(), count, 1, idx.data(), d2.data());
      }
      for (std::size_t r = 0; r < count; ++r)
      {
        const double distance = std::sqrt(d2[r]);
        const double ratio = radius > 0 ? distance / radius
                                        : (distance == 0 ? 0.0 : std::numeric_limits<double>::infinity());
        out[first + r] = static_cast<float>(ratio);
        beyond += ratio > kOutOfModelRatio ? 1 : 0;
      }
    }
  }
  return beyond;
}

} // namespace mcv
