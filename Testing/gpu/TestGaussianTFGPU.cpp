// The CUDA path of the Gaussian-widget transfer function (transfer_function/cuda/GaussianTFCuda.h through
// mcv::applyGaussianWidgets) against the CPU path: RGBA within 1e-5 (same float log-weights,
// different exp: a few ulp), bytes within 1, opacity-only within 1e-5, on random
// coordinates and widgets (2D, 3D, 1..16 widgets, NaN/Inf coordinates, voxels far from
// every widget) and on PCA coordinates of the real Colin27 brain's features. Also: the
// device-resident coordinates are reused only while data/version stay the same, and a
// widget list too long for constant memory falls back to the CPU with a warning.
#include "cuda/GaussianTFCuda.h"

#include "DimensionReduction.h"
#include "FeatureVectors.h"
#include "GaussianTransferFunction.h"
#include "HalfCoordinates.h"

#include "RequireGpu.h"
#include "TestVolumes.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <random>
#include <string>
#include <vector>

namespace
{

namespace mt = mcv::testing;
using mcv::Device;
using mcv::GaussianWidget;

std::vector<GaussianWidget> randomWidgets(int count, std::mt19937& rng, double lo = 0, double hi = 1)
{
  std::uniform_real_distribution<double> pos(lo, hi), unit(0, 1), sigma(0.03 * (hi - lo), 0.5 * (hi - lo));
  std::vector<GaussianWidget> widgets(count);
  for (GaussianWidget& w : widgets)
  {
    for (int d = 0; d < 3; ++d)
    {
      w.center[d] = pos(rng);
      w.color[d] = unit(rng);
    }
    w.sigma = sigma(rng);
    w.opacity = unit(rng);
  }
  return widgets;
}

// Uniform in [-1, 2]^components (partly far outside the widgets' unit box), 1 % NaN/Inf.
std::vector<float> randomCoords(std::size_t n, int components, std::mt19937& rng)
{
  std::uniform_real_distribution<float> box(-1.f, 2.f), unit(0.f, 1.f);
  std::vector<float> c(n * components);
  for (float& x : c)
  {
    const float u = unit(rng);
    x = u < 0.005f ? std::numeric_limits<float>::quiet_NaN()
                   : (u < 0.01f ? std::numeric_limits<float>::infinity() : box(rng));
  }
  return c;
}

struct Both
{
  std::vector<float> cpu, gpu;
};

Both rgbaBoth(const mcv::CoordinateView& view, const std::vector<GaussianWidget>& widgets)
{
  Both out{ std::vector<float>(4 * view.count, -1.f), std::vector<float>(4 * view.count, -2.f) };
  const mcv::TransferFunctionRun cpu = mcv::applyGaussianWidgets(view, widgets, out.cpu.data(), Device::CPU);
  const mcv::TransferFunctionRun gpu = mcv::applyGaussianWidgets(view, widgets, out.gpu.data(), Device::GPU);
  EXPECT_TRUE(cpu.ok()) << cpu.error;
  EXPECT_TRUE(gpu.ok()) << gpu.error;
  EXPECT_EQ(cpu.deviceUsed, Device::CPU);
  EXPECT_EQ(gpu.deviceUsed, Device::GPU) << (gpu.warnings.empty() ? "" : gpu.warnings.back());
  return out;
}

double maxDiff(const std::vector<float>& a, const std::vector<float>& b)
{
  double worst = 0;
  for (std::size_t i = 0; i < a.size(); ++i)
  {
    if (std::isnan(a[i]) || std::isnan(b[i]))
      return std::numeric_limits<double>::infinity();
    worst = std::max(worst, double(std::fabs(a[i] - b[i])));
  }
  return worst;
}

TEST(GaussianTFGPU, AgreesWithCPUOnRandomInput)
{
  MCV_REQUIRE_GPU();
  std::mt19937 rng(2024);
  double worstAll = 0;
  for (int components : { 2, 3 })
  {
    const std::vector<float> coords = randomCoords(200003, components, rng);
    const mcv::CoordinateView view{ coords.data(), coords.size() / components, components };
    for (int count = 1; count <= 16; ++count)
    {
      const std::vector<GaussianWidget> widgets = randomWidgets(count, rng);
      const Both rgba = rgbaBoth(view, widgets);
      const double worst = maxDiff(rgba.cpu, rgba.gpu);
      worstAll = std::max(worstAll, worst);
      EXPECT_LE(worst, 1e-5) << components << "D, " << count << " widgets";

      std::vector<float> opCpu(view.count), opGpu(view.count);
      ASSERT_TRUE(mcv::gaussianWidgetOpacity(view, widgets, opCpu.data(), Device::CPU).ok());
      const mcv::TransferFunctionRun run = mcv::gaussianWidgetOpacity(view, widgets, opGpu.data(), Device::GPU);
      ASSERT_EQ(run.deviceUsed, Device::GPU);
      EXPECT_LE(maxDiff(opCpu, opGpu), 1e-5) << components << "D, " << count << " widgets, opacity";

      std::vector<unsigned char> bCpu(4 * view.count), bGpu(4 * view.count);
      ASSERT_TRUE(mcv::applyGaussianWidgets(view, widgets, bCpu.data(), Device::CPU).ok());
      ASSERT_EQ(mcv::applyGaussianWidgets(view, widgets, bGpu.data(), Device::GPU).deviceUsed, Device::GPU);
      std::size_t off = 0;
      for (std::size_t i = 0; i < bCpu.size(); ++i)
      {
        ASSERT_LE(std::abs(int(bCpu[i]) - int(bGpu[i])), 1) << i;
        off += bCpu[i] != bGpu[i];
      }
      EXPECT_LE(off, bCpu.size() / 10000) << "bytes off by one (float ties at k + 1/2)";
      // Non-finite voxels: transparent black on the GPU too.
      for (std::size_t v = 0; v < view.count; ++v)
      {
        bool finite = true;
        for (int d = 0; d < components; ++d)
          finite = finite && std::isfinite(coords[v * components + d]);
        if (!finite)
        {
          for (int k = 0; k < 4; ++k)
            ASSERT_EQ(rgba.gpu[4 * v + k], 0.f) << v;
        }
      }
    }
  }
  std::printf("[ agreement ] random coordinates, 1..16 widgets: max |GPU - CPU| = %.2e\n", worstAll);
}

TEST(GaussianTFGPU, Float16CoordinatesShadeAsTheirFloats)
{
  MCV_REQUIRE_GPU();
  std::mt19937 rng(16);
  const int components = 3;
  const std::vector<float> coords = randomCoords(100003, components, rng);
  std::vector<std::uint16_t> halves(coords.size());
  mcv::floatsToHalves(coords.data(), coords.size(), halves.data());
  std::vector<float> decoded(coords.size());
  mcv::halvesToFloats(halves.data(), halves.size(), decoded.data());
  const std::size_t n = coords.size() / components;
  const mcv::CoordinateView asFloats{ decoded.data(), n, components };
  mcv::CoordinateView asHalves{ nullptr, n, components };
  asHalves.halves = halves.data();
  const std::vector<GaussianWidget> widgets = randomWidgets(8, rng);
  // The halves cross the bus as they are and are widened on the device, exactly: the same
  // float32 values, so the same bits as the float32 run on the GPU, and within the GPU's
  // usual distance of the CPU's decode.
  std::vector<float> fromFloats(4 * n, -1.f), fromHalves(4 * n, -2.f), onCpu(4 * n, -3.f);
  const mcv::TransferFunctionRun a = mcv::applyGaussianWidgets(asFloats, widgets, fromFloats.data(), Device::GPU);
  const mcv::TransferFunctionRun b = mcv::applyGaussianWidgets(asHalves, widgets, fromHalves.data(), Device::GPU);
  ASSERT_TRUE(a.ok() && b.ok()) << a.error << b.error;
  EXPECT_EQ(a.deviceUsed, Device::GPU);
  EXPECT_EQ(b.deviceUsed, Device::GPU) << (b.warnings.empty() ? "" : b.warnings.back());
  EXPECT_EQ(fromHalves, fromFloats);
  ASSERT_TRUE(mcv::applyGaussianWidgets(asHalves, widgets, onCpu.data(), Device::CPU).ok());
  EXPECT_LE(maxDiff(onCpu, fromHalves), 1e-5);
}

TEST(GaussianTFGPU, ResidentCoordinatesFollowTheVersion)
{
  MCV_REQUIRE_GPU();
  std::mt19937 rng(5);
  std::vector<float> coords = randomCoords(50000, 3, rng);
  const std::vector<GaussianWidget> widgets = randomWidgets(4, rng);
  mcv::CoordinateView view{ coords.data(), coords.size() / 3, 3, 7 };
  const Both first = rgbaBoth(view, widgets);
  EXPECT_LE(maxDiff(first.cpu, first.gpu), 1e-5);

  // New values, new version: uploaded again. Version 0: always uploaded.
  for (float& x : coords)
    x = 1.f - x;
  for (std::uint64_t version : { std::uint64_t(8), std::uint64_t(0), std::uint64_t(0) })
  {
    view.version = version;
    const Both rgba = rgbaBoth(view, widgets);
    EXPECT_LE(maxDiff(rgba.cpu, rgba.gpu), 1e-5) << "version " << version;
    std::reverse(coords.begin(), coords.end());
  }

  // The cache object says when it copied.
  mcv::cuda::GaussianTFGpu gpu;
  std::string error;
  bool uploaded = false;
  ASSERT_TRUE(gpu.setCoordinates({ coords.data(), view.count, 3, 42 }, &error, &uploaded)) << error;
  EXPECT_TRUE(uploaded);
  ASSERT_TRUE(gpu.setCoordinates({ coords.data(), view.count, 3, 42 }, &error, &uploaded)) << error;
  EXPECT_FALSE(uploaded);
  ASSERT_TRUE(gpu.setCoordinates({ coords.data(), view.count, 3, 43 }, &error, &uploaded)) << error;
  EXPECT_TRUE(uploaded);
  ASSERT_TRUE(gpu.setCoordinates({ coords.data(), view.count - 1, 3, 43 }, &error, &uploaded)) << error;
  EXPECT_TRUE(uploaded);
  ASSERT_TRUE(gpu.setCoordinates({ coords.data(), view.count - 1, 3, 0 }, &error, &uploaded)) << error;
  EXPECT_TRUE(uploaded);
  mcv::releaseGaussianWidgetDeviceCache();
}

TEST(GaussianTFGPU, TooManyWidgetsFallBackToTheCPU)
{
  MCV_REQUIRE_GPU();
  std::mt19937 rng(9);
  const std::vector<float> coords = randomCoords(1000, 2, rng);
  const std::vector<GaussianWidget> widgets = randomWidgets(int(mcv::cuda::GaussianTFMaxWidgets) + 1, rng);
  std::vector<float> gpu(4 * 1000), cpu(4 * 1000);
  const mcv::TransferFunctionRun run = mcv::applyGaussianWidgets({ coords.data(), 1000, 2 }, widgets, gpu.data(), Device::GPU);
  ASSERT_TRUE(run.ok()) << run.error;
  EXPECT_EQ(run.deviceUsed, Device::CPU);
  ASSERT_FALSE(run.warnings.empty());
  EXPECT_NE(run.warnings.back().find("constant memory"), std::string::npos) << run.warnings.back();
  ASSERT_TRUE(mcv::applyGaussianWidgets({ coords.data(), 1000, 2 }, widgets, cpu.data(), Device::CPU).ok());
  EXPECT_EQ(maxDiff(cpu, gpu), 0.0);
}

TEST(GaussianTFGPU, Colin27PCACoordinates)
{
  MCV_REQUIRE_GPU();
  if (!mt::haveDataFile("ch2.nii.gz"))
  {
    GTEST_SKIP() << "ch2.nii.gz not in " << mt::dataDir() << " (scripts/fetch-data.sh)";
  }
  const mt::Volume brain = mt::loadNifti(mt::dataFile("ch2.nii.gz"));
  const std::size_t n = brain.grid.voxelCount();
  mcv::FeatureOptions fo;
  fo.preset = mcv::FeaturePreset::SixD;
  mcv::ChannelView channel;
  channel.data = brain.values.data();
  const int F = mcv::featureCount(1, fo);
  std::vector<float> features(n * F);
  mcv::FeatureResult fr;
  ASSERT_TRUE(mcv::computeFeatures({ channel }, brain.grid, fo, { features.data(), n, F }, fr)) << fr.error;
  for (int dims : { 2, 3 })
  {
    mcv::ReductionOptions ro;
    ro.outputDimension = dims;
    ro.trustworthinessSample = 0;
    const mcv::ReductionResult red = mcv::reduceDimension({ features.data(), n, F }, ro);
    ASSERT_TRUE(red.ok()) << red.error;
    // Widgets on 5 voxels' coordinates, sigma a fifth of the coordinates' spread.
    double spread = 0;
    for (int d = 0; d < dims; ++d)
    {
      float lo = std::numeric_limits<float>::infinity(), hi = -lo;
      for (std::size_t v = 0; v < n; ++v)
      {
        lo = std::min(lo, red.coordinates[v * dims + d]);
        hi = std::max(hi, red.coordinates[v * dims + d]);
      }
      spread = std::max(spread, double(hi - lo));
    }
    std::mt19937 rng(11);
    std::vector<GaussianWidget> widgets = randomWidgets(5, rng);
    std::uniform_int_distribution<std::size_t> voxel(0, n - 1);
    for (GaussianWidget& w : widgets)
    {
      const std::size_t v = voxel(rng);
      for (int d = 0; d < dims; ++d)
        w.center[d] = red.coordinates[v * dims + d];
      w.sigma = 0.2 * spread;
    }
    const mcv::CoordinateView view{ red.coordinates.data(), n, dims, 1 };
    const Both rgba = rgbaBoth(view, widgets);
    const double worst = maxDiff(rgba.cpu, rgba.gpu);
    double visible = 0;
    for (std::size_t v = 0; v < n; ++v)
      visible += rgba.cpu[4 * v + 3] > 0.05f;
    std::printf("[ agreement ] Colin27 6D features -> PCA %dD, %zu voxels (%.0f %% with alpha > 0.05): "
                "max |GPU - CPU| = %.2e\n", dims, n, 100 * visible / n, worst);
    EXPECT_LE(worst, 1e-5);
    EXPECT_GT(visible, 0.01 * n) << "the widgets should colour part of the brain";
  }
  mcv::releaseGaussianWidgetDeviceCache();
}

} // namespace
