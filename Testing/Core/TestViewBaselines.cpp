// Known-answer tests of the baseline viewpoint methods (area maximising, viewpoint entropy)
// and of their opacity ray caster.
#include "ViewBaselines.h"

#include "BestViewpoint.h"
#include "TestVolumes.h"

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

namespace
{
using mcv::Vec3;
namespace mt = mcv::testing;

double dot(const Vec3& a, const Vec3& b)
{
  return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}
double norm(const Vec3& a)
{
  return std::sqrt(dot(a, a));
}
double angleDeg(const Vec3& a, const Vec3& b)
{
  const double c = dot(a, b) / (norm(a) * norm(b));
  return std::acos(std::max(-1.0, std::min(1.0, c))) * 180.0 / M_PI;
}
bool allFinite(const mcv::ViewDirections& v)
{
  for (int a = 0; a < 3; ++a)
    if (!std::isfinite(v.best[a]) || !std::isfinite(v.worst[a]) || !std::isfinite(v.viewUp[a]) ||
      !std::isfinite(v.center[a]) || !std::isfinite(v.eigenvalues[a]))
      return false;
  return true;
}
void expectFrame(const mcv::ViewDirections& v)
{
  EXPECT_NEAR(norm(v.best), 1.0, 1e-9);
  EXPECT_NEAR(norm(v.worst), 1.0, 1e-9);
  EXPECT_NEAR(norm(v.viewUp), 1.0, 1e-9);
  EXPECT_NEAR(dot(v.best, v.viewUp), 0.0, 1e-9);
  EXPECT_TRUE(allFinite(v));
}

// ------------------------------------------------------------------ area maximising

TEST(AreaMaximizing, KnownBoxGivesFaceAreasOverK)
{
  // Anisotropic spacing and a non-zero origin: the answer is in world units.
  const auto grid = mt::makeGrid(40, 30, 20, { 0.5, 1.0, 2.0 }, { -3, 7, 100 });
  // Voxels i 5..24 (20 voxels), j 3..12 (10), k 2..5 (4) -> w = 10, h = 10, d = 8.
  const auto vol = mt::boxVolumeIndex(grid, { 5, 3, 2 }, { 24, 12, 5 }, 0.7f);
  const auto v = mcv::areaMaximizingView(vol.values.data(), grid, 0.0f);
  ASSERT_TRUE(v.valid) << v.message;
  const double w = 10, h = 10, d = 8;
  const double K = std::sqrt(w * w * h * h + h * h * d * d + d * d * w * w);
  EXPECT_NEAR(v.best[0], h * d / K, 1e-12);
  EXPECT_NEAR(v.best[1], d * w / K, 1e-12);
  EXPECT_NEAR(v.best[2], w * h / K, 1e-12);
  // Smallest face: h*d = d*w = 80 < w*h = 100 -> ties go to the lowest axis, x.
  EXPECT_EQ(v.worst, (Vec3{ 1, 0, 0 }));
  expectFrame(v);
  const auto c = mt::gridCenter(grid);
  EXPECT_NEAR(v.center[0], c[0], 1e-12);
  EXPECT_NEAR(v.center[1], c[1], 1e-12);
  EXPECT_NEAR(v.center[2], c[2], 1e-12);
  EXPECT_EQ(v.eigenvalues, (Vec3{ 0, 0, 0 }));
}

TEST(AreaMaximizing, ThresholdSelectsTheTightBox)
{
  const auto grid = mt::makeGrid(32, 32, 32);
  auto vol = mt::boxVolumeIndex(grid, { 0, 0, 0 }, { 31, 31, 31 }, 0.05f); // faint haze
  for (int k = 10; k <= 13; ++k) // an opaque slab 32 x 32 x 4 inside
    for (int j = 0; j < 32; ++j)
      for (int i = 0; i < 32; ++i)
        vol.values[(k * 32 + j) * 32 + i] = 0.9f;
  const auto all = mcv::areaMaximizingView(vol.values.data(), grid, 0.0f);
  ASSERT_TRUE(all.valid);
  const double third = 1.0 / std::sqrt(3.0);
  EXPECT_NEAR(all.best[0], third, 1e-12);
  EXPECT_NEAR(all.best[2], third, 1e-12);
  const auto slab = mcv::areaMaximizingView(vol.values.data(), grid, 0.1f);
  ASSERT_TRUE(slab.valid);
  // w = h = 32, d = 4: u = (128, 128, 1024) / K, and the smallest face is x's.
  const double K = std::sqrt(128.0 * 128 * 2 + 1024.0 * 1024);
  EXPECT_NEAR(slab.best[0], 128 / K, 1e-12);
  EXPECT_NEAR(slab.best[2], 1024 / K, 1e-12);
  EXPECT_LT(angleDeg(slab.best, { 0, 0, 1 }), 15.0);
  EXPECT_EQ(slab.worst, (Vec3{ 1, 0, 0 }));
}

TEST(AreaMaximizing, SingleSliceLooksAlongItsNormal)
{
  const auto grid = mt::makeGrid(20, 30, 1);
  const auto vol = mt::constantVolume(grid, 0.5f);
  const auto v = mcv::areaMaximizingView(vol.values.data(), grid);
  ASSERT_TRUE(v.valid);
  // w = 20, h = 30, d = 1 (one voxel thick): mostly z.
  EXPECT_LT(angleDeg(v.best, { 0, 0, 1 }), 5.0);
  expectFrame(v);
}

TEST(AreaMaximizing, TransparentVolumeIsInvalidWithMessage)
{
  const auto grid = mt::makeGrid(8, 8, 8);
  auto vol = mt::constantVolume(grid, 0.0f);
  vol.values[5] = std::nanf("");
  const auto v = mcv::areaMaximizingView(vol.values.data(), grid);
  EXPECT_FALSE(v.valid);
  EXPECT_FALSE(v.message.empty());
  EXPECT_TRUE(allFinite(v));
}

TEST(AreaMaximizing, BadGridIsInvalidWithMessage)
{
  const auto empty = mt::makeGrid(0, 8, 8);
  const float one = 1.0f;
  auto v = mcv::areaMaximizingView(&one, empty);
  EXPECT_FALSE(v.valid);
  EXPECT_NE(v.message.find("empty"), std::string::npos) << v.message;
  EXPECT_TRUE(allFinite(v));
  v = mcv::areaMaximizingView(nullptr, mt::makeGrid(1, 1, 1));
  EXPECT_FALSE(v.valid);
  EXPECT_FALSE(v.message.empty());
  v = mcv::areaMaximizingView(&one, mt::makeGrid(1, 1, 1, { 1, 0, 1 }));
  EXPECT_FALSE(v.valid);
  EXPECT_NE(v.message.find("spacing"), std::string::npos) << v.message;
}

// ------------------------------------------------------------------ entropy of an image

TEST(ImageEntropy, AnalyticValues)
{
  std::vector<float> uniform(1024, 0.3f);
  EXPECT_NEAR(mcv::imageEntropy(uniform.data(), uniform.size()), 10.0, 1e-9); // log2(1024)
  std::vector<float> oneHot(1024, 0.0f);
  oneHot[17] = 0.8f;
  EXPECT_EQ(mcv::imageEntropy(oneHot.data(), oneHot.size()), 0.0);
  std::vector<float> blank(64, 0.0f);
  EXPECT_EQ(mcv::imageEntropy(blank.data(), blank.size()), 0.0);
  EXPECT_EQ(mcv::imageEntropy(nullptr, 0), 0.0);
  // Two pixels 1:3 -> H = -(1/4 log2 1/4 + 3/4 log2 3/4).
  const float two[2] = { 1.0f, 3.0f };
  EXPECT_NEAR(mcv::imageEntropy(two, 2), 0.8112781244591328, 1e-9);
  // Scale invariance (p_i = I_i / sum I), NaN pixels ignored.
  std::vector<float> a = { 0.1f, 0.2f, 0.3f, 0.4f }, b = { 1, 2, 3, 4 };
  EXPECT_NEAR(mcv::imageEntropy(a.data(), 4), mcv::imageEntropy(b.data(), 4), 1e-6);
  b.push_back(std::nanf(""));
  EXPECT_NEAR(mcv::imageEntropy(a.data(), 4), mcv::imageEntropy(b.data(), 5), 1e-6);
}

// ------------------------------------------------------------------ the ray caster

// Covered area (world units^2) of an image: pixels with accumulated opacity > 0.5.
double coveredArea(const std::vector<float>& image, const mcv::ImageGrid& grid, int size)
{
  double r2 = 0;
  for (int a = 0; a < 3; ++a)
    r2 += std::pow(0.5 * grid.dims[a] * grid.spacing[a], 2);
  const double pixel = 2.0 * std::sqrt(r2) / size;
  std::size_t covered = 0;
  for (float p : image)
    covered += p > 0.5f;
  return covered * pixel * pixel;
}

TEST(RenderOpacityImage, AxisAlignedBoxCoversItsFace)
{
  // Box of voxels 16..47 x 24..39 x 8..55 (footprint 32 x 16 x 48) in 64^3.
  const auto grid = mt::makeGrid(64, 64, 64);
  const auto vol = mt::boxVolumeIndex(grid, { 16, 24, 8 }, { 47, 39, 55 }, 1.0f);
  const int N = 128;
  struct Case
  {
    Vec3 dir;
    double area, perimeter;
  };
  const Case cases[] = { { { 1, 0, 0 }, 16.0 * 48, 2 * (16 + 48) },
    { { 0, -1, 0 }, 32.0 * 48, 2 * (32 + 48) }, { { 0, 0, 1 }, 32.0 * 16, 2 * (32 + 16) } };
  for (const Case& c : cases)
  {
    const auto image = mcv::renderOpacityImage(vol.values.data(), grid, c.dir, N);
    ASSERT_EQ(image.size(), static_cast<std::size_t>(N * N));
    const double area = coveredArea(image, grid, N);
    // Trilinear blur: the > 0.5 edge lies between the footprint and half a voxel beyond;
    // pixels (0.87 world units) quantise it by about one pixel along the perimeter.
    EXPECT_GT(area, c.area - 0.9 * c.perimeter) << c.dir[0] << c.dir[1] << c.dir[2];
    EXPECT_LT(area, c.area + 1.5 * c.perimeter) << c.dir[0] << c.dir[1] << c.dir[2];
    float mx = 0;
    for (float p : image)
    {
      ASSERT_TRUE(std::isfinite(p));
      ASSERT_GE(p, 0.0f);
      ASSERT_LE(p, 1.0f);
      mx = std::max(mx, p);
    }
    EXPECT_GE(mx, 0.99f); // opaque box: early termination at 0.99
  }
}

TEST(RenderOpacityImage, OpacityCorrectionMatchesSlabThickness)
{
  // A slab 8 voxels thick of per-voxel opacity a, seen along its normal: 1 - (1 - a)^8.
  const auto grid = mt::makeGrid(32, 32, 32);
  const float a = 0.1f;
  const auto vol = mt::boxVolumeIndex(grid, { 0, 0, 12 }, { 31, 31, 19 }, a);
  const int N = 64;
  const auto image = mcv::renderOpacityImage(vol.values.data(), grid, { 0, 0, 1 }, N);
  // Centre pixel: well inside the slab's face.
  const float centre = image[(N / 2) * N + N / 2];
  const double expected = 1.0 - std::pow(1.0 - a, 8.0);
  // The half-voxel trilinear ramps at the two faces add about one voxel's worth.
  EXPECT_NEAR(centre, expected, 0.06) << "expected about " << expected;
  // Oblique view through the same slab is more opaque (longer path).
  const auto oblique = mcv::renderOpacityImage(vol.values.data(), grid, { 0.6, 0, 0.8 }, N);
  EXPECT_GT(oblique[(N / 2) * N + N / 2], centre);
}

TEST(RenderOpacityImage, DegenerateInputsGiveBlankImages)
{
  const auto grid = mt::makeGrid(8, 8, 8);
  const auto vol = mt::constantVolume(grid, 0.5f);
  EXPECT_TRUE(mcv::renderOpacityImage(vol.values.data(), grid, { 1, 0, 0 }, 0).empty());
  for (float p : mcv::renderOpacityImage(vol.values.data(), grid, { 0, 0, 0 }, 8))
    EXPECT_EQ(p, 0.0f);
  for (float p : mcv::renderOpacityImage(nullptr, grid, { 0, 0, 1 }, 8))
    EXPECT_EQ(p, 0.0f);
  // NaN voxels count as transparent.
  auto nan = mt::constantVolume(grid, std::nanf(""));
  for (float p : mcv::renderOpacityImage(nan.values.data(), grid, { 0, 1, 0 }, 8))
    EXPECT_EQ(p, 0.0f);
}

TEST(RenderOpacityImage, SingleSliceIsVisibleAlongItsNormal)
{
  const auto grid = mt::makeGrid(16, 16, 1);
  const auto vol = mt::constantVolume(grid, 0.5f);
  const auto image = mcv::renderOpacityImage(vol.values.data(), grid, { 0, 0, -1 }, 32);
  const float centre = image[16 * 32 + 16];
  EXPECT_NEAR(centre, 0.5f, 1e-3); // one voxel of travel: the opacity itself
}

// ------------------------------------------------------------------ viewpoint entropy

TEST(ViewpointEntropy, FlatSlabIsSeenFaceOn)
{
  // A square slab 40 x 40 x 3 of moderate opacity tilted nowhere: face-on covers the most
  // pixels with near-equal opacity, edge-on the fewest.
  const auto grid = mt::makeGrid(48, 48, 48);
  const auto vol = mt::boxVolumeIndex(grid, { 4, 4, 22 }, { 43, 43, 24 }, 0.3f);
  mcv::EntropyOptions opt;
  opt.samples = 200;
  opt.imageSize = 48;
  std::vector<double> seen;
  const auto v = mcv::viewpointEntropyView(
    vol.values.data(), grid, opt, [&](double p) { seen.push_back(p); });
  ASSERT_TRUE(v.valid) << v.message;
  EXPECT_LT(mcv::axisAngleDegrees(v.best, { 0, 0, 1 }), 15.0);
  EXPECT_GT(mcv::axisAngleDegrees(v.worst, { 0, 0, 1 }), 70.0);
  expectFrame(v);
  EXPECT_EQ(v.eigenvalues, (Vec3{ 0, 0, 0 }));
  // Progress: one call per sample, increasing, ending at 1.
  ASSERT_EQ(seen.size(), 200u);
  for (std::size_t i = 1; i < seen.size(); ++i)
    EXPECT_GT(seen[i], seen[i - 1]);
  EXPECT_DOUBLE_EQ(seen.back(), 1.0);
}

TEST(ViewpointEntropy, AnisotropicSpacingIsRespected)
{
  // Isotropic in voxels, but z spacing 0.1: in world units a thin plate seen along z.
  const auto grid = mt::makeGrid(24, 24, 24, { 1, 1, 0.1 });
  const auto vol = mt::boxVolumeIndex(grid, { 2, 2, 2 }, { 21, 21, 21 }, 0.2f);
  mcv::EntropyOptions opt;
  opt.samples = 100;
  opt.imageSize = 32;
  const auto v = mcv::viewpointEntropyView(vol.values.data(), grid, opt);
  ASSERT_TRUE(v.valid) << v.message;
  EXPECT_LT(mcv::axisAngleDegrees(v.best, { 0, 0, 1 }), 20.0);
  const auto a = mcv::areaMaximizingView(vol.values.data(), grid);
  ASSERT_TRUE(a.valid);
  EXPECT_LT(angleDeg(a.best, { 0, 0, 1 }), 10.0);
}

TEST(ViewpointEntropy, EmptyVolumeIsInvalidWithMessageAndNoNaN)
{
  const auto grid = mt::makeGrid(16, 16, 16);
  const auto vol = mt::constantVolume(grid, 0.0f);
  bool finished = false;
  const auto v = mcv::viewpointEntropyView(
    vol.values.data(), grid, mcv::EntropyOptions{}, [&](double p) { finished = p == 1.0; });
  EXPECT_FALSE(v.valid);
  EXPECT_FALSE(v.message.empty());
  EXPECT_TRUE(allFinite(v));
  EXPECT_TRUE(finished);
}

TEST(ViewpointEntropy, BadOptionsAreInvalidWithMessage)
{
  const auto grid = mt::makeGrid(8, 8, 8);
  const auto vol = mt::constantVolume(grid, 0.5f);
  mcv::EntropyOptions opt;
  opt.samples = 0;
  auto v = mcv::viewpointEntropyView(vol.values.data(), grid, opt);
  EXPECT_FALSE(v.valid);
  EXPECT_NE(v.message.find("samples"), std::string::npos) << v.message;
  opt.samples = 10;
  opt.imageSize = -3;
  v = mcv::viewpointEntropyView(vol.values.data(), grid, opt);
  EXPECT_FALSE(v.valid);
  EXPECT_NE(v.message.find("image size"), std::string::npos) << v.message;
  v = mcv::viewpointEntropyView(vol.values.data(), mt::makeGrid(8, 0, 8), mcv::EntropyOptions{});
  EXPECT_FALSE(v.valid);
  EXPECT_TRUE(allFinite(v));
}

TEST(ViewpointEntropy, SingleSampleAndDeterminism)
{
  const auto grid = mt::makeGrid(20, 20, 20);
  const auto vol = mt::gaussianBlobs(grid, { { { 6, 6, 6 }, 2.0, 1.0 }, { { 13, 12, 9 }, 3.0, 0.8 } });
  mcv::EntropyOptions opt;
  opt.samples = 1;
  opt.imageSize = 16;
  const auto one = mcv::viewpointEntropyView(vol.values.data(), grid, opt);
  ASSERT_TRUE(one.valid);
  EXPECT_EQ(one.best, one.worst);
  EXPECT_NEAR(one.best[2], 1.0 - 1.0, 1e-12); // the only Fibonacci sample has z = 0
  opt.samples = 50;
  const auto a = mcv::viewpointEntropyView(vol.values.data(), grid, opt);
  const auto b = mcv::viewpointEntropyView(vol.values.data(), grid, opt);
  ASSERT_TRUE(a.valid);
  EXPECT_EQ(a.best, b.best);
  EXPECT_EQ(a.worst, b.worst);
  EXPECT_NE(a.best, a.worst);
}

// ------------------------------------------------------------------ through the entry point

// A thin tilted disc: every method should look (about) along its normal.
mt::Volume tiltedDisc(const Vec3& normal, float opacity)
{
  const auto grid = mt::makeGrid(48, 48, 48);
  mt::Volume v = mt::constantVolume(grid, 0.0f);
  const double n = norm(normal);
  const Vec3 u = { normal[0] / n, normal[1] / n, normal[2] / n };
  const auto c = mt::gridCenter(grid);
  mt::forEachVoxel(grid, [&](int, int, int, double x, double y, double z, std::size_t idx) {
    const Vec3 r = { x - c[0], y - c[1], z - c[2] };
    const double h = dot(r, u);
    const double radial2 = dot(r, r) - h * h;
    if (std::fabs(h) <= 1.5 && radial2 <= 18.0 * 18.0)
      v.values[idx] = opacity;
  });
  return v;
}

TEST(BaselinesThroughEntryPoint, TiltedDiscAllMethodsFindTheNormal)
{
  const Vec3 normal = { 1, 2, 3 };
  const auto disc = tiltedDisc(normal, 0.3f);
  mcv::BestViewpointOptions opt;
  opt.device = mcv::Device::CPU;
  opt.entropy.samples = 300;
  opt.entropy.imageSize = 48;
  double last = -1;
  opt.progress = [&](double p) {
    EXPECT_GE(p, last - 1e-12);
    last = p;
  };

  opt.method = mcv::ViewMethod::ViewpointEntropy;
  const auto entropy = mcv::computeBestViewpoint(disc.values.data(), disc.grid, opt);
  ASSERT_TRUE(entropy.ok()) << entropy.error;
  ASSERT_TRUE(entropy.view.valid) << entropy.view.message;
  EXPECT_LT(mcv::axisAngleDegrees(entropy.view.best, normal), 12.0);
  EXPECT_GT(mcv::axisAngleDegrees(entropy.view.worst, normal), 70.0);
  EXPECT_DOUBLE_EQ(last, 1.0);

  opt.method = mcv::ViewMethod::HarrisPCA;
  last = -1;
  const auto harris = mcv::computeBestViewpoint(disc.values.data(), disc.grid, opt);
  ASSERT_TRUE(harris.ok()) << harris.error;
  ASSERT_TRUE(harris.view.valid) << harris.view.message;
  EXPECT_LT(mcv::axisAngleDegrees(harris.view.best, normal), 5.0);
  EXPECT_LT(mcv::axisAngleDegrees(harris.view.best, entropy.view.best), 15.0);

  // Area maximising only sees the disc's axis-aligned bounding box: (hd, dw, wh)/K of it.
  opt.method = mcv::ViewMethod::AreaMaximizing;
  last = -1;
  const auto area = mcv::computeBestViewpoint(disc.values.data(), disc.grid, opt);
  ASSERT_TRUE(area.ok()) << area.error;
  ASSERT_TRUE(area.view.valid) << area.view.message;
  const auto direct = mcv::areaMaximizingView(disc.values.data(), disc.grid);
  EXPECT_EQ(area.view.best, direct.best);
  for (int a = 0; a < 3; ++a)
    EXPECT_GT(area.view.best[a], 0.0);
}

TEST(BaselinesThroughEntryPoint, TransparentVolumeWarnsWithoutNaN)
{
  const auto grid = mt::makeGrid(16, 16, 16);
  const auto vol = mt::constantVolume(grid, 0.0f);
  for (auto method : { mcv::ViewMethod::AreaMaximizing, mcv::ViewMethod::ViewpointEntropy })
  {
    mcv::BestViewpointOptions opt;
    opt.method = method;
    opt.device = mcv::Device::CPU;
    const auto r = mcv::computeBestViewpoint(vol.values.data(), grid, opt);
    ASSERT_TRUE(r.ok()) << r.error;
    EXPECT_FALSE(r.view.valid);
    EXPECT_FALSE(r.warnings.empty());
    EXPECT_TRUE(allFinite(r.view));
  }
}

} // namespace
