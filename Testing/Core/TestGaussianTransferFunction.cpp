// Gaussian-widget transfer function (Filters/Core/transfer_function/GaussianTransferFunction.h), CPU path:
// hand-computed voxels for 1, 2 and 5 widgets in 2D and 3D, a double-precision reference
// of the header's formula written here independently, bytes = round(255 v), the bad
// inputs, non-finite coordinates, the opacity-only path and the exp kernel.
#include "GaussianTransferFunction.h"
#include "GaussianWidgetsReference.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <limits>
#include <random>
#include <vector>

namespace
{

using mcv::Device;
using mcv::GaussianWidget;

GaussianWidget widget(double cx, double cy, double cz, double sigma, double r, double g, double b, double opacity)
{
  GaussianWidget w;
  w.center[0] = cx;
  w.center[1] = cy;
  w.center[2] = cz;
  w.sigma = sigma;
  w.color[0] = r;
  w.color[1] = g;
  w.color[2] = b;
  w.opacity = opacity;
  return w;
}

// The header's formula, in double, one voxel at a time.
std::vector<double> reference(const std::vector<float>& coords, int components, const std::vector<GaussianWidget>& widgets)
{
  const std::size_t n = coords.size() / components;
  std::vector<double> rgba(4 * n, 0.0);
  for (std::size_t v = 0; v < n; ++v)
  {
    bool finite = true;
    for (int d = 0; d < components; ++d)
      finite = finite && std::isfinite(coords[v * components + d]);
    if (finite)
      mcv::testing::referenceRGBA(coords.data() + v * components, components, widgets, &rgba[4 * v]);
  }
  return rgba;
}

std::vector<float> shade(const std::vector<float>& coords, int components, const std::vector<GaussianWidget>& widgets,
  mcv::TransferFunctionRun* runOut = nullptr)
{
  std::vector<float> rgba(4 * (coords.size() / components), -1.f);
  const mcv::TransferFunctionRun run = mcv::applyGaussianWidgets(
    { coords.data(), coords.size() / components, components }, widgets, rgba.data(), Device::CPU);
  EXPECT_TRUE(run.ok()) << run.error;
  EXPECT_EQ(run.deviceUsed, Device::CPU);
  if (runOut)
    *runOut = run;
  return rgba;
}

void expectRGBA(const std::vector<float>& rgba, std::size_t voxel, double r, double g, double b, double a,
  double tol = 1e-6)
{
  EXPECT_NEAR(rgba[4 * voxel + 0], r, tol) << "voxel " << voxel << " red";
  EXPECT_NEAR(rgba[4 * voxel + 1], g, tol) << "voxel " << voxel << " green";
  EXPECT_NEAR(rgba[4 * voxel + 2], b, tol) << "voxel " << voxel << " blue";
  EXPECT_NEAR(rgba[4 * voxel + 3], a, tol) << "voxel " << voxel << " alpha";
}

// Random widgets in the unit box and coordinates around it (some far outside).
std::vector<GaussianWidget> randomWidgets(int count, std::mt19937& rng)
{
  std::uniform_real_distribution<double> unit(0, 1), sigma(0.05, 0.5);
  std::vector<GaussianWidget> w;
  for (int i = 0; i < count; ++i)
    w.push_back(widget(unit(rng), unit(rng), unit(rng), sigma(rng), unit(rng), unit(rng), unit(rng), unit(rng)));
  return w;
}

std::vector<float> randomCoords(std::size_t n, int components, std::mt19937& rng)
{
  std::uniform_real_distribution<float> box(-0.5f, 1.5f);
  std::vector<float> c(n * components);
  for (float& x : c)
    x = box(rng);
  return c;
}

// -------------------------------------------------------------------------------------
// Hand-computed voxels.

TEST(GaussianTF, OneWidget3D)
{
  const std::vector<GaussianWidget> w{ widget(1, 2, 3, 0.5, 0.2, 0.4, 0.6, 0.8) };
  // centre; |d| = sigma along x; |d| = sigma off-axis (0.3, 0.4); |d| = 2 sigma along z
  const std::vector<float> c{ 1, 2, 3, 1.5f, 2, 3, 1.3f, 2.4f, 3, 1, 2, 4 };
  const std::vector<float> rgba = shade(c, 3, w);
  expectRGBA(rgba, 0, 0.2, 0.4, 0.6, 0.8);
  expectRGBA(rgba, 1, 0.2, 0.4, 0.6, 0.4852245277701068); // 0.8 exp(-1/2)
  expectRGBA(rgba, 2, 0.2, 0.4, 0.6, 0.4852245277701068);
  expectRGBA(rgba, 3, 0.2, 0.4, 0.6, 0.8 * std::exp(-2.0));
}

TEST(GaussianTF, OneWidget2DIgnoresThirdCentreCoordinate)
{
  const std::vector<GaussianWidget> w{ widget(1, 2, 100, 0.5, 0.2, 0.4, 0.6, 0.8) };
  const std::vector<float> c{ 1, 2, 1.5f, 2, 1.3f, 2.4f };
  const std::vector<float> rgba = shade(c, 2, w);
  expectRGBA(rgba, 0, 0.2, 0.4, 0.6, 0.8);
  expectRGBA(rgba, 1, 0.2, 0.4, 0.6, 0.4852245277701068);
  expectRGBA(rgba, 2, 0.2, 0.4, 0.6, 0.4852245277701068);
}

TEST(GaussianTF, TwoWidgets)
{
  // Red at x = 0, blue at x = 2, sigma 1, opacity 0.5 each.
  const std::vector<GaussianWidget> w{ widget(0, 0, 0, 1, 1, 0, 0, 0.5), widget(2, 0, 0, 1, 0, 0, 1, 0.5) };
  // Midpoint: alpha = 0.5 exp(-1/2) = 0.30326533 from each: purple, 1 - (1 - alpha)^2.
  // On the red centre: alphas 0.5 and 0.5 exp(-2): red 1/(1 + exp(-2)) = 0.88079708.
  for (int components : { 2, 3 })
  {
    std::vector<float> c = components == 3 ? std::vector<float>{ 1, 0, 0, 0, 0, 0 } : std::vector<float>{ 1, 0, 0, 0 };
    const std::vector<float> rgba = shade(c, components, w);
    expectRGBA(rgba, 0, 0.5, 0, 0.5, 0.5145607994197728);
    expectRGBA(rgba, 1, 0.8807970779778823, 0, 0.11920292202211755, 0.5338338208091532);
  }
}

TEST(GaussianTF, FiveWidgets)
{
  const std::vector<GaussianWidget> w{ widget(0, 0, 0, 0.1, 1, 0, 0, 0.9), widget(10, 0, 0, 0.1, 0, 1, 0, 0.7),
    widget(0, 10, 0, 0.1, 0, 0, 1, 0.5), widget(0, 0, 10, 0.1, 1, 1, 0, 0.3), widget(5, 5, 5, 0.1, 0, 1, 1, 1.0) };
  // On a centre the others are >= 7 apart, sigma 0.1 (weights <= exp(-2450)): that widget alone.
  const std::vector<float> c3{ 0, 0, 0, 10, 0, 0, 0, 10, 0, 0, 0, 10, 5, 5, 5 };
  const std::vector<float> rgba3 = shade(c3, 3, w);
  expectRGBA(rgba3, 0, 1, 0, 0, 0.9);
  expectRGBA(rgba3, 1, 0, 1, 0, 0.7);
  expectRGBA(rgba3, 2, 0, 0, 1, 0.5);
  expectRGBA(rgba3, 3, 1, 1, 0, 0.3);
  expectRGBA(rgba3, 4, 0, 1, 1, 1.0);
  // In 2D widget 3 sits on widget 0 (same x, y): on (0, 0) they mix 0.9 : 0.3 in colour,
  // opacity 1 - 0.1 * 0.7 = 0.93.
  const std::vector<float> c2{ 0, 0, 5, 5 };
  const std::vector<float> rgba2 = shade(c2, 2, w);
  expectRGBA(rgba2, 0, 1, 0.3 / 1.2, 0, 0.93);
  expectRGBA(rgba2, 1, 0, 1, 1, 1.0);
}

// -------------------------------------------------------------------------------------
// Against the double reference on random voxels.

TEST(GaussianTF, MatchesDoubleReference)
{
  std::mt19937 rng(42);
  for (int components : { 2, 3 })
  {
    for (int count : { 1, 2, 5, 8, 16 })
    {
      const std::vector<GaussianWidget> w = randomWidgets(count, rng);
      const std::vector<float> c = randomCoords(3001, components, rng); // 46 blocks + a partial one
      const std::vector<float> rgba = shade(c, components, w);
      const std::vector<double> ref = reference(c, components, w);
      double worstAlpha = 0, worstPremultiplied = 0, worstVisibleColour = 0;
      for (std::size_t v = 0; v < c.size() / components; ++v)
      {
        const double a = ref[4 * v + 3];
        worstAlpha = std::max(worstAlpha, std::abs(rgba[4 * v + 3] - a));
        for (int k = 0; k < 3; ++k)
        {
          const double diff = std::abs(rgba[4 * v + k] - ref[4 * v + k]);
          worstPremultiplied = std::max(worstPremultiplied, diff * a);
          if (a > 1e-3)
            worstVisibleColour = std::max(worstVisibleColour, diff);
        }
      }
      // Float32 arithmetic: alpha and colour x alpha (what the renderer composites) to 1e-6;
      // the colour of a visible voxel too. Far from every widget (alpha ~ 0) the colour is a
      // ratio of weights exp(e_i - m) whose float exponents e_i carry |e_i| x 1e-7 error.
      EXPECT_LT(worstAlpha, 1e-6) << components << "D, " << count << " widgets";
      EXPECT_LT(worstPremultiplied, 1e-6) << components << "D, " << count << " widgets";
      EXPECT_LT(worstVisibleColour, 1e-6) << components << "D, " << count << " widgets";
    }
  }
}

TEST(GaussianTF, ColourFarFromEveryWidgetIsTheWeightedMean)
{
  // 40 sigma from both widgets: alphas ~ exp(-800) underflow, yet the formula's colour is the
  // weighted mean; here the weights differ by exp(-2) (distances 40 and sqrt(1604)).
  const std::vector<GaussianWidget> w{ widget(0, 0, 0, 1, 1, 0, 0, 1), widget(0, 2, 0, 1, 0, 0, 1, 1) };
  const std::vector<float> c{ 40, 0, 0 };
  const std::vector<float> rgba = shade(c, 3, w);
  const double wb = std::exp(-(1604.0 - 1600.0) / 2);
  expectRGBA(rgba, 0, 1 / (1 + wb), 0, wb / (1 + wb), 0, 1e-5);
}

// -------------------------------------------------------------------------------------
// Outputs.

TEST(GaussianTF, BytesAreRoundedFloats)
{
  std::mt19937 rng(7);
  for (int components : { 2, 3 })
  {
    const std::vector<GaussianWidget> w = randomWidgets(5, rng);
    const std::vector<float> c = randomCoords(5000, components, rng);
    const mcv::CoordinateView view{ c.data(), c.size() / components, components };
    std::vector<float> f(4 * view.count);
    std::vector<unsigned char> b(4 * view.count);
    ASSERT_TRUE(mcv::applyGaussianWidgets(view, w, f.data(), Device::CPU).ok());
    ASSERT_TRUE(mcv::applyGaussianWidgets(view, w, b.data(), Device::CPU).ok());
    for (std::size_t i = 0; i < f.size(); ++i)
      ASSERT_EQ(int(b[i]), int(std::lround(255.0 * double(f[i])))) << i << " value " << f[i];
  }
  // Exact values: 0, 1 and 0.5 (127.5 rounds up to 128).
  const std::vector<GaussianWidget> half{ widget(0, 0, 0, 1, 0.5, 1, 0, 0.5) };
  const std::vector<float> c{ 0, 0 };
  unsigned char b[4];
  ASSERT_TRUE(mcv::applyGaussianWidgets({ c.data(), 1, 2 }, half, b, Device::CPU).ok());
  EXPECT_EQ(b[0], 128);
  EXPECT_EQ(b[1], 255);
  EXPECT_EQ(b[2], 0);
  EXPECT_EQ(b[3], 128);
}

TEST(GaussianTF, OpacityOnlyEqualsAlphaOfRGBA)
{
  std::mt19937 rng(3);
  for (int components : { 2, 3 })
  {
    const std::vector<GaussianWidget> w = randomWidgets(6, rng);
    std::vector<float> c = randomCoords(777, components, rng);
    c[5] = std::numeric_limits<float>::quiet_NaN();
    const mcv::CoordinateView view{ c.data(), c.size() / components, components };
    std::vector<float> rgba(4 * view.count), opacity(view.count);
    ASSERT_TRUE(mcv::applyGaussianWidgets(view, w, rgba.data(), Device::CPU).ok());
    ASSERT_TRUE(mcv::gaussianWidgetOpacity(view, w, opacity.data(), Device::CPU).ok());
    for (std::size_t v = 0; v < view.count; ++v)
      ASSERT_EQ(opacity[v], rgba[4 * v + 3]) << v; // the same operations: the same bits
  }
}

TEST(GaussianTF, NonFiniteOrOverflowingCoordinatesAreTransparentBlack)
{
  const float nan = std::numeric_limits<float>::quiet_NaN(), inf = std::numeric_limits<float>::infinity();
  const std::vector<GaussianWidget> w{ widget(0, 0, 0, 1, 1, 1, 1, 1) };
  const std::vector<float> c3{ nan, 0, 0, 0, inf, 0, 0, 0, -inf, 1e30f, 0, 0, 0, 0, 0 };
  const std::vector<float> rgba3 = shade(c3, 3, w);
  for (std::size_t v = 0; v < 4; ++v)
    expectRGBA(rgba3, v, 0, 0, 0, 0, 0);
  expectRGBA(rgba3, 4, 1, 1, 1, 1); // a finite neighbour is untouched
  const std::vector<float> c2{ 0, nan, inf, 0, 0, 0 };
  const std::vector<float> rgba2 = shade(c2, 2, w);
  expectRGBA(rgba2, 0, 0, 0, 0, 0, 0);
  expectRGBA(rgba2, 1, 0, 0, 0, 0, 0);
  expectRGBA(rgba2, 2, 1, 1, 1, 1);
}

// -------------------------------------------------------------------------------------
// Bad input: each a clear error or a warning.

TEST(GaussianTF, ParseErrors)
{
  const std::vector<double> seven{ 0, 0, 0, 1, 1, 1, 1 };
  mcv::WidgetList list = mcv::parseGaussianWidgets(seven.data(), seven.size());
  EXPECT_FALSE(list.ok());
  EXPECT_NE(list.error.find("not a multiple of 8"), std::string::npos) << list.error;

  for (double sigma : { 0.0, -1.0 })
  {
    const std::vector<double> v{ 0, 0, 0, 1, 1, 1, 1, 1, 0, 0, 0, sigma, 1, 1, 1, 1 };
    list = mcv::parseGaussianWidgets(v.data(), v.size());
    EXPECT_FALSE(list.ok());
    EXPECT_NE(list.error.find("widget 1: sigma"), std::string::npos) << list.error;
  }
  const std::vector<double> nan{ 0, std::nan(""), 0, 1, 1, 1, 1, 1 };
  list = mcv::parseGaussianWidgets(nan.data(), nan.size());
  EXPECT_FALSE(list.ok());
  EXPECT_NE(list.error.find("not finite"), std::string::npos) << list.error;
  // The message names the field (cy, the 2nd number), not an index that reads as a value.
  EXPECT_NE(list.error.find("cy (number 2 of its 8"), std::string::npos) << list.error;
}

TEST(GaussianTF, ClampsWithWarnings)
{
  const std::vector<double> v{ 0, 0, 0, 1, 1.5, -0.25, 0.5, 2, 0, 0, 0, 1, 0.1, 0.2, 0.3, 0.4 };
  const mcv::WidgetList list = mcv::parseGaussianWidgets(v.data(), v.size());
  ASSERT_TRUE(list.ok()) << list.error;
  ASSERT_EQ(list.widgets.size(), 2u);
  ASSERT_EQ(list.warnings.size(), 1u);
  EXPECT_NE(list.warnings[0].find("widget 0"), std::string::npos) << list.warnings[0];
  EXPECT_NE(list.warnings[0].find("clamped"), std::string::npos) << list.warnings[0];
  EXPECT_EQ(list.widgets[0].color[0], 1.0);
  EXPECT_EQ(list.widgets[0].color[1], 0.0);
  EXPECT_EQ(list.widgets[0].color[2], 0.5);
  EXPECT_EQ(list.widgets[0].opacity, 1.0);
  EXPECT_EQ(list.widgets[1].opacity, 0.4);

  // The same widgets given straight to apply: clamped with the same warning.
  std::vector<GaussianWidget> raw{ widget(0, 0, 0, 1, 1.5, -0.25, 0.5, 2) };
  const std::vector<float> c{ 0, 0, 0 };
  mcv::TransferFunctionRun run;
  const std::vector<float> rgba = shade(c, 3, raw, &run);
  ASSERT_EQ(run.warnings.size(), 1u);
  EXPECT_NE(run.warnings[0].find("clamped"), std::string::npos);
  expectRGBA(rgba, 0, 1, 0, 0.5, 1);
}

TEST(GaussianTF, NoWidgetsIsTransparentWithAWarning)
{
  const mcv::WidgetList list = mcv::parseGaussianWidgets(nullptr, 0);
  ASSERT_TRUE(list.ok());
  EXPECT_TRUE(list.widgets.empty());
  ASSERT_EQ(list.warnings.size(), 1u);
  EXPECT_NE(list.warnings[0].find("transparent"), std::string::npos);

  const std::vector<float> c{ 0, 0, 0, 1, 1, 1 };
  const std::vector<float> rgba = shade(c, 3, {});
  for (float x : rgba)
    EXPECT_EQ(x, 0.f);
  // Widgets of opacity 0 add nothing either.
  const std::vector<float> zero = shade(c, 3, { widget(0, 0, 0, 1, 1, 1, 1, 0) });
  for (float x : zero)
    EXPECT_EQ(x, 0.f);
}

TEST(GaussianTF, ApplyRejectsBadInput)
{
  const std::vector<float> c(12, 0.f);
  std::vector<float> out(16);
  const std::vector<GaussianWidget> ok{ widget(0, 0, 0, 1, 1, 1, 1, 1) };
  for (int components : { 1, 4 })
  {
    const mcv::TransferFunctionRun run =
      mcv::applyGaussianWidgets({ c.data(), 3, components }, ok, out.data(), Device::CPU);
    EXPECT_FALSE(run.ok());
    EXPECT_NE(run.error.find("2 or 3 components"), std::string::npos) << run.error;
  }
  EXPECT_FALSE(mcv::applyGaussianWidgets({ nullptr, 3, 3 }, ok, out.data(), Device::CPU).ok());
  EXPECT_FALSE(mcv::applyGaussianWidgets({ c.data(), 3, 3 }, ok, static_cast<float*>(nullptr), Device::CPU).ok());
  mcv::TransferFunctionRun run = mcv::applyGaussianWidgets(
    { c.data(), 3, 3 }, { widget(0, 0, 0, 0, 1, 1, 1, 1) }, out.data(), Device::CPU);
  EXPECT_FALSE(run.ok());
  EXPECT_NE(run.error.find("sigma"), std::string::npos) << run.error;
  // No voxels: nothing to do, no error.
  EXPECT_TRUE(mcv::applyGaussianWidgets({ nullptr, 0, 3 }, ok, out.data(), Device::CPU).ok());
}

// GPU asked: the CPU with a warning; Auto: the CPU without one (the expected case).
TEST(GaussianTF, DeviceWithoutGpuFallsBackWithAWarning)
{
  std::string why;
  if (mcv::gpuUsable(&why))
  {
    GTEST_SKIP() << "a GPU is usable here: Testing/gpu covers the GPU path";
  }
  const std::vector<float> c{ 0, 0, 0 };
  float rgba[4];
  for (Device d : { Device::Auto, Device::GPU })
  {
    const mcv::TransferFunctionRun run =
      mcv::applyGaussianWidgets({ c.data(), 1, 3 }, { widget(0, 0, 0, 1, 1, 1, 1, 1) }, rgba, d);
    ASSERT_TRUE(run.ok());
    EXPECT_EQ(run.deviceUsed, Device::CPU);
    EXPECT_EQ(run.warnings.size(), d == Device::GPU ? 1u : 0u);
    EXPECT_FLOAT_EQ(rgba[3], 1.f);
  }
}

// -------------------------------------------------------------------------------------
// The vectorised exp.

TEST(GaussianTF, ExpKernelRelativeError)
{
  double worst = 0;
  for (int i = 0; i <= 2000000; ++i)
  {
    const float x = static_cast<float>(-87.3 * i / 2000000.0);
    const double exact = std::exp(double(x));
    worst = std::max(worst, std::abs(mcv::detail::expNonPositive(x) - exact) / exact);
  }
  EXPECT_LT(worst, 1.5e-7); // measured 8.1e-8
  EXPECT_EQ(mcv::detail::expNonPositive(0.f), 1.f);
  const float floor = mcv::detail::expNonPositive(-87.3f);
  EXPECT_EQ(mcv::detail::expNonPositive(-1000.f), floor);
  EXPECT_EQ(mcv::detail::expNonPositive(-std::numeric_limits<float>::infinity()), floor);
  EXPECT_EQ(mcv::detail::expNonPositive(std::numeric_limits<float>::quiet_NaN()), floor);
  EXPECT_LT(floor, 1.3e-38f);
}

} // namespace
