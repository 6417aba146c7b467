// The fused, streaming CPU Harris response against a direct, unfused reference.
#include "HarrisResponse.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <vector>

namespace
{

int clampi(int i, int n)
{
  return std::max(0, std::min(n - 1, i));
}

// Straight from the definition: gradient products at every voxel, then a full
// KernelWidth^3 weighted sum (not separable), then det - k tr^3. Double precision.
std::vector<double> referenceResponse(
  const std::vector<float>& I, const mcv::ImageGrid& g, const mcv::HarrisParameters& p)
{
  const int nx = g.dims[0], ny = g.dims[1], nz = g.dims[2];
  auto at = [&](int i, int j, int k) {
    return static_cast<double>(I[(static_cast<std::size_t>(clampi(k, nz)) * ny + clampi(j, ny)) * nx + clampi(i, nx)]);
  };
  std::vector<double> products(I.size() * 6);
  for (int k = 0; k < nz; ++k)
    for (int j = 0; j < ny; ++j)
      for (int i = 0; i < nx; ++i)
      {
        const double gx = (at(i + 1, j, k) - at(i - 1, j, k)) / (2 * g.spacing[0]);
        const double gy = (at(i, j + 1, k) - at(i, j - 1, k)) / (2 * g.spacing[1]);
        const double gz = (at(i, j, k + 1) - at(i, j, k - 1)) / (2 * g.spacing[2]);
        const double pr[6] = { gx * gx, gx * gy, gx * gz, gy * gy, gy * gz, gz * gz };
        std::copy(pr, pr + 6, &products[((static_cast<std::size_t>(k) * ny + j) * nx + i) * 6]);
      }
  const int r = p.kernelWidth / 2;
  std::vector<double> w(p.kernelWidth);
  double sum = 0;
  for (int t = 0; t < p.kernelWidth; ++t)
  {
    w[t] = std::exp(-(t - r) * (t - r) / (2 * p.sigma * p.sigma));
    sum += w[t];
  }
  for (double& x : w)
  {
    x /= sum;
  }
  std::vector<double> R(I.size());
  for (int k = 0; k < nz; ++k)
    for (int j = 0; j < ny; ++j)
      for (int i = 0; i < nx; ++i)
      {
        double m[6] = { 0, 0, 0, 0, 0, 0 };
        for (int c = -r; c <= r; ++c)
          for (int b = -r; b <= r; ++b)
            for (int a = -r; a <= r; ++a)
            {
              const double wt = w[a + r] * w[b + r] * w[c + r];
              const double* src = &products[((static_cast<std::size_t>(clampi(k + c, nz)) * ny +
                                                 clampi(j + b, ny)) * nx + clampi(i + a, nx)) * 6];
              for (int q = 0; q < 6; ++q)
              {
                m[q] += wt * src[q];
              }
            }
        const double det = m[0] * (m[3] * m[5] - m[4] * m[4]) - m[1] * (m[1] * m[5] - m[4] * m[2]) +
          m[2] * (m[1] * m[4] - m[3] * m[2]);
        const double tr = m[0] + m[3] + m[5];
        R[(static_cast<std::size_t>(k) * ny + j) * nx + i] = det - p.k * tr * tr * tr;
      }
  return R;
}

TEST(HarrisResponse, GaussianTapsAreNormalisedAndSymmetric)
{
  mcv::HarrisParameters p;
  float taps[5];
  mcv::gaussianTaps(p, taps);
  EXPECT_NEAR(taps[0] + taps[1] + taps[2] + taps[3] + taps[4], 1.0f, 1e-6f);
  EXPECT_FLOAT_EQ(taps[0], taps[4]);
  EXPECT_FLOAT_EQ(taps[1], taps[3]);
  EXPECT_GT(taps[2], taps[1]);
  EXPECT_NEAR(taps[1] / taps[2], std::exp(-1.0 / (2 * 1.5 * 1.5)), 1e-6);
}

TEST(HarrisResponse, MatchesUnfusedReferenceOnRandomAnisotropicVolume)
{
  mcv::ImageGrid g;
  g.dims = { 19, 13, 11 };
  g.spacing = { 0.8, 1.0, 2.5 };
  std::mt19937 rng(1);
  std::uniform_real_distribution<float> u(0.f, 1.f);
  std::vector<float> I(g.voxelCount());
  for (float& v : I)
  {
    v = u(rng);
  }
  for (const mcv::HarrisParameters& p :
    { mcv::HarrisParameters{}, mcv::HarrisParameters{ 1.0, 3, 0.01 }, mcv::HarrisParameters{ 2.0, 7, 0.004 } })
  {
    std::vector<float> R(g.voxelCount());
    mcv::computeHarrisResponseCPU(I.data(), g, p, R.data());
    const std::vector<double> want = referenceResponse(I, g, p);
    double scale = 0;
    for (double v : want)
    {
      scale = std::max(scale, std::abs(v));
    }
    for (std::size_t v = 0; v < R.size(); ++v)
    {
      ASSERT_NEAR(R[v], want[v], 1e-4 * scale) << "voxel " << v << " width " << p.kernelWidth;
    }
  }
}

TEST(HarrisResponse, ConstantVolumeGivesExactlyZero)
{
  mcv::ImageGrid g;
  g.dims = { 16, 16, 16 };
  std::vector<float> I(g.voxelCount(), 0.37f), R(g.voxelCount(), -1.f);
  mcv::computeHarrisResponseCPU(I.data(), g, {}, R.data());
  for (float v : R)
  {
    ASSERT_EQ(v, 0.f);
  }
}

TEST(HarrisResponse, IsotropicBlobPeaksAtItsCentre)
{
  mcv::ImageGrid g;
  g.dims = { 21, 21, 21 };
  std::vector<float> I(g.voxelCount());
  for (int k = 0; k < 21; ++k)
    for (int j = 0; j < 21; ++j)
      for (int i = 0; i < 21; ++i)
      {
        const double d2 = (i - 10) * (i - 10) + (j - 9) * (j - 9) + (k - 11) * (k - 11);
        I[(k * 21 + j) * 21 + i] = static_cast<float>(std::exp(-d2 / (2 * 1.5 * 1.5)));
      }
  std::vector<float> R(g.voxelCount());
  mcv::computeHarrisResponseCPU(I.data(), g, {}, R.data());
  const auto peak = std::max_element(R.begin(), R.end()) - R.begin();
  EXPECT_EQ(peak, (11 * 21 + 9) * 21 + 10);
  EXPECT_GT(R[peak], 0.f);
}

TEST(HarrisResponse, ParametersAreChecked)
{
  EXPECT_STREQ(mcv::checkHarrisParameters({}), "");
  EXPECT_STRNE(mcv::checkHarrisParameters({ 0.0, 5, 0.004 }), "");
  EXPECT_STRNE(mcv::checkHarrisParameters({ 1.5, 4, 0.004 }), "");
  EXPECT_STRNE(mcv::checkHarrisParameters({ 1.5, 5, -1.0 }), "");
}

} // namespace
