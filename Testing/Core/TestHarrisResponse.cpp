// The fused, streaming CPU Harris response against a direct, unfused reference, against
// the float arithmetic of the CUDA kernel written out voxel by voxel (bit for bit), between
// its AVX2 and portable builds, and its top-N selected on the fly against the selection
// from the response volume.
#include "HarrisResponse.h"
#include "TopResponses.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <random>
#include <string>
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

// The CUDA kernel's float arithmetic (cuda/HarrisKernel.cu as nvcc 13 compiles it for
// sm_90), one voxel at a time without tiles: the gradient products, the x, y and z passes
// each a chain of fmas from 0 in tap order reading clamped positions, and the response
// with the kernel's fused product-differences.
std::vector<float> gpuArithmetic(const std::vector<float>& I, const mcv::ImageGrid& g, const mcv::HarrisParameters& p)
{
  const int nx = g.dims[0], ny = g.dims[1], nz = g.dims[2], W = p.kernelWidth, R = W / 2;
  const std::size_t n = I.size();
  float taps[31];
  mcv::gaussianTaps(p, taps);
  const float scale[3] = { static_cast<float>(0.5 / g.spacing[0]), static_cast<float>(0.5 / g.spacing[1]),
    static_cast<float>(0.5 / g.spacing[2]) };
  auto index = [&](int i, int j, int k) {
    return (static_cast<std::size_t>(clampi(k, nz)) * ny + clampi(j, ny)) * nx + clampi(i, nx);
  };
  std::vector<float> a(6 * n), b(6 * n);
  for (int k = 0; k < nz; ++k)
    for (int j = 0; j < ny; ++j)
      for (int i = 0; i < nx; ++i)
      {
        const float gx = (I[index(i + 1, j, k)] - I[index(i - 1, j, k)]) * scale[0];
        const float gy = (I[index(i, j + 1, k)] - I[index(i, j - 1, k)]) * scale[1];
        const float gz = (I[index(i, j, k + 1)] - I[index(i, j, k - 1)]) * scale[2];
        const float products[6] = { gx * gx, gx * gy, gx * gz, gy * gy, gy * gz, gz * gz };
        for (int c = 0; c < 6; ++c)
          a[c * n + index(i, j, k)] = products[c];
      }
  const std::array<int, 3> step[3] = { { 1, 0, 0 }, { 0, 1, 0 }, { 0, 0, 1 } };
  for (int axis = 0; axis < 3; ++axis)
  {
    for (int c = 0; c < 6; ++c)
      for (int k = 0; k < nz; ++k)
        for (int j = 0; j < ny; ++j)
          for (int i = 0; i < nx; ++i)
          {
            float sum = 0.f;
            for (int t = 0; t < W; ++t)
            {
              const int d = t - R;
              sum = std::fma(taps[t], a[c * n + index(i + d * step[axis][0], j + d * step[axis][1], k + d * step[axis][2])], sum);
            }
            b[c * n + index(i, j, k)] = sum;
          }
    std::swap(a, b);
  }
  const int plane = g.extendedAxes() == 2 ? (nx == 1 ? 0 : (ny == 1 ? 1 : 2)) : -1;
  const float kk = static_cast<float>(p.k);
  std::vector<float> R3(n);
  for (std::size_t v = 0; v < n; ++v)
  {
    const float xx = a[v], xy = a[n + v], xz = a[2 * n + v], yy = a[3 * n + v], yz = a[4 * n + v], zz = a[5 * n + v];
    if (plane < 0)
    {
      const float det = std::fma(xz, std::fma(xy, yz, -(yy * xz)),
        std::fma(xx, std::fma(yy, zz, -(yz * yz)), -(xy * std::fma(xy, zz, -(yz * xz)))));
      const float tr = (xx + yy) + zz;
      R3[v] = std::fma(-tr, tr * (tr * kk), det);
    }
    else
    {
      const float pa = plane == 0 ? yy : xx, pb = plane == 0 ? yz : (plane == 1 ? xz : xy),
                  pc = plane == 2 ? yy : zz;
      const float tr = pa + pc;
      R3[v] = std::fma(-tr, tr * kk, std::fma(pa, pc, -(pb * pb)));
    }
  }
  return R3;
}

std::vector<float> randomVolume(const mcv::ImageGrid& g, unsigned seed)
{
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> u(0.f, 1.f);
  std::vector<float> I(g.voxelCount());
  for (float& v : I)
  {
    v = u(rng);
  }
  return I;
}

std::size_t differingBits(const std::vector<float>& a, const std::vector<float>& b)
{
  std::size_t differ = 0;
  for (std::size_t v = 0; v < a.size(); ++v)
  {
    differ += std::memcmp(&a[v], &b[v], sizeof(float)) != 0;
  }
  return differ;
}

struct Shape
{
  std::array<int, 3> dims;
  std::array<double, 3> spacing;
  mcv::HarrisParameters params;
};

// Tiles split along x (nx > 384) and y, kernel widths of the unrolled kernels (3, 5, 7) and
// of the general one (1, 9), volumes smaller than the kernel, single slices (2D form).
const Shape kShapes[] = { { { 37, 53, 29 }, { 0.8, 1.3, 2.1 }, {} }, { { 400, 9, 12 }, { 1, 1, 1 }, {} },
  { { 41, 35, 27 }, { 1, 1.2, 0.9 }, { 1.0, 3, 0.04 } }, { { 41, 35, 27 }, { 1, 1.2, 0.9 }, { 2.0, 7, 0.004 } },
  { { 19, 13, 11 }, { 1, 1, 1 }, { 2.5, 9, 0.004 } }, { { 19, 13, 11 }, { 1, 1, 1 }, { 1.0, 1, 0.04 } },
  { { 5, 6, 3 }, { 1, 1, 1 }, {} }, { { 45, 38, 1 }, { 0.7, 1.1, 1.6 }, {} }, { { 1, 45, 38 }, { 0.7, 1.1, 1.6 }, {} },
  { { 45, 1, 38 }, { 0.7, 1.1, 1.6 }, {} } };

// check(grid, volume, params) on a random volume of each shape of kShapes, the volumes
// seeded seed + 1, seed + 2, ...
template <class Check>
void onEveryShape(unsigned seed, Check check)
{
  for (const Shape& shape : kShapes)
  {
    mcv::ImageGrid g;
    g.dims = shape.dims;
    g.spacing = shape.spacing;
    SCOPED_TRACE(std::to_string(g.dims[0]) + "x" + std::to_string(g.dims[1]) + "x" +
      std::to_string(g.dims[2]) + " width " + std::to_string(shape.params.kernelWidth));
    check(g, randomVolume(g, ++seed), shape.params);
  }
}

TEST(HarrisResponse, RoundsLikeTheGpuKernelBitForBit)
{
  onEveryShape(7, [](const mcv::ImageGrid& g, const std::vector<float>& I, const mcv::HarrisParameters& params) {
    std::vector<float> R(I.size());
    mcv::computeHarrisResponseCPU(I.data(), g, params, R.data());
    EXPECT_EQ(differingBits(R, gpuArithmetic(I, g, params)), 0u);
  });
}

TEST(HarrisResponse, PortableAndVectorisedPathsGiveTheSameBits)
{
  onEveryShape(70, [](const mcv::ImageGrid& g, const std::vector<float>& I, const mcv::HarrisParameters& params) {
    std::vector<float> wide(I.size()), portable(I.size());
    mcv::computeHarrisResponseCPU(I.data(), g, params, wide.data());
    mcv::computeHarrisResponseCPU(I.data(), g, params, portable.data(), mcv::HarrisCpuKernel::Portable);
    EXPECT_EQ(differingBits(wide, portable), 0u);
  });
}

// The top-N selected while the response is computed: the selection from the whole
// response volume, points and order; with a box, the selection among its voxels.
TEST(HarrisResponse, TopNWhileComputingEqualsSelectionFromTheVolume)
{
  mcv::ImageGrid g;
  g.dims = { 70, 41, 33 };
  g.spacing = { 1.0, 0.9, 1.4 };
  std::vector<float> I = randomVolume(g, 5);
  for (std::size_t v = 0; v < I.size(); v += 3)
  {
    I[v] = 0.5f; // plateaus: equal responses, ties broken by index
  }
  std::vector<float> R(I.size());
  mcv::computeHarrisResponseCPU(I.data(), g, {}, R.data());
  for (int N : { 1, 300, 2048, 1000000 })
  {
    const mcv::InterestPoints want = mcv::selectTopResponsesCPU(R.data(), R.size(), N);
    const mcv::InterestPoints got = mcv::computeHarrisTopNCPU(I.data(), g, {}, N);
    EXPECT_EQ(got.indices, want.indices) << "N = " << N;
    EXPECT_EQ(got.scores, want.scores) << "N = " << N;
  }
  mcv::VoxelBox box;
  box.lo = { 10, 3, 7 };
  box.hi = { 50, 40, 20 };
  std::vector<float> inside(R.size(), 0.f);
  for (int k = box.lo[2]; k <= box.hi[2]; ++k)
    for (int j = box.lo[1]; j <= box.hi[1]; ++j)
      for (int i = box.lo[0]; i <= box.hi[0]; ++i)
      {
        const std::size_t v = (static_cast<std::size_t>(k) * g.dims[1] + j) * g.dims[0] + i;
        inside[v] = R[v];
      }
  const mcv::InterestPoints want = mcv::selectTopResponsesCPU(inside.data(), inside.size(), 500);
  const mcv::InterestPoints got = mcv::computeHarrisTopNCPU(I.data(), g, {}, 500, &box);
  EXPECT_EQ(got.indices, want.indices);
  EXPECT_EQ(got.scores, want.scores);
  EXPECT_EQ(mcv::computeHarrisTopNCPU(I.data(), g, {}, 0).size(), 0u);
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
