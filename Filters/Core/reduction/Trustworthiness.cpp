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
    std::vector<std::uint32_t> order(n);
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
      // The k nearest in the embedding.
      std::iota(order.begin(), order.end(), 0u);
      std::partial_sort(order.begin(), order.begin() + k, order.end(), [&](std::uint32_t a, std::uint32_t b) {
        return dy[a] < dy[b] || (dy[a] == dy[b] && a < b);
      });
      // Their ranks in the original space (1 = nearest; ties by index, as a stable sort
      // orders them): 1 + the points before. k counting passes instead of sorting all n.
      for (int j = 0; j < k; ++j)
      {
        const std::uint32_t m = order[static_cast<std::size_t>(j)];
        const double v = dx[m];
        std::size_t before = 0;
        for (std::size_t l = 0; l < n; ++l)
        {
          before += dx[l] < v || (dx[l] == v && l < m);
        }
        const double r = static_cast<double>(before + 1);
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
