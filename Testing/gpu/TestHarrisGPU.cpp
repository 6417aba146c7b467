// The CUDA path of the best-viewpoint pipeline against the CPU reference: Harris response
// per voxel (relative tolerance), top-N (exactly, for the selection alone; >= 99% overlap
// end to end, where float rounding may swap near-equal scores), and PCA view directions
// (within 0.5 degrees). Every test skips when no GPU is usable.
#include "cuda/DeviceProbe.h"
#include "cuda/HarrisCuda.h"
#include "cuda/HarrisPipeline.h"

#include "HarrisResponse.h"
#include "TopResponses.h"
#include "ViewFromPoints.h"

#include "PointComparison.h"
#include "RequireGpu.h"
#include "TestVolumes.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <limits>
#include <random>
#include <string>
#include <unordered_set>
#include <vector>

namespace
{

namespace mt = mcv::testing;
using mcv::HarrisParameters;
using mcv::ImageGrid;
using mcv::InterestPoints;

constexpr int kN = 2048;

// ---------------------------------------------------------------------------------------
// Comparison helpers
// ---------------------------------------------------------------------------------------

struct ResponseAgreement
{
  double maxAbsCpu = 0;     // max |R_cpu|
  double maxNormError = 0;  // max |R_gpu - R_cpu| / max |R_cpu|
  double maxRelError = 0;   // max |R_gpu - R_cpu| / |R_cpu| over |R_cpu| >= 1e-3 max
  std::size_t checked = 0;  // voxels in maxRelError
  std::size_t loose = 0;    // of those, relative error > 1e-3
  std::size_t nonFinite = 0;
  bool signMismatchLarge = false;
};

// R = det - k tr^3 cancels where det ~ k tr^3 and in flat-ish regions; both paths round
// differently (fused multiply-adds, summation order), so errors are judged against the
// volume's response scale as well as per voxel.
ResponseAgreement compareResponses(
  const std::vector<float>& gpu, const std::vector<float>& cpu, double gpuScale = 1.0)
{
  ResponseAgreement a;
  for (float c : cpu)
  {
    a.maxAbsCpu = std::max(a.maxAbsCpu, static_cast<double>(std::fabs(c)));
  }
  const double floor = 1e-3 * a.maxAbsCpu;
  for (std::size_t i = 0; i < cpu.size(); ++i)
  {
    const double g = static_cast<double>(gpu[i]) * gpuScale, c = cpu[i];
    if (!std::isfinite(g))
    {
      ++a.nonFinite;
      continue;
    }
    const double d = std::fabs(g - c);
    if (a.maxAbsCpu > 0)
    {
      a.maxNormError = std::max(a.maxNormError, d / a.maxAbsCpu);
    }
    if (std::fabs(c) >= floor && a.maxAbsCpu > 0)
    {
      ++a.checked;
      const double rel = d / std::fabs(c);
      a.maxRelError = std::max(a.maxRelError, rel);
      if (rel > 1e-3)
      {
        ++a.loose;
      }
      if (std::fabs(c) > 1e-2 * a.maxAbsCpu && (g > 0) != (c > 0))
      {
        a.signMismatchLarge = true;
      }
    }
  }
  return a;
}

void expectResponsesAgree(const ResponseAgreement& a, const std::string& what)
{
  SCOPED_TRACE(what);
  std::printf("[ agreement ] %-34s max|cpu| %.3e  max err/max|cpu| %.2e  max rel err %.2e  "
              "rel err > 1e-3: %zu of %zu\n",
    what.c_str(), a.maxAbsCpu, a.maxNormError, a.maxRelError, a.loose, a.checked);
  EXPECT_EQ(a.nonFinite, 0u);
  EXPECT_LE(a.maxNormError, 1e-4) << "max |gpu - cpu| / max|cpu|";
  // Per voxel: at most 1% of the significant voxels above 1e-3 relative error (voxels
  // where det and k tr^3 nearly cancel).
  EXPECT_LE(static_cast<double>(a.loose), 1e-2 * static_cast<double>(a.checked) + 1)
    << a.loose << " of " << a.checked << " voxels; max relative error " << a.maxRelError;
  EXPECT_FALSE(a.signMismatchLarge);
}

void expectOrdered(const InterestPoints& p)
{
  for (std::size_t i = 1; i < p.size(); ++i)
  {
    const bool ok = p.scores[i - 1] > p.scores[i] ||
      (p.scores[i - 1] == p.scores[i] && p.indices[i - 1] < p.indices[i]);
    ASSERT_TRUE(ok) << "order broken at " << i;
  }
  for (float s : p.scores)
  {
    ASSERT_TRUE(s > 0.f && std::isfinite(s));
  }
}

// GPU top-N vs CPU top-N of the same volume: overlap and view directions.
void expectTopNAgree(const InterestPoints& gpu, const InterestPoints& cpu, const ImageGrid& grid,
  const std::string& what, bool checkView = true)
{
  SCOPED_TRACE(what);
  expectOrdered(gpu);
  // Fewer candidates than N: a voxel with R near 0 may fall on either side of 0.
  const double sizeSlack = std::max(1.0, 0.01 * static_cast<double>(cpu.size()));
  EXPECT_LE(std::fabs(static_cast<double>(gpu.size()) - static_cast<double>(cpu.size())), sizeSlack);
  const double o = mcv::testing::indexOverlap(gpu, cpu);
  std::printf("[ top-N     ] %-34s %zu points, overlap %.4f\n", what.c_str(), cpu.size(), o);
  EXPECT_GE(o, cpu.size() >= 200 ? 0.99 : 0.95) << "top-N overlap";
  if (!checkView || cpu.size() < 16)
  {
    return;
  }
  const mcv::ViewDirections vg = mcv::computeViewDirections(mcv::worldPositions(gpu, grid));
  const mcv::ViewDirections vc = mcv::computeViewDirections(mcv::worldPositions(cpu, grid));
  ASSERT_TRUE(vc.valid) << vc.message;
  ASSERT_TRUE(vg.valid) << vg.message;
  // The best view is well defined only when the two smallest variances differ.
  const double gap = (vc.eigenvalues[1] - vc.eigenvalues[2]) / std::max(vc.eigenvalues[0], 1e-12);
  std::printf("[ view      ] %-34s best-view angle %.4f deg (eigen gap %.3f)\n", what.c_str(),
    mcv::axisAngleDegrees(vg.best, vc.best), gap);
  if (gap > 0.02)
  {
    EXPECT_LE(mcv::axisAngleDegrees(vg.best, vc.best), 0.5) << "best view direction";
  }
  const double gap01 = (vc.eigenvalues[0] - vc.eigenvalues[1]) / std::max(vc.eigenvalues[0], 1e-12);
  if (gap01 > 0.02)
  {
    EXPECT_LE(mcv::axisAngleDegrees(vg.worst, vc.worst), 0.5) << "worst view direction";
  }
}

std::vector<float> cpuResponse(const mt::Volume& v, const HarrisParameters& p)
{
  std::vector<float> r(v.values.size());
  mcv::computeHarrisResponseCPU(v.values.data(), v.grid, p, r.data());
  return r;
}

std::vector<float> gpuResponse(const mt::Volume& v, const HarrisParameters& p)
{
  std::vector<float> r(v.values.size(), std::numeric_limits<float>::quiet_NaN());
  std::string error;
  EXPECT_TRUE(mcv::cuda::harrisResponse(v.values.data(), v.grid, p, r.data(), &error)) << error;
  return r;
}

// Smooth random structure: random values, box-blurred once, so that Harris sees blobs
// and corners of several sizes (not only voxel noise).
mt::Volume smoothRandomVolume(const ImageGrid& grid, std::uint64_t seed)
{
  mt::Volume noise = mt::randomVolume(grid, seed);
  mt::Volume v = noise;
  const int nx = grid.dims[0], ny = grid.dims[1], nz = grid.dims[2];
  auto at = [&](int i, int j, int k) {
    i = std::max(0, std::min(nx - 1, i));
    j = std::max(0, std::min(ny - 1, j));
    k = std::max(0, std::min(nz - 1, k));
    return noise.values[(static_cast<std::size_t>(k) * ny + j) * nx + i];
  };
  for (int k = 0; k < nz; ++k)
    for (int j = 0; j < ny; ++j)
      for (int i = 0; i < nx; ++i)
      {
        float s = 0;
        for (int c = -1; c <= 1; ++c)
          for (int b = -1; b <= 1; ++b)
            for (int a = -1; a <= 1; ++a)
              s += at(i + a, j + b, k + c);
        v.values[(static_cast<std::size_t>(k) * ny + j) * nx + i] = s / 27.0f;
      }
  v.name = "smooth random";
  return v;
}

// ---------------------------------------------------------------------------------------
// Device query
// ---------------------------------------------------------------------------------------

TEST(HarrisGPU, DeviceUsableGivesAReason)
{
  std::string why;
  const bool usable = mcv::cuda::deviceUsable(&why);
  if (!usable)
  {
    EXPECT_FALSE(why.empty());
    GTEST_SKIP() << "no usable GPU: " << why;
  }
  SUCCEED();
}

// ---------------------------------------------------------------------------------------
// Response: GPU vs CPU
// ---------------------------------------------------------------------------------------

struct VolumeCase
{
  int nx, ny, nz;
  std::array<double, 3> spacing;
  std::uint64_t seed;
  bool smooth;
};

void PrintTo(const VolumeCase& c, std::ostream* os)
{
  *os << c.nx << "x" << c.ny << "x" << c.nz << " spacing (" << c.spacing[0] << ", "
      << c.spacing[1] << ", " << c.spacing[2] << ")";
}

class HarrisGPUVolumes : public ::testing::TestWithParam<VolumeCase>
{
};

TEST_P(HarrisGPUVolumes, ResponseAndTopNMatchCPU)
{
  MCV_REQUIRE_GPU();
  const VolumeCase c = GetParam();
  const ImageGrid grid = mt::makeGrid(c.nx, c.ny, c.nz, c.spacing, { 1.5, -2.0, 0.25 });
  const mt::Volume v = c.smooth ? smoothRandomVolume(grid, c.seed) : mt::randomVolume(grid, c.seed);
  const HarrisParameters p;
  const std::vector<float> rc = cpuResponse(v, p);
  const std::vector<float> rg = gpuResponse(v, p);
  expectResponsesAgree(compareResponses(rg, rc), "response");

  InterestPoints gpu;
  std::string error;
  ASSERT_TRUE(mcv::cuda::harrisTopN(v.values.data(), grid, p, kN, gpu, &error)) << error;
  const InterestPoints cpu = mcv::selectTopResponsesCPU(rc.data(), rc.size(), kN);
  expectTopNAgree(gpu, cpu, grid, "top-N");
  // The GPU's own response volume, selected on the CPU: the same set exactly.
  const InterestPoints cpuOfGpu = mcv::selectTopResponsesCPU(rg.data(), rg.size(), kN);
  EXPECT_EQ(gpu.indices, cpuOfGpu.indices);
  EXPECT_EQ(gpu.scores, cpuOfGpu.scores);
}

INSTANTIATE_TEST_SUITE_P(Sizes, HarrisGPUVolumes,
  ::testing::Values(VolumeCase{ 37, 53, 29, { 1, 1, 1 }, 11, false },
    VolumeCase{ 37, 53, 29, { 0.8, 1.3, 2.1 }, 12, true },
    VolumeCase{ 64, 64, 64, { 1, 1, 1 }, 13, true },
    VolumeCase{ 100, 70, 45, { 1.0, 0.5, 2.0 }, 14, true },
    VolumeCase{ 33, 17, 70, { 1, 1, 1 }, 15, false },
    VolumeCase{ 5, 6, 7, { 1, 1, 1 }, 16, false },  // smaller than the tile and the halo
    VolumeCase{ 129, 31, 3, { 1, 1, 1 }, 17, true }, // fewer slices than the kernel width
    VolumeCase{ 2, 40, 33, { 1, 1, 1 }, 18, false }),
  [](const ::testing::TestParamInfo<VolumeCase>& info) {
    const VolumeCase& c = info.param;
    std::string name = std::to_string(c.nx) + "x" + std::to_string(c.ny) + "x" + std::to_string(c.nz);
    if (c.spacing[0] != 1 || c.spacing[1] != 1 || c.spacing[2] != 1)
      name += "_anisotropic";
    return name + (c.smooth ? "_smooth" : "_noise");
  });

TEST(HarrisGPU, KernelWidths)
{
  MCV_REQUIRE_GPU();
  const mt::Volume v = smoothRandomVolume(mt::makeGrid(41, 35, 27, { 1.0, 1.2, 0.9 }), 21);
  for (int width : { 1, 3, 5, 7 })
  {
    HarrisParameters p;
    p.kernelWidth = width;
    p.sigma = width == 7 ? 2.0 : 1.5;
    p.k = width == 1 ? 0.04 : 0.004;
    expectResponsesAgree(compareResponses(gpuResponse(v, p), cpuResponse(v, p)),
      "kernel width " + std::to_string(width));
  }
  HarrisParameters wide;
  wide.kernelWidth = 9;
  std::vector<float> r(v.values.size());
  std::string error;
  EXPECT_FALSE(mcv::cuda::harrisResponse(v.values.data(), v.grid, wide, r.data(), &error));
  EXPECT_FALSE(error.empty());
}

TEST(HarrisGPU, SingleSlices)
{
  MCV_REQUIRE_GPU();
  const HarrisParameters p;
  for (const std::array<int, 3> dims : { std::array<int, 3>{ 45, 38, 1 },
         std::array<int, 3>{ 1, 45, 38 }, std::array<int, 3>{ 45, 1, 38 } })
  {
    const ImageGrid grid = mt::makeGrid(dims[0], dims[1], dims[2], { 0.7, 1.1, 1.6 });
    const mt::Volume v = smoothRandomVolume(grid, 31 + dims[0]);
    const std::vector<float> rc = cpuResponse(v, p);
    const std::vector<float> rg = gpuResponse(v, p);
    const std::string what = "slice " + std::to_string(dims[0]) + "x" + std::to_string(dims[1]) +
      "x" + std::to_string(dims[2]);
    expectResponsesAgree(compareResponses(rg, rc), what);
    InterestPoints gpu;
    std::string error;
    ASSERT_TRUE(mcv::cuda::harrisTopN(v.values.data(), grid, p, 300, gpu, &error)) << error;
    expectTopNAgree(gpu, mcv::selectTopResponsesCPU(rc.data(), rc.size(), 300), grid, what, false);
  }
}

// The kernel's response is the CPU path's bit for bit (both round the same operations in
// the same order), for every kernel width the GPU runs, partial tiles and a single slice.
TEST(HarrisGPU, ResponseBitsEqualTheCpu)
{
  MCV_REQUIRE_GPU();
  struct Case
  {
    std::array<int, 3> dims;
    int width;
  };
  for (const Case& c : { Case{ { 77, 45, 41 }, 5 }, Case{ { 37, 53, 29 }, 3 }, Case{ { 41, 35, 27 }, 7 },
         Case{ { 19, 13, 11 }, 1 }, Case{ { 45, 38, 1 }, 5 } })
  {
    const std::string what = std::to_string(c.dims[0]) + "x" + std::to_string(c.dims[1]) + "x" +
      std::to_string(c.dims[2]) + " width " + std::to_string(c.width);
    const mt::Volume v =
      smoothRandomVolume(mt::makeGrid(c.dims[0], c.dims[1], c.dims[2], { 0.8, 1.3, 1.1 }), 71 + c.width);
    HarrisParameters p;
    p.kernelWidth = c.width;
    const std::vector<float> rg = gpuResponse(v, p), rc = cpuResponse(v, p);
    std::size_t differ = 0;
    for (std::size_t i = 0; i < rg.size(); ++i)
    {
      differ += std::memcmp(&rg[i], &rc[i], sizeof(float)) != 0;
    }
    EXPECT_EQ(differ, 0u) << what;
  }
}

// A volume of zeros with the given non-zero voxels (x, y, z, value), values integral so
// that its float and uint8 forms are the same numbers.
mt::Volume sparseVolume(const ImageGrid& grid, const std::vector<std::array<int, 4>>& voxels)
{
  mt::Volume v;
  v.grid = grid;
  v.values.assign(grid.voxelCount(), 0.0f);
  for (const auto& p : voxels)
  {
    v.values[(static_cast<std::size_t>(p[2]) * grid.dims[1] + p[1]) * grid.dims[0] + p[0]] =
      static_cast<float>(p[3]);
  }
  return v;
}

// Empty-space skipping (a slice whose input tile is all zero is not computed, an output
// slice whose whole z window is such slices is stored as zeros) keeps the CPU's bits and
// top-N: every width-5 kernel variant, float and uint8 input, z chunks 0 (automatic) to 5,
// on volumes that are zero except (a) a small blob and a far-corner voxel, (b) single
// voxels at the outer edge of a block's input tile in x and y (the support of a voxel is 3
// voxels each way: a voxel at x = 34 reaches output x = 31 of the first 32-wide tile, one at
// x = 29 output x = 32 of the second; the same in y for the 16-high tiles) and at every z
// distance from the chunk boundaries of chunks 1, 2, 3 and 5, and (c) nothing. An
// off-by-one in the halo or in the z window makes the response 0 where the CPU's is not.
TEST(HarrisGPU, EmptySpaceSkippingKeepsTheCpuBits)
{
  MCV_REQUIRE_GPU();
  const ImageGrid grid = mt::makeGrid(77, 45, 41, { 0.8, 1.3, 1.1 });
  std::vector<std::array<int, 4>> blob;
  for (int z = 18; z <= 22; ++z)
    for (int y = 20; y <= 24; ++y)
      for (int x = 38; x <= 42; ++x)
      {
        const int d2 = (x - 40) * (x - 40) + (y - 22) * (y - 22) + (z - 20) * (z - 20);
        if (d2 <= 5)
          blob.push_back({ x, y, z, 200 - 30 * d2 });
      }
  blob.push_back({ 76, 44, 40, 255 });
  const std::vector<std::array<int, 4>> edges = { { 34, 7, 4, 255 }, { 29, 30, 9, 180 },
    { 50, 18, 15, 120 }, { 60, 13, 21, 255 }, { 66, 34, 26, 90 }, { 0, 0, 0, 255 },
    { 76, 0, 33, 200 }, { 10, 44, 40, 255 }, { 45, 29, 37, 77 } };
  struct Case
  {
    std::string name;
    mt::Volume volume;
  };
  const Case cases[] = { { "blob and corner", sparseVolume(grid, blob) },
    { "tile and chunk edges", sparseVolume(grid, edges) }, { "all zero", sparseVolume(grid, {}) } };
  const HarrisParameters p;
  for (const Case& c : cases)
  {
    const mt::Volume& v = c.volume;
    const std::vector<float> rc = cpuResponse(v, p);
    const InterestPoints topCpu = mcv::selectTopResponsesCPU(rc.data(), rc.size(), kN);
    std::size_t nonZero = 0;
    for (float r : rc)
    {
      nonZero += r != 0.f;
    }
    if (c.name == "all zero")
    {
      EXPECT_EQ(nonZero, 0u);
    }
    else
    {
      // the isolated voxels' supports: each reaches 7^3 voxels around it
      EXPECT_GT(nonZero, 7u * 7u * 7u) << c.name;
      EXPECT_GT(topCpu.size(), 0u) << c.name;
    }
    std::vector<std::uint8_t> bytes(v.values.size());
    for (std::size_t i = 0; i < bytes.size(); ++i)
    {
      bytes[i] = static_cast<std::uint8_t>(v.values[i]);
    }
    for (const bool asBytes : { false, true })
    {
      mcv::cuda::HarrisPipeline pipeline;
      std::string error;
      ASSERT_TRUE(asBytes ? pipeline.uploadVolume(bytes.data(), v.grid, &error)
                          : pipeline.uploadVolume(v.values.data(), v.grid, &error))
        << error;
      std::vector<float> rg(v.values.size());
      for (int variant = 0; variant < mcv::cuda::HarrisPipeline::kernelVariantCount(); ++variant)
        for (int chunk : { 0, 1, 2, 3, 5 })
        {
          SCOPED_TRACE(c.name + (asBytes ? ", uint8" : ", float") + ", variant " +
            std::to_string(variant) + ", zChunk " + std::to_string(chunk));
          pipeline.setKernelVariant(variant, 1);
          pipeline.setZChunk(chunk);
          std::fill(rg.begin(), rg.end(), std::numeric_limits<float>::quiet_NaN());
          ASSERT_TRUE(pipeline.response(p, rg.data(), &error)) << error;
          std::size_t differ = 0, first = rg.size();
          for (std::size_t i = 0; i < rg.size(); ++i)
          {
            if (std::memcmp(&rg[i], &rc[i], sizeof(float)) != 0)
            {
              first = std::min(first, i);
              ++differ;
            }
          }
          EXPECT_EQ(differ, 0u) << "first differing voxel " << first;
          InterestPoints top;
          ASSERT_TRUE(pipeline.topN(p, kN, top, &error)) << error;
          EXPECT_EQ(top.indices, topCpu.indices);
          EXPECT_EQ(top.scores, topCpu.scores);
        }
    }
  }
}

TEST(HarrisGPU, ZChunksGiveIdenticalResults)
{
  MCV_REQUIRE_GPU();
  const mt::Volume v = smoothRandomVolume(mt::makeGrid(70, 40, 37), 41);
  const HarrisParameters p;
  mcv::cuda::HarrisPipeline pipeline;
  std::string error;
  ASSERT_TRUE(pipeline.uploadVolume(v.values.data(), v.grid, &error)) << error;
  std::vector<float> reference(v.values.size()), other(v.values.size());
  ASSERT_TRUE(pipeline.response(p, reference.data(), &error)) << error;
  InterestPoints top0;
  ASSERT_TRUE(pipeline.topN(p, kN, top0, &error)) << error;
  for (int chunk : { 1, 2, 3, 5, 8, 36, 37, 100 })
  {
    pipeline.setZChunk(chunk);
    ASSERT_TRUE(pipeline.response(p, other.data(), &error)) << error;
    EXPECT_EQ(pipeline.lastZChunk(), std::min(chunk, 37));
    EXPECT_TRUE(reference == other) << "zChunk " << chunk;
    InterestPoints top;
    ASSERT_TRUE(pipeline.topN(p, kN, top, &error)) << error;
    EXPECT_EQ(top.indices, top0.indices) << "zChunk " << chunk;
  }
}

// Every width-5 variant, both histogram modes and z chunks of odd and even length (the
// two-slice variant's last round may hold one slice) give the default's bits and top-N; a
// volume thinner than the kernel repeats its border slices in every round. Float and uint8
// input (each variant's uint8 path keeps the loaded bytes its own way).
TEST(HarrisGPU, KernelVariantsGiveIdenticalResults)
{
  MCV_REQUIRE_GPU();
  for (const std::array<int, 3>& dims : { std::array<int, 3>{ 77, 45, 41 }, std::array<int, 3>{ 40, 21, 3 } })
    for (const bool bytes : { false, true })
  {
    const mt::Volume v = smoothRandomVolume(mt::makeGrid(dims[0], dims[1], dims[2], { 1.0, 0.8, 1.2 }), 51);
    const auto [lo, hi] = std::minmax_element(v.values.begin(), v.values.end());
    std::vector<std::uint8_t> b(v.values.size());
    for (std::size_t i = 0; i < b.size(); ++i)
    {
      b[i] = static_cast<std::uint8_t>(std::lround((v.values[i] - *lo) / (*hi - *lo) * 255.0f));
    }
    const HarrisParameters p;
    mcv::cuda::HarrisPipeline pipeline;
    std::string error;
    ASSERT_TRUE(bytes ? pipeline.uploadVolume(b.data(), v.grid, &error)
                      : pipeline.uploadVolume(v.values.data(), v.grid, &error))
      << error;
    std::vector<float> reference(v.values.size()), other(v.values.size());
    ASSERT_TRUE(pipeline.response(p, reference.data(), &error)) << error;
    InterestPoints top0;
    ASSERT_TRUE(pipeline.topN(p, kN, top0, &error)) << error;
    for (int variant = 0; variant < mcv::cuda::HarrisPipeline::kernelVariantCount(); ++variant)
      for (int histMode = 0; histMode < 2; ++histMode)
        for (int chunk : { 0, 1, 2, 3 })
        {
          SCOPED_TRACE("nz " + std::to_string(dims[2]) + (bytes ? " uint8" : " float") +
            ", variant " + std::to_string(variant) +
            ", histogram mode " + std::to_string(histMode) + ", zChunk " + std::to_string(chunk));
          pipeline.setKernelVariant(variant, histMode);
          pipeline.setZChunk(chunk);
          ASSERT_TRUE(pipeline.response(p, other.data(), &error)) << error;
          EXPECT_TRUE(reference == other);
          InterestPoints top;
          ASSERT_TRUE(pipeline.topN(p, kN, top, &error)) << error;
          EXPECT_EQ(top.indices, top0.indices);
          EXPECT_EQ(top.scores, top0.scores);
        }
  }
}

// Exact pruning of topN (HarrisBound.cuh): with every z chunk of the pruned blocks and
// share of phase A, float and uint8 input, the same points and scores as without it; on the
// structured volume it leaves most blocks out (else the test of sameness would pass with a
// gate that prunes nothing). A slow selection (forced) falls back to the whole volume; a
// k of at least 1/27 has no candidate at all (R <= tr^3 (1/27 - k) <= 0).
TEST(HarrisGPU, PruningGivesTheSameTopN)
{
  MCV_REQUIRE_GPU();
  const mt::Volume structured = mt::structuredVolume(192);
  const mt::Volume smooth = smoothRandomVolume(mt::makeGrid(77, 45, 41, { 1.0, 0.8, 1.2 }), 52);
  const mt::Volume noise = mt::randomVolume(mt::makeGrid(50, 37, 29), 53);
  for (const mt::Volume* v : { &structured, &smooth, &noise })
    for (const bool bytes : { false, true })
    {
      const auto [lo, hi] = std::minmax_element(v->values.begin(), v->values.end());
      std::vector<std::uint8_t> b(v->values.size());
      for (std::size_t i = 0; i < b.size(); ++i)
      {
        b[i] = static_cast<std::uint8_t>(std::lround((v->values[i] - *lo) / (*hi - *lo) * 255.0f));
      }
      mcv::cuda::HarrisPipeline pipeline;
      std::string error;
      ASSERT_TRUE(bytes ? pipeline.uploadVolume(b.data(), v->grid, &error)
                        : pipeline.uploadVolume(v->values.data(), v->grid, &error))
        << error;
      HarrisParameters p;
      pipeline.setPruning(mcv::cuda::HarrisPipeline::Pruning::Never);
      InterestPoints whole;
      ASSERT_TRUE(pipeline.topN(p, kN, whole, &error)) << error;
      ASSERT_GT(whole.size(), 0u);
      for (const std::array<int, 2>& setting : { std::array<int, 2>{ 8, 64 },
             std::array<int, 2>{ 1, 64 }, std::array<int, 2>{ 13, 1 }, std::array<int, 2>{ 4, 100000 } })
      {
        SCOPED_TRACE(v->name + (bytes ? " uint8" : " float") + ", z chunk " +
          std::to_string(setting[0]) + ", phase share 1/" + std::to_string(setting[1]));
        pipeline.setPruning(mcv::cuda::HarrisPipeline::Pruning::Always, setting[0], setting[1]);
        InterestPoints pruned;
        ASSERT_TRUE(pipeline.topN(p, kN, pruned, &error)) << error;
        EXPECT_EQ(pruned.indices, whole.indices);
        EXPECT_EQ(pruned.scores, whole.scores);
        const double share = pipeline.lastComputedBlockShare();
        std::printf("[ pruning ] %s%s z chunk %d, phase 1/%d: %.1f %% of the blocks computed\n",
          v->name.c_str(), bytes ? " uint8" : " float", setting[0], setting[1], 100.0 * share);
        EXPECT_GT(share, 0.0);
        if (v == &structured && setting[0] == 1 && setting[1] == 64)
        {
          EXPECT_LT(share, 0.4);
        }
      }
      pipeline.setPruning(mcv::cuda::HarrisPipeline::Pruning::Always);
      pipeline.setForceSlowSelect(true);
      InterestPoints slow;
      ASSERT_TRUE(pipeline.topN(p, kN, slow, &error)) << error;
      EXPECT_EQ(slow.indices, whole.indices);
      EXPECT_DOUBLE_EQ(pipeline.lastComputedBlockShare(), 1.0); // fell back to every block
      pipeline.setForceSlowSelect(false);
      p.k = 0.05;
      InterestPoints none;
      ASSERT_TRUE(pipeline.topN(p, kN, none, &error)) << error;
      EXPECT_EQ(none.size(), 0u);
    }
}

// Fewer candidates than N (a single small blob): phase A finds fewer than N, so every block
// with a non-zero bound is computed, and the points are those of the whole volume.
TEST(HarrisGPU, PruningWithFewerCandidatesThanN)
{
  MCV_REQUIRE_GPU();
  mt::Volume v;
  v.grid = mt::makeGrid(64, 48, 40);
  v.values.assign(v.grid.voxelCount(), 0.0f);
  for (int z = 18; z < 22; ++z)
    for (int y = 20; y < 25; ++y)
      for (int x = 30; x < 33; ++x)
      {
        v.values[(static_cast<std::size_t>(z) * 48 + y) * 64 + x] = 1.0f;
      }
  mcv::cuda::HarrisPipeline pipeline;
  std::string error;
  ASSERT_TRUE(pipeline.uploadVolume(v.values.data(), v.grid, &error)) << error;
  const HarrisParameters p;
  pipeline.setPruning(mcv::cuda::HarrisPipeline::Pruning::Never);
  InterestPoints whole, pruned;
  ASSERT_TRUE(pipeline.topN(p, kN, whole, &error)) << error;
  pipeline.setPruning(mcv::cuda::HarrisPipeline::Pruning::Always);
  ASSERT_TRUE(pipeline.topN(p, kN, pruned, &error)) << error;
  ASSERT_GT(whole.size(), 0u);
  EXPECT_LT(whole.size(), static_cast<std::size_t>(kN));
  EXPECT_EQ(pruned.indices, whole.indices);
  EXPECT_EQ(pruned.scores, whole.scores);
}

TEST(HarrisGPU, Uint8VolumeRanksLikeFloat)
{
  MCV_REQUIRE_GPU();
  const mt::Volume v = mt::structuredVolume(72);
  std::vector<std::uint8_t> bytes(v.values.size());
  for (std::size_t i = 0; i < bytes.size(); ++i)
  {
    bytes[i] = static_cast<std::uint8_t>(std::lround(v.values[i] * 255.0f));
  }
  const HarrisParameters p;
  mcv::cuda::HarrisPipeline pipeline;
  std::string error;
  ASSERT_TRUE(pipeline.uploadVolume(bytes.data(), v.grid, &error)) << error;
  std::vector<float> rg(v.values.size());
  ASSERT_TRUE(pipeline.response(p, rg.data(), &error)) << error;
  const std::vector<float> rc = cpuResponse(v, p);
  expectResponsesAgree(compareResponses(rg, rc, std::pow(255.0, -6.0)), "uint8 response / 255^6");
  InterestPoints gpu;
  mcv::cuda::GpuStageTimings t;
  ASSERT_TRUE(pipeline.topN(p, kN, gpu, &error, &t)) << error;
  EXPECT_GT(t.harrisMs, 0.0);
  EXPECT_GE(t.selectMs, 0.0);
  std::printf("[ select    ] structured 72 uint8: list of %lld candidates, %s path\n",
    pipeline.lastListSize(), pipeline.lastSelectUsedSlowPath() ? "slow" : "fast");
  EXPECT_FALSE(pipeline.lastSelectUsedSlowPath());
  expectTopNAgree(gpu, mcv::selectTopResponsesCPU(rc.data(), rc.size(), kN), v.grid, "uint8 top-N");
}

TEST(HarrisGPU, StructuredVolumeViewDirections)
{
  MCV_REQUIRE_GPU();
  mt::Volume v = mt::structuredVolume(96);
  v.grid.spacing = { 1.0, 0.9, 1.4 };
  const HarrisParameters p;
  const std::vector<float> rc = cpuResponse(v, p);
  InterestPoints gpu;
  std::string error;
  ASSERT_TRUE(mcv::cuda::harrisTopN(v.values.data(), v.grid, p, kN, gpu, &error)) << error;
  expectTopNAgree(gpu, mcv::selectTopResponsesCPU(rc.data(), rc.size(), kN), v.grid, "structured 96");
}

TEST(HarrisGPU, BadInputIsRefused)
{
  MCV_REQUIRE_GPU();
  const HarrisParameters p;
  std::vector<float> values(64, 0.5f);
  InterestPoints out;
  std::string error;
  EXPECT_FALSE(mcv::cuda::harrisTopN(values.data(), mt::makeGrid(64, 1, 1), p, 10, out, &error));
  EXPECT_FALSE(error.empty());
  error.clear();
  EXPECT_FALSE(mcv::cuda::harrisTopN(values.data(), mt::makeGrid(8, 0, 8), p, 10, out, &error));
  EXPECT_FALSE(error.empty());
  HarrisParameters even;
  even.kernelWidth = 4;
  error.clear();
  EXPECT_FALSE(mcv::cuda::harrisTopN(values.data(), mt::makeGrid(4, 4, 4), even, 10, out, &error));
  EXPECT_FALSE(error.empty());
}

TEST(HarrisGPU, FlatVolumeHasNoPoints)
{
  MCV_REQUIRE_GPU();
  const mt::Volume v = mt::constantVolume(mt::makeGrid(40, 30, 20), 0.3f);
  InterestPoints out;
  std::string error;
  ASSERT_TRUE(mcv::cuda::harrisTopN(v.values.data(), v.grid, HarrisParameters(), kN, out, &error))
    << error;
  EXPECT_EQ(out.size(), 0u);
}

// ---------------------------------------------------------------------------------------
// Selection alone: exactly the CPU's answer, ties included
// ---------------------------------------------------------------------------------------

void expectSameSelection(
  const std::vector<float>& scores, int N, const std::string& what, bool expectFastPath = false)
{
  const InterestPoints cpu = mcv::selectTopResponsesCPU(scores.data(), scores.size(), N);
  mcv::cuda::HarrisPipeline pipeline;
  for (bool forceSlow : { false, true })
  {
    SCOPED_TRACE(what + ", N = " + std::to_string(N) + (forceSlow ? ", slow path" : ""));
    pipeline.setForceSlowSelect(forceSlow);
    InterestPoints gpu;
    std::string error;
    ASSERT_TRUE(pipeline.selectFromScores(scores.data(), scores.size(), N, gpu, &error)) << error;
    if (forceSlow)
    {
      EXPECT_TRUE(pipeline.lastSelectUsedSlowPath());
    }
    else if (expectFastPath)
    {
      EXPECT_FALSE(pipeline.lastSelectUsedSlowPath());
    }
    ASSERT_EQ(gpu.size(), cpu.size());
    EXPECT_EQ(gpu.indices, cpu.indices);
    for (std::size_t i = 0; i < cpu.size(); ++i)
    {
      ASSERT_EQ(gpu.scores[i], cpu.scores[i]) << "at " << i;
    }
  }
}

TEST(TopNGPU, MatchesCPUWithTiesAndSpecialValues)
{
  MCV_REQUIRE_GPU();
  std::mt19937_64 rng(5);
  std::vector<float> s(1 << 20);
  std::uniform_int_distribution<int> level(-20, 60);
  for (float& x : s)
  {
    x = static_cast<float>(level(rng)) * 0.125f; // many exact ties, negatives, zeros
  }
  const float inf = std::numeric_limits<float>::infinity();
  s[7] = std::numeric_limits<float>::quiet_NaN();
  s[8] = inf;
  s[9] = -inf;
  s[10] = std::numeric_limits<float>::denorm_min();
  s[11] = std::numeric_limits<float>::max();
  s[12] = -0.0f;
  for (int N : { 1, 2, 100, 2048, 5000 })
  {
    expectSameSelection(s, N, "quantised ties");
  }
}

TEST(TopNGPU, LowBitsDecide)
{
  MCV_REQUIRE_GPU();
  // All scores in one level-1 bin (and many in one level-2 bin): levels 2 and 3 decide.
  std::mt19937_64 rng(6);
  std::vector<float> s(300000);
  std::uniform_int_distribution<std::uint32_t> low(0, (1u << 14) - 1);
  for (float& x : s)
  {
    std::uint32_t bits = 0x3F800000u | low(rng); // 1.0 .. 1.0 + 2^-9, step 2^-23
    std::memcpy(&x, &bits, 4);
  }
  for (int N : { 1, 777, 2048, 16384 })
  {
    expectSameSelection(s, N, "one level-1 bin");
  }
  // 300000 entries in the N-th score's bin: longer than the fast list, the slow path runs.
  mcv::cuda::HarrisPipeline pipeline;
  InterestPoints gpu;
  std::string error;
  ASSERT_TRUE(pipeline.selectFromScores(s.data(), s.size(), 777, gpu, &error)) << error;
  EXPECT_TRUE(pipeline.lastSelectUsedSlowPath());
  EXPECT_EQ(pipeline.lastListSize(), static_cast<long long>(s.size()));
}

TEST(TopNGPU, ModerateTiesOnTheFastPath)
{
  MCV_REQUIRE_GPU();
  // ~200 copies of each value: more ties at the threshold than places, few enough for the
  // one-block tie sort; the list (the threshold's level-1 bin) fits the fast path.
  std::vector<float> s(200000);
  for (std::size_t i = 0; i < s.size(); ++i)
  {
    s[i] = static_cast<float>((i * 7919) % 997) + 1.0f;
  }
  for (int N : { 1, 100, 1000, 2048 })
  {
    expectSameSelection(s, N, "moderate ties", true);
  }
  expectSameSelection(s, 2049, "N above the fast path's 2048");
  expectSameSelection(s, 5000, "N above the fast path's 2048");
}

TEST(TopNGPU, FewerCandidatesThanN)
{
  MCV_REQUIRE_GPU();
  std::vector<float> s(100000, 0.0f);
  for (int i = 0; i < 1500; ++i)
  {
    s[(i * 7919) % s.size()] = 1.0f + static_cast<float>(i % 37);
  }
  expectSameSelection(s, 2048, "1500 candidates");
  expectSameSelection(s, 1500, "exactly N candidates");
  expectSameSelection(std::vector<float>(5000, -1.0f), 2048, "no candidates");
  expectSameSelection(std::vector<float>(70000, 2.5f), 2048, "all equal");
}

TEST(TopNGPU, HarrisScaleValues)
{
  MCV_REQUIRE_GPU();
  // Scores spread over many binades, as Harris responses are.
  std::mt19937_64 rng(8);
  std::lognormal_distribution<float> dist(-20.0f, 6.0f);
  std::bernoulli_distribution positive(0.4);
  std::vector<float> s(3000000);
  for (float& x : s)
  {
    x = positive(rng) ? dist(rng) : -dist(rng);
  }
  expectSameSelection(s, 2048, "log-normal");
}

// ---------------------------------------------------------------------------------------
// Real volumes (skipped when scripts/fetch-data.sh has not fetched them)
// ---------------------------------------------------------------------------------------

void realVolumeCase(const mt::Volume& raw)
{
  mt::Volume v = raw;
  v.values = mt::rampToUnit(raw);
  const HarrisParameters p;
  const std::vector<float> rc = cpuResponse(v, p);
  const std::vector<float> rg = gpuResponse(v, p);
  expectResponsesAgree(compareResponses(rg, rc), v.name + " response");
  InterestPoints gpu;
  std::string error;
  ASSERT_TRUE(mcv::cuda::harrisTopN(v.values.data(), v.grid, p, kN, gpu, &error)) << error;
  const InterestPoints cpu = mcv::selectTopResponsesCPU(rc.data(), rc.size(), kN);
  expectTopNAgree(gpu, cpu, v.grid, v.name + " top-N");
  std::printf("[ %s ] %dx%dx%d top-%d overlap %.4f\n", v.name.c_str(), v.grid.dims[0],
    v.grid.dims[1], v.grid.dims[2], kN, mcv::testing::indexOverlap(gpu, cpu));
}

TEST(HarrisGPUReal, Colin27)
{
  MCV_REQUIRE_GPU();
  if (!mt::haveDataFile("ch2.nii.gz"))
  {
    GTEST_SKIP() << "ch2.nii.gz not in " << mt::dataDir() << " (scripts/fetch-data.sh)";
  }
  realVolumeCase(mt::loadNifti(mt::dataFile("ch2.nii.gz")));
}

TEST(HarrisGPUReal, BrainSmall)
{
  MCV_REQUIRE_GPU();
  if (!mt::haveDataFile("brainsmall.den"))
  {
    GTEST_SKIP() << "brainsmall.den not in " << mt::dataDir() << " (scripts/fetch-data.sh)";
  }
  realVolumeCase(mt::loadVolPackDen(mt::dataFile("brainsmall.den"), true));
}

} // namespace
