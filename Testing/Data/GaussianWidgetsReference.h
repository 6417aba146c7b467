// The Gaussian widgets' colour and opacity at one point (GaussianTransferFunction.h's
// formula), written plainly in double: the reference the tests compare the CPU and GPU
// paths with, and the baseline the benchmark times them against.
#pragma once

#include "GaussianTransferFunction.h"

#include <cmath>
#include <vector>

namespace mcv
{
namespace testing
{

// rgba[0..2]: the widgets' colours weighted by their alphas a_i = opacity_i
// exp(-|x - centre_i|^2 / (2 sigma_i^2)) (0 where every a_i is 0); rgba[3]: 1 - prod (1 - a_i).
inline void referenceRGBA(const float* x, int components,
  const std::vector<mcv::GaussianWidget>& widgets, double rgba[4])
{
  double transmit = 1, sum = 0, rgb[3] = { 0, 0, 0 };
  for (const mcv::GaussianWidget& w : widgets)
  {
    double d2 = 0;
    for (int d = 0; d < components; ++d)
    {
      d2 += (x[d] - w.center[d]) * (x[d] - w.center[d]);
    }
    const double alpha = w.opacity * std::exp(-d2 / (2 * w.sigma * w.sigma));
    transmit *= 1 - alpha;
    sum += alpha;
    for (int k = 0; k < 3; ++k)
    {
      rgb[k] += alpha * w.color[k];
    }
  }
  for (int k = 0; k < 3; ++k)
  {
    rgba[k] = sum > 0 ? rgb[k] / sum : 0;
  }
  rgba[3] = 1 - transmit;
}

} // namespace testing
} // namespace mcv
