// The whole best-viewpoint pipeline (CPU) on synthetic volumes with known answers.
#include "BestViewpoint.h"
#include "TestVolumes.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <vector>

namespace
{

using mcv::Vec3;

Vec3 normalized(Vec3 v)
{
  const double n = std::sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
  return { v[0] / n, v[1] / n, v[2] / n };
}

// Opacity of isotropic Gaussian blobs (sigma in world units) at world positions.
std::vector<float> blobVolume(const mcv::ImageGrid& g, const std::vector<Vec3>& centres, double sigma)
{
  std::vector<mcv::testing::Blob> blobs;
  for (const Vec3& c : centres)
  {
    blobs.push_back({ c, sigma, 1.0 });
  }
  return mcv::testing::gaussianBlobs(g, blobs).values;
}

// Blob centres spread over the plane through `centre` with unit normal `n`.
std::vector<Vec3> centresOnPlane(const Vec3& centre, const Vec3& n, double radius, int count, unsigned seed)
{
  const Vec3 helper = std::abs(n[0]) < 0.9 ? Vec3{ 1, 0, 0 } : Vec3{ 0, 1, 0 };
  const Vec3 u = normalized({ n[1] * helper[2] - n[2] * helper[1], n[2] * helper[0] - n[0] * helper[2],
    n[0] * helper[1] - n[1] * helper[0] });
  const Vec3 w = { n[1] * u[2] - n[2] * u[1], n[2] * u[0] - n[0] * u[2], n[0] * u[1] - n[1] * u[0] };
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> c(-radius, radius);
  std::vector<Vec3> out;
  while (static_cast<int>(out.size()) < count)
  {
    const double a = c(rng), b = c(rng);
    if (a * a + b * b <= radius * radius)
    {
      out.push_back({ centre[0] + a * u[0] + b * w[0], centre[1] + a * u[1] + b * w[1],
        centre[2] + a * u[2] + b * w[2] });
    }
  }
  return out;
}

mcv::BestViewpointOptions cpuOptions()
{
  mcv::BestViewpointOptions o;
  o.device = mcv::Device::CPU;
  return o;
}

TEST(BestViewpoint, BlobsOnTiltedPlaneGiveThePlaneNormal)
{
  mcv::ImageGrid g;
  g.dims = { 64, 64, 64 };
  const Vec3 normal = normalized({ 1, 2, 3 });
  const std::vector<float> I = blobVolume(g, centresOnPlane({ 31.5, 31.5, 31.5 }, normal, 24, 40, 1), 1.5);
  const mcv::BestViewpointResult r = mcv::computeBestViewpoint(I.data(), g, cpuOptions());
  ASSERT_TRUE(r.ok()) << r.error;
  ASSERT_TRUE(r.view.valid) << r.view.message;
  EXPECT_EQ(r.points.size(), 2048u);
  EXPECT_LT(mcv::axisAngleDegrees(r.view.best, normal), 2.0);
  EXPECT_LT(r.view.eigenvalues[2], 0.05);
}

TEST(BestViewpoint, RodGivesWorstDirectionAlongTheRod)
{
  mcv::ImageGrid g;
  g.dims = { 48, 48, 48 };
  const Vec3 axis = normalized({ 1, 1, 0.5 });
  std::vector<Vec3> centres;
  for (double t = -18; t <= 18; t += 4)
  {
    centres.push_back({ 23.5 + t * axis[0], 23.5 + t * axis[1], 23.5 + t * axis[2] });
  }
  const std::vector<float> I = blobVolume(g, centres, 1.5);
  const mcv::BestViewpointResult r = mcv::computeBestViewpoint(I.data(), g, cpuOptions());
  ASSERT_TRUE(r.ok() && r.view.valid);
  EXPECT_LT(mcv::axisAngleDegrees(r.view.worst, axis), 2.0);
  EXPECT_GT(r.view.eigenvalues[0], 0.9);
}

TEST(BestViewpoint, SymmetricBoxGivesNearEqualEigenvalues)
{
  mcv::ImageGrid g;
  g.dims = { 40, 40, 40 };
  std::vector<Vec3> corners;
  for (int c = 0; c < 8; ++c)
  {
    corners.push_back({ c & 1 ? 29.5 : 9.5, c & 2 ? 29.5 : 9.5, c & 4 ? 29.5 : 9.5 });
  }
  // Eight identical blobs at the corners of a cube: every principal axis is equivalent.
  const std::vector<float> I = blobVolume(g, corners, 1.5);
  const mcv::BestViewpointResult r = mcv::computeBestViewpoint(I.data(), g, cpuOptions());
  ASSERT_TRUE(r.ok() && r.view.valid);
  for (int i = 0; i < 3; ++i)
  {
    EXPECT_NEAR(r.view.eigenvalues[i], 1.0 / 3.0, 0.02);
  }
}

TEST(BestViewpoint, AnisotropicSpacingIsRespected)
{
  // The plane x_world = z_world sampled with spacing (1, 1, 2): its normal is (1, 0, -1)/sqrt2
  // in world space but (2, 0, -1)/sqrt5 in index space.
  mcv::ImageGrid g;
  g.dims = { 64, 48, 32 };
  g.spacing = { 1.0, 1.0, 2.0 };
  g.origin = { -10.0, 5.0, 3.0 };
  const Vec3 normal = normalized({ 1, 0, -1 });
  const Vec3 centre = { -10 + 31.5, 5 + 23.5, 3 + 31.0 };
  const std::vector<float> I = blobVolume(g, centresOnPlane(centre, normal, 20, 30, 2), 2.0);
  const mcv::BestViewpointResult r = mcv::computeBestViewpoint(I.data(), g, cpuOptions());
  ASSERT_TRUE(r.ok() && r.view.valid);
  EXPECT_LT(mcv::axisAngleDegrees(r.view.best, normal), 2.0);
  EXPECT_GT(mcv::axisAngleDegrees(r.view.best, normalized({ 2, 0, -1 })), 10.0);
  EXPECT_NEAR(r.view.center[1], centre[1], 3.0);
}

TEST(BestViewpoint, TheUnitOfTheSpacingDoesNotMatter)
{
  // The same voxels (anisotropic 1 : 1 : 2 spacing) written in millimetres, metres, 10 nm
  // voxels in metres, picometres and 1e9: the same interest points and view direction.
  // Before the response was made unit-free, 1e-8 turned the view by 36-87 degrees and
  // 1e-12 / 1e9 found no interest points at all.
  mcv::ImageGrid reference;
  reference.dims = { 48, 40, 32 };
  reference.spacing = { 1.0, 1.0, 2.0 };
  const Vec3 normal = normalized({ 1, 2, -1 });
  const std::vector<float> I =
    blobVolume(reference, centresOnPlane({ 23.5, 19.5, 31.0 }, normal, 16, 30, 3), 2.0);
  const mcv::BestViewpointResult base = mcv::computeBestViewpoint(I.data(), reference, cpuOptions());
  ASSERT_TRUE(base.ok() && base.view.valid);
  for (double unit : { 1e-3, 1e-8, 1e-12, 1e9 })
  {
    mcv::ImageGrid g = reference;
    for (int a = 0; a < 3; ++a)
    {
      g.spacing[a] = reference.spacing[a] * unit;
    }
    const mcv::BestViewpointResult r = mcv::computeBestViewpoint(I.data(), g, cpuOptions());
    ASSERT_TRUE(r.ok() && r.view.valid) << "unit " << unit << ": " << r.view.message;
    EXPECT_EQ(r.points.indices, base.points.indices) << "unit " << unit;
    EXPECT_LT(mcv::axisAngleDegrees(r.view.best, base.view.best), 1e-3) << "unit " << unit;
    for (int i = 0; i < 3; ++i)
    {
      EXPECT_NEAR(r.view.eigenvalues[i], base.view.eigenvalues[i], 1e-6) << "unit " << unit;
    }
  }
}

TEST(BestViewpoint, ConstantVolumeWarnsAndGivesNoDirection)
{
  mcv::ImageGrid g;
  g.dims = { 20, 20, 20 };
  for (float value : { 0.f, 0.5f })
  {
    std::vector<float> I(g.voxelCount(), value);
    const mcv::BestViewpointResult r = mcv::computeBestViewpoint(I.data(), g, cpuOptions());
    ASSERT_TRUE(r.ok());
    EXPECT_FALSE(r.view.valid);
    ASSERT_FALSE(r.warnings.empty());
    EXPECT_NE(r.warnings.back().find("is constant"), std::string::npos) << r.warnings.back();
    EXPECT_EQ(r.points.size(), 0u);
    for (int a = 0; a < 3; ++a)
    {
      EXPECT_FALSE(std::isnan(r.view.best[a]));
      EXPECT_FALSE(std::isnan(r.view.eigenvalues[a]));
    }
  }
}

TEST(BestViewpoint, ParametersThatLeaveNoInterestPointAreNamed)
{
  // Blobs everywhere, but HarrisK 10 makes every response negative: the message must name
  // the parameters, not call the volume constant or flat.
  mcv::ImageGrid g;
  g.dims = { 32, 32, 32 };
  const std::vector<float> I = blobVolume(g, { { 10, 10, 10 }, { 20, 16, 12 }, { 14, 22, 20 } }, 1.5);
  mcv::BestViewpointOptions o = cpuOptions();
  o.harris.k = 10;
  const mcv::BestViewpointResult r = mcv::computeBestViewpoint(I.data(), g, o);
  ASSERT_TRUE(r.ok());
  EXPECT_FALSE(r.view.valid);
  ASSERT_FALSE(r.warnings.empty());
  const std::string& w = r.warnings.back();
  EXPECT_NE(w.find("HarrisK 10"), std::string::npos) << w;
  EXPECT_EQ(w.find("constant"), std::string::npos) << w;
}

TEST(BestViewpoint, SingleSliceGivesItsNormal)
{
  for (int axis = 0; axis < 3; ++axis)
  {
    mcv::ImageGrid g;
    g.dims = { 50, 50, 50 };
    g.dims[axis] = 1;
    std::vector<Vec3> centres;
    std::mt19937 rng(axis);
    std::uniform_real_distribution<double> c(8, 42);
    for (int b = 0; b < 12; ++b)
    {
      Vec3 p = { c(rng), c(rng), c(rng) };
      p[axis] = 0;
      centres.push_back(p);
    }
    const std::vector<float> I = blobVolume(g, centres, 1.5);
    const mcv::BestViewpointResult r = mcv::computeBestViewpoint(I.data(), g, cpuOptions());
    ASSERT_TRUE(r.ok()) << r.error;
    ASSERT_TRUE(r.view.valid) << r.view.message;
    Vec3 normal = { 0, 0, 0 };
    normal[axis] = 1;
    EXPECT_LT(mcv::axisAngleDegrees(r.view.best, normal), 1e-6);
    EXPECT_FALSE(r.warnings.empty()); // says it is a single slice
  }
}

TEST(BestViewpoint, BadInputGivesErrors)
{
  mcv::ImageGrid g;
  g.dims = { 10, 10, 10 };
  std::vector<float> I(g.voxelCount(), 0.f);
  mcv::BestViewpointOptions o = cpuOptions();
  o.numberOfInterestPoints = 0;
  EXPECT_FALSE(mcv::computeBestViewpoint(I.data(), g, o).ok());
  o.numberOfInterestPoints = -3;
  EXPECT_FALSE(mcv::computeBestViewpoint(I.data(), g, o).ok());
  o = cpuOptions();
  o.harris.kernelWidth = 4;
  EXPECT_FALSE(mcv::computeBestViewpoint(I.data(), g, o).ok());
  mcv::ImageGrid empty;
  EXPECT_FALSE(mcv::computeBestViewpoint(I.data(), empty, cpuOptions()).ok());
  mcv::ImageGrid line;
  line.dims = { 10, 1, 1 };
  EXPECT_FALSE(mcv::computeBestViewpoint(I.data(), line, cpuOptions()).ok());
  mcv::ImageGrid flat = g;
  flat.spacing[1] = 0.0;
  const mcv::BestViewpointResult noSpacing = mcv::computeBestViewpoint(I.data(), flat, cpuOptions());
  EXPECT_FALSE(noSpacing.ok());
  // Which axis, and where a user fixes it.
  EXPECT_NE(noSpacing.error.find("axis 1 (y)"), std::string::npos) << noSpacing.error;
  EXPECT_NE(noSpacing.error.find("DataSpacing"), std::string::npos) << noSpacing.error;
}

// The best view of three blobs in a 24^3 volume, asked of `device`.
mcv::BestViewpointResult threeBlobsOn(mcv::Device device)
{
  mcv::ImageGrid g;
  g.dims = { 24, 24, 24 };
  const std::vector<float> I = blobVolume(g, { { 8, 8, 8 }, { 16, 12, 10 }, { 10, 18, 16 } }, 1.5);
  mcv::BestViewpointOptions o;
  o.device = device;
  return mcv::computeBestViewpoint(I.data(), g, o);
}

// Without a usable GPU both GPU and Auto run on the CPU: asked for the GPU, a warning says
// why; Auto takes the CPU silently.
TEST(BestViewpoint, WithoutGpuGpuAndAutoRunOnTheCpu)
{
  if (mcv::gpuUsable())
  {
    GTEST_SKIP() << "a GPU is usable here; neither falls back";
  }
  for (mcv::Device device : { mcv::Device::GPU, mcv::Device::Auto })
  {
    SCOPED_TRACE(device == mcv::Device::GPU ? "GPU" : "Auto");
    const mcv::BestViewpointResult r = threeBlobsOn(device);
    ASSERT_TRUE(r.ok());
    EXPECT_EQ(r.deviceUsed, mcv::Device::CPU);
    EXPECT_TRUE(r.view.valid);
    if (device == mcv::Device::GPU)
    {
      ASSERT_FALSE(r.warnings.empty());
      EXPECT_NE(r.warnings.front().find("no usable GPU"), std::string::npos);
    }
    else
    {
      for (const std::string& w : r.warnings)
      {
        EXPECT_EQ(w.find("GPU"), std::string::npos) << w;
      }
    }
  }
}

} // namespace
