// The z-slab path of the best viewpoint (HarrisSlabStream: halo slices, running top-N)
// against the whole-volume GPU pipeline: the same N points (indices and scores, exactly)
// and so the same view, for several slab heights, forced byte budgets, slab boundaries
// placed on the strongest points, float and uint8 input; and against the CPU path as the
// whole-volume agreement tests do. The slab plan is checked without a GPU.
#include "cuda/HarrisCuda.h"
#include "cuda/HarrisPipeline.h"
#include "cuda/HarrisSlabStream.h"

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
#include <set>
#include <string>
#include <vector>

namespace
{

namespace mt = mcv::testing;
using mcv::HarrisParameters;
using mcv::ImageGrid;
using mcv::InterestPoints;

constexpr int kN = 2048;
constexpr std::size_t kMiB = std::size_t(1) << 20;

// ---------------------------------------------------------------------------------------
// The plan (no GPU needed)
// ---------------------------------------------------------------------------------------

TEST(SlabPlan, LargestSlabWithinTheBudget)
{
  const ImageGrid grid = mt::makeGrid(300, 200, 500);
  const std::size_t plane = 300 * 200;
  for (int bytes : { 1, 4 })
    for (int width : { 1, 3, 5, 7 })
      for (std::size_t budget : { 80 * kMiB, 100 * kMiB, 333 * kMiB, 1000 * kMiB })
      {
        SCOPED_TRACE(std::to_string(bytes) + " B/voxel, width " + std::to_string(width) +
          ", budget " + std::to_string(budget / kMiB) + " MiB");
        const mcv::cuda::SlabPlan p = mcv::cuda::planSlabs(grid, bytes, width, budget);
        EXPECT_EQ(p.halo, 1 + width / 2);
        ASSERT_GE(p.ownedSlices, 1);
        EXPECT_LE(p.ownedSlices, 500);
        EXPECT_EQ(p.slabs, (500 + p.ownedSlices - 1) / p.ownedSlices);
        EXPECT_LE(p.deviceBytes, budget);
        // Two input slabs with halos + the owned scores + the selection reserve.
        const std::size_t in = std::min<std::size_t>(p.ownedSlices + 2 * p.halo, 500);
        EXPECT_EQ(p.deviceBytes, 2 * in * plane * bytes + p.ownedSlices * plane * 4 +
            mcv::cuda::kSelectionReserveBytes);
        if (p.ownedSlices < 500)
        {
          // One more owned slice would not fit (the planned bound counts full halos).
          const std::size_t more = 2 * (p.ownedSlices + 1 + 2 * p.halo) * plane * bytes +
            (p.ownedSlices + 1) * plane * 4 + mcv::cuda::kSelectionReserveBytes;
          EXPECT_GT(more, budget);
        }
      }
}

TEST(SlabPlan, TooSmallBudgetsAndCaps)
{
  const ImageGrid grid = mt::makeGrid(1024, 1024, 64);
  // 64 MiB is the selection reserve alone; 80 MiB cannot hold 2 x (1 + 6) float slices + 1.
  EXPECT_EQ(mcv::cuda::planSlabs(grid, 4, 5, 64 * kMiB).ownedSlices, 0);
  EXPECT_EQ(mcv::cuda::planSlabs(grid, 4, 5, 80 * kMiB).ownedSlices, 0);
  EXPECT_EQ(mcv::cuda::planSlabs(grid, 4, 5, 0).ownedSlices, 0);
  const mcv::cuda::SlabPlan whole = mcv::cuda::planSlabs(grid, 1, 5, std::size_t(64) << 30);
  EXPECT_EQ(whole.ownedSlices, 64);
  EXPECT_EQ(whole.slabs, 1);
  const mcv::cuda::SlabPlan capped = mcv::cuda::planSlabs(grid, 1, 5, std::size_t(64) << 30, 10);
  EXPECT_EQ(capped.ownedSlices, 10);
  EXPECT_EQ(capped.slabs, 7);
  EXPECT_EQ(mcv::cuda::wholeVolumeDeviceBytes(grid, 1),
    grid.voxelCount() * 5 + mcv::cuda::kSelectionReserveBytes);
  EXPECT_EQ(mcv::cuda::deviceBudgetBytes(123 * kMiB), 123 * kMiB); // an explicit limit wins
}

// ---------------------------------------------------------------------------------------
// Slabs vs the whole volume on the GPU
// ---------------------------------------------------------------------------------------

template <typename T>
InterestPoints wholeTopN(const std::vector<T>& values, const ImageGrid& grid, const HarrisParameters& p)
{
  mcv::cuda::HarrisPipeline pipeline;
  std::string error;
  InterestPoints out;
  EXPECT_TRUE(pipeline.uploadVolume(values.data(), grid, &error)) << error;
  EXPECT_TRUE(pipeline.topN(p, kN, out, &error)) << error;
  return out;
}

void expectSamePoints(const InterestPoints& slabs, const InterestPoints& whole, const ImageGrid& grid)
{
  ASSERT_FALSE(whole.indices.empty());
  EXPECT_EQ(slabs.indices, whole.indices);
  EXPECT_EQ(slabs.scores, whole.scores);
  if (whole.size() >= 16)
  {
    const mcv::ViewDirections a = mcv::computeViewDirections(mcv::worldPositions(slabs, grid));
    const mcv::ViewDirections b = mcv::computeViewDirections(mcv::worldPositions(whole, grid));
    EXPECT_EQ(a.valid, b.valid);
    EXPECT_EQ(mcv::axisAngleDegrees(a.best, b.best), 0.0);
  }
}

// Runs the slab stream with at most `slices` owned slices per slab.
template <typename T>
InterestPoints slabTopN(mcv::cuda::HarrisSlabStream& stream, const std::vector<T>& values,
  const ImageGrid& grid, const HarrisParameters& p, int slices, mcv::cuda::SlabTimings* t = nullptr)
{
  stream.setBudgetBytes(std::size_t(1) << 30);
  stream.setMaxOwnedSlices(slices);
  InterestPoints out;
  std::string error;
  EXPECT_TRUE(stream.topN(values.data(), grid, p, kN, out, &error, t)) << error;
  return out;
}

std::vector<std::uint8_t> toBytes(const std::vector<float>& v)
{
  std::vector<std::uint8_t> b(v.size());
  for (std::size_t i = 0; i < v.size(); ++i)
    b[i] = static_cast<std::uint8_t>(std::lround(std::min(1.f, std::max(0.f, v[i])) * 255.0f));
  return b;
}

TEST(HarrisSlabsGPU, RandomVolumesEqualWholeVolume)
{
  MCV_REQUIRE_GPU();
  mcv::cuda::HarrisSlabStream stream;
  struct Case
  {
    int nx, ny, nz;
    std::array<double, 3> spacing;
    int width;
  };
  // (Width 1 has no case: without smoothing the tensor has rank 1, det = 0, and no voxel has
  // a positive response, so there is nothing to compare.)
  for (const Case c : { Case{ 61, 47, 40, { 1, 1, 1 }, 5 }, Case{ 37, 53, 29, { 0.8, 1.3, 2.1 }, 5 },
         Case{ 40, 33, 31, { 1, 1, 1 }, 3 }, Case{ 40, 33, 31, { 1, 0.9, 1.2 }, 7 },
         Case{ 33, 17, 70, { 1, 1, 1 }, 3 }, Case{ 45, 38, 3, { 1, 1, 1 }, 5 } })
  {
    HarrisParameters p;
    p.kernelWidth = c.width;
    p.sigma = c.width == 7 ? 2.0 : 1.5;
    const ImageGrid grid = mt::makeGrid(c.nx, c.ny, c.nz, c.spacing, { 1.5, -2.0, 0.25 });
    const mt::Volume v = mt::randomVolume(grid, 100 + c.nz + c.width);
    const InterestPoints whole = wholeTopN(v.values, grid, p);
    const std::vector<std::uint8_t> bytes = toBytes(v.values);
    const InterestPoints wholeBytes = wholeTopN(bytes, grid, p);
    for (int slices : { 1, 2, 3, 5, 8, 13, c.nz - 1, c.nz })
    {
      if (slices < 1)
        continue;
      SCOPED_TRACE(std::to_string(c.nx) + "x" + std::to_string(c.ny) + "x" + std::to_string(c.nz) +
        " width " + std::to_string(c.width) + ", " + std::to_string(slices) + " slices per slab");
      mcv::cuda::SlabTimings t;
      expectSamePoints(slabTopN(stream, v.values, grid, p, slices, &t), whole, grid);
      EXPECT_EQ(t.slabs, (c.nz + std::min(slices, c.nz) - 1) / std::min(slices, c.nz));
      EXPECT_EQ(t.halo, 1 + c.width / 2);
      expectSamePoints(slabTopN(stream, bytes, grid, p, slices), wholeBytes, grid);
    }
  }
}

// Slab boundaries on the strongest points: each of the ten strongest voxels becomes the
// first owned slice of a slab (boundary just below it) and the last (just above it).
TEST(HarrisSlabsGPU, BoundariesThroughTheStrongestPoints)
{
  MCV_REQUIRE_GPU();
  mt::Volume v = mt::structuredVolume(80);
  v.grid.spacing = { 1.0, 0.9, 1.4 };
  const HarrisParameters p;
  const InterestPoints whole = wholeTopN(v.values, v.grid, p);
  ASSERT_GE(whole.size(), 10u);
  const std::int64_t plane = 80 * 80;
  std::set<int> heights;
  for (std::size_t i = 0; i < 10; ++i)
  {
    const int z = static_cast<int>(whole.indices[i] / plane);
    // Uniform heights S put boundaries at multiples of S: S = z cuts below z, S = z + 1 above.
    for (int s : { z, z + 1 })
      if (s >= 1 && s < 80)
        heights.insert(s);
  }
  ASSERT_FALSE(heights.empty());
  mcv::cuda::HarrisSlabStream stream;
  for (int s : heights)
  {
    SCOPED_TRACE(std::to_string(s) + " slices per slab");
    mcv::cuda::SlabTimings t;
    expectSamePoints(slabTopN(stream, v.values, v.grid, p, s, &t), whole, v.grid);
    EXPECT_GE(t.slabs, 2);
  }
  std::printf("[ slabs     ] structured 80: strongest points on boundaries of %zu slab heights\n",
    heights.size());
}

// Gaussian blobs centred exactly on slab boundaries (and one slice either side): the
// strongest responses straddle the boundaries.
TEST(HarrisSlabsGPU, BlobsOnTheBoundaries)
{
  MCV_REQUIRE_GPU();
  const ImageGrid grid = mt::makeGrid(64, 56, 48);
  std::vector<mt::Blob> blobs;
  const int S = 12; // boundaries at z = 12, 24, 36
  for (int k = 1; k * S < 48; ++k)
    for (int dz : { -1, 0, 1 })
    {
      mt::Blob b;
      b.center = { 10.0 + 14 * k + 3 * dz, 12.0 + 9 * k - 2 * dz, static_cast<double>(k * S + dz) - 0.5 };
      b.sigma = 2.0 + 0.3 * k;
      b.amplitude = 0.9;
      blobs.push_back(b);
    }
  const mt::Volume v = mt::gaussianBlobs(grid, blobs);
  const HarrisParameters p;
  const InterestPoints whole = wholeTopN(v.values, grid, p);
  mcv::cuda::HarrisSlabStream stream;
  mcv::cuda::SlabTimings t;
  expectSamePoints(slabTopN(stream, v.values, grid, p, S, &t), whole, grid);
  EXPECT_EQ(t.slabs, 4);
  const std::vector<std::uint8_t> bytes = toBytes(v.values);
  expectSamePoints(slabTopN(stream, bytes, grid, p, S), wholeTopN(bytes, grid, p), grid);
}

// A byte budget (no slice cap) that holds a few slabs: the plan's slab count, same points.
TEST(HarrisSlabsGPU, ForcedByteBudget)
{
  MCV_REQUIRE_GPU();
  const mt::Volume v = mt::structuredVolume(128);
  const std::vector<std::uint8_t> bytes = toBytes(v.values);
  const HarrisParameters p;
  const std::size_t plane = 128 * 128;
  // uint8: 64 MiB reserve + 2 x (S + 6) slices + 4 S slices -> S = 40 slices: 4 slabs.
  const std::size_t budget = mcv::cuda::kSelectionReserveBytes + (2 * (40 + 6) + 4 * 40) * plane;
  mcv::cuda::HarrisSlabStream stream;
  stream.setBudgetBytes(budget);
  InterestPoints out;
  std::string error;
  mcv::cuda::SlabTimings t;
  ASSERT_TRUE(stream.topN(bytes.data(), v.grid, p, kN, out, &error, &t)) << error;
  EXPECT_EQ(t.ownedSlices, 40);
  EXPECT_EQ(t.slabs, 4);
  EXPECT_LE(t.deviceBytes, budget);
  EXPECT_GT(t.harrisMs, 0.0);
  expectSamePoints(out, wholeTopN(bytes, v.grid, p), v.grid);

  stream.setBudgetBytes(mcv::cuda::kSelectionReserveBytes + 2 * plane); // not one slab
  EXPECT_FALSE(stream.topN(bytes.data(), v.grid, p, kN, out, &error));
  EXPECT_NE(error.find("not even one z-slab"), std::string::npos) << error;
  EXPECT_TRUE(out.indices.empty());
  // The stream recovers on the next call.
  stream.setBudgetBytes(budget);
  ASSERT_TRUE(stream.topN(bytes.data(), v.grid, p, kN, out, &error)) << error;
  EXPECT_EQ(out.indices, wholeTopN(bytes, v.grid, p).indices);
}

// ---------------------------------------------------------------------------------------
// harrisTopN (the core's entry point) under a small budget: slabs, and the CPU agrees
// ---------------------------------------------------------------------------------------

// Restores the default budget when a test ends (also on a failed assertion).
struct BudgetGuard
{
  explicit BudgetGuard(std::size_t bytes) { mcv::cuda::setHarrisDeviceBudget(bytes); }
  ~BudgetGuard()
  {
    mcv::cuda::setHarrisDeviceBudget(0);
    mcv::cuda::releaseHarrisCache();
  }
};

void expectSlabbedMatchesWholeAndCPU(const mt::Volume& v, std::size_t budget, int minSlabs)
{
  const HarrisParameters p;
  InterestPoints whole, slabs;
  std::string error;
  mcv::cuda::GpuStageTimings tw, ts;
  ASSERT_TRUE(mcv::cuda::harrisTopN(v.values.data(), v.grid, p, kN, whole, &error, &tw)) << error;
  EXPECT_EQ(tw.slabs, 0);
  {
    BudgetGuard guard(budget);
    ASSERT_TRUE(mcv::cuda::harrisTopN(v.values.data(), v.grid, p, kN, slabs, &error, &ts)) << error;
  }
  EXPECT_GE(ts.slabs, minSlabs);
  expectSamePoints(slabs, whole, v.grid);

  // The CPU path: the GPU's response selected on the CPU gives the same points exactly; the
  // CPU's own response (float rounding differs) at least 99% of them and the same view.
  std::vector<float> rg(v.values.size()), rc(v.values.size());
  ASSERT_TRUE(mcv::cuda::harrisResponse(v.values.data(), v.grid, p, rg.data(), &error)) << error;
  const InterestPoints cpuOfGpu = mcv::selectTopResponsesCPU(rg.data(), rg.size(), kN);
  EXPECT_EQ(slabs.indices, cpuOfGpu.indices);
  EXPECT_EQ(slabs.scores, cpuOfGpu.scores);
  mcv::computeHarrisResponseCPU(v.values.data(), v.grid, p, rc.data());
  const InterestPoints cpu = mcv::selectTopResponsesCPU(rc.data(), rc.size(), kN);
  const double overlap = mt::indexOverlap(slabs, cpu);
  const mcv::ViewDirections vs = mcv::computeViewDirections(mcv::worldPositions(slabs, v.grid));
  const mcv::ViewDirections vc = mcv::computeViewDirections(mcv::worldPositions(cpu, v.grid));
  ASSERT_TRUE(vc.valid && vs.valid);
  const double angle = mcv::axisAngleDegrees(vs.best, vc.best);
  const double gap = (vc.eigenvalues[1] - vc.eigenvalues[2]) / std::max(vc.eigenvalues[0], 1e-12);
  std::printf("[ slabs     ] %-20s %d slabs: top-N overlap with the CPU %.4f, best-view angle "
              "%.4f deg (eigen gap %.3f)\n",
    v.name.c_str(), ts.slabs, overlap, angle, gap);
  EXPECT_GE(overlap, 0.99);
  if (gap > 0.02)
  {
    EXPECT_LE(angle, 0.5);
  }
}

TEST(HarrisSlabsGPU, EntryPointUnderASmallBudgetMatchesWholeAndCPU)
{
  MCV_REQUIRE_GPU();
  mt::Volume v = mt::structuredVolume(96);
  v.grid.spacing = { 1.0, 0.9, 1.4 };
  // float: 64 MiB reserve + 2 x (S + 6) x 36 KiB + S x 36 KiB: about 20 slices, 5 slabs.
  const std::size_t plane = 96 * 96 * 4;
  expectSlabbedMatchesWholeAndCPU(v, mcv::cuda::kSelectionReserveBytes + 3 * 26 * plane, 4);
}

void realVolumeCase(const mt::Volume& raw)
{
  mt::Volume v = raw;
  v.values = mt::rampToUnit(raw);
  // Budget for about 1/5 of the slices per slab (float input).
  const std::size_t plane = static_cast<std::size_t>(v.grid.dims[0]) * v.grid.dims[1] * 4;
  const std::size_t slices = std::max(1, v.grid.dims[2] / 5);
  expectSlabbedMatchesWholeAndCPU(v, mcv::cuda::kSelectionReserveBytes + (3 * slices + 12) * plane, 4);
}

TEST(HarrisSlabsGPUReal, BrainSmall)
{
  MCV_REQUIRE_GPU();
  if (!mt::haveDataFile("brainsmall.den"))
  {
    GTEST_SKIP() << "brainsmall.den not in " << mt::dataDir() << " (scripts/fetch-data.sh)";
  }
  realVolumeCase(mt::loadVolPackDen(mt::dataFile("brainsmall.den"), true));
}

TEST(HarrisSlabsGPUReal, Colin27)
{
  MCV_REQUIRE_GPU();
  if (!mt::haveDataFile("ch2.nii.gz"))
  {
    GTEST_SKIP() << "ch2.nii.gz not in " << mt::dataDir() << " (scripts/fetch-data.sh)";
  }
  realVolumeCase(mt::loadNifti(mt::dataFile("ch2.nii.gz")));
}

} // namespace
