#include "Trustworthiness.h"

#include <algorithm>
#include <cstdint>
#include <cmath>
#include <limits>
#include <numeric>
#include <vector>

namespace mcv
{

double trustworthiness(const float* X, int D, const float* Y, int d, std::size_t n, int k)
{
  if (k < 1 || 2 * static_cast<std::size_t>(k) >= n)
  {
    return std::numeric_limits<double>::quiet_NaN();
  }
  const long long count = static_cast<long long>(n);
  double penalty = 0;
#pragma omp parallel reduction(+ : penalty)
  {
    std::vector<double> dx(n), dy(n);
    std::vector<std::uint32_t> order(n), rank(n);
#pragma omp for schedule(dynamic, 16)
    for (long long ii = 0; ii < count; ++ii)
    {
      const std::size_t i = static_cast<std::size_t>(ii);
      for (std::size_t j = 0; j < n; ++j)
      {
        double sx = 0, sy = 0;
        for (int c = 0; c < D; ++c)
        {
          const double t = static_cast<double>(X[i * D + c]) - X[j * D + c];
          sx += t * t;
        }
        for (int c = 0; c < d; ++c)
        {
          const double t = static_cast<double>(Y[i * d + c]) - Y[j * d + c];
          sy += t * t;
        }
        dx[j] = sx;
        dy[j] = sy;
      }
      dx[i] = dy[i] = std::numeric_limits<double>::infinity(); // self last, as scikit-learn
      // Ranks in the original space (1 = nearest); ties by index (a stable order).
      std::iota(order.begin(), order.end(), 0u);
      std::stable_sort(order.begin(), order.end(), [&](std::uint32_t a, std::uint32_t b) { return dx[a] < dx[b]; });
      for (std::size_t r = 0; r < n; ++r)
      {
        rank[order[r]] = static_cast<std::uint32_t>(r + 1);
      }
      // The k nearest in the embedding.
      std::iota(order.begin(), order.end(), 0u);
      std::partial_sort(order.begin(), order.begin() + k, order.end(), [&](std::uint32_t a, std::uint32_t b) {
        return dy[a] < dy[b] || (dy[a] == dy[b] && a < b);
      });
      for (int j = 0; j < k; ++j)
      {
        const double r = rank[order[static_cast<std::size_t>(j)]];
        if (r > k)
        {
          penalty += r - k;
        }
      }
    }
  }
  const double nn = static_cast<double>(n);
  return 1.0 - penalty * (2.0 / (nn * k * (2.0 * nn - 3.0 * k - 1.0)));
}

} // namespace mcv
