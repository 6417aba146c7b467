// The GPU fused reduction: features computed, normalised and placed on
// the device slab by slab (features/cuda/FusedPlacementCuda.h) against the CPU fused path
// (FeatureBricks blocks + placeOutOfSample), with a device budget forced small so that many
// slabs (and both streams) are used. Same reference sample and fit (both come from the CPU
// statistics pass), coordinates within 1e-5 of their range. On a random 3-channel volume of
// mixed scalar types with NaN voxels, and on the real Colin27 brain (a 40-slice piece, so
// the CPU side stays a few seconds). Skips without a GPU.
#include "FusedRuns.h"
#include "BrainFeatures.h"
#include "RequireGpu.h"

#include "HalfCoordinates.h"

#include <gtest/gtest.h>

#include <cstdint>
#include <cstdio>
#include <vector>

namespace
{

namespace mt = mcv::testing;
using mcv::Device;

void expectSameCoordinates(const mt::FusedRun& cpu, const mt::FusedRun& gpu)
{
  EXPECT_EQ(cpu.result.deviceUsed, Device::CPU);
  EXPECT_EQ(gpu.result.deviceUsed, Device::GPU) << (gpu.result.warnings.empty() ? "" : gpu.result.warnings.back());
  EXPECT_EQ(gpu.result.referenceIndices, cpu.result.referenceIndices);
  EXPECT_EQ(gpu.result.usedColumns, cpu.result.usedColumns);
  const float range = mt::coordinateRange(cpu.result.coordinates);
  ASSERT_GT(range, 0.0f);
  const float diff = mt::maxDifference(gpu.result.coordinates, cpu.result.coordinates);
  std::printf("[ fused ] %zu voxels, %zu slabs of %d slices: max |GPU - CPU| = %.3g (range %.3g, ratio %.2g)\n",
    cpu.result.coordinates.size() / 3, gpu.stats.slabs, gpu.stats.slabSlices, diff, range, diff / range);
  EXPECT_LE(diff, 1e-5f * range);
}

TEST(FusedGPU, RandomVolumeManySlabsMatchesTheCpu)
{
  MCV_REQUIRE_GPU();
  const mt::TypedChannels t = mt::randomChannels({ 37, 29, 26 }, 11);
  const mcv::ReductionOptions cpuOptions = mt::isomapOptions(600, Device::CPU);
  const mcv::ReductionOptions gpuOptions = mt::isomapOptions(600, Device::GPU);
  const mt::FusedRun cpu = mt::runFused(t.views(), t.grid, cpuOptions, 0, 4 * 37 * 29 * 24 * sizeof(float));
  const std::size_t budget = mt::budgetForSlices(t.grid, 3, 24, 600, 3, 3);
  const mt::FusedRun gpu = mt::runFused(t.views(), t.grid, gpuOptions, budget);
  EXPECT_GE(gpu.stats.slabSlices, 3);
  EXPECT_LE(gpu.stats.slabSlices, 5); // the references are fewer than the budget assumed
  EXPECT_GE(gpu.stats.slabs, 5u);
  EXPECT_LE(gpu.stats.deviceBytes, budget);
  expectSameCoordinates(cpu, gpu);
  // Only channels went up (with their ghost slices) besides the references, only
  // coordinates came down.
  const std::size_t voxels = t.grid.voxelCount();
  EXPECT_EQ(gpu.stats.bytesFromDevice, voxels * 3 * sizeof(float));
  EXPECT_GE(gpu.stats.bytesToDevice, voxels * 3 * sizeof(float));
  EXPECT_LT(gpu.stats.bytesToDevice, voxels * 3 * sizeof(float) * 2);
  // The whole volume in one slab (the default budget) gives the same coordinates.
  const mt::FusedRun whole = mt::runFused(t.views(), t.grid, gpuOptions, 0);
  EXPECT_EQ(whole.stats.slabs, 1u);
  EXPECT_EQ(whole.result.coordinates, gpu.result.coordinates);
}

TEST(FusedGPU, TooSmallABudgetFallsBackToTheCpuWithAWarning)
{
  MCV_REQUIRE_GPU();
  const mt::TypedChannels t = mt::randomChannels({ 20, 18, 12 }, 5);
  const mt::FusedRun cpu = mt::runFused(t.views(), t.grid, mt::isomapOptions(300, Device::CPU), 0);
  const mt::FusedRun gpu = mt::runFused(t.views(), t.grid, mt::isomapOptions(300, Device::GPU), 1024);
  EXPECT_EQ(gpu.result.deviceUsed, Device::CPU);
  int said = 0;
  for (const std::string& w : gpu.result.warnings)
    said += (w.find("GPU fused placement failed after 0 of") != std::string::npos &&
      w.find("MiB of device memory") != std::string::npos && w.find("CPU") != std::string::npos);
  EXPECT_EQ(said, 1);
  EXPECT_EQ(gpu.result.coordinates, cpu.result.coordinates);
}

TEST(FusedGPU, Float16OutputIsTheFloatOutputRounded)
{
  // float16 coordinates: each slab's pinned staging buffer is rounded into the
  // output, so the result is the float32 GPU output rounded, bit for bit; the same from the
  // GPU placement of a Features matrix (placed a chunk of rows at a time).
  MCV_REQUIRE_GPU();
  const mt::TypedChannels t = mt::randomChannels({ 37, 29, 26 }, 11);
  const std::size_t budget = mt::budgetForSlices(t.grid, 3, 24, 600, 3, 3);
  const mt::FusedRun f32 = mt::runFused(t.views(), t.grid, mt::isomapOptions(600, Device::GPU), budget);
  std::vector<std::uint16_t> halves(t.grid.voxelCount() * 3, 0xFFFF);
  mcv::ReductionOptions o = mt::isomapOptions(600, Device::GPU);
  o.coordinatesHalfOutput = halves.data();
  const mt::FusedRun f16 = mt::runFused(t.views(), t.grid, o, budget);
  EXPECT_EQ(f16.result.deviceUsed, Device::GPU);
  EXPECT_GE(f16.stats.slabs, 5u);
  EXPECT_TRUE(f16.result.coordinates.empty());
  std::vector<std::uint16_t> rounded(f32.result.coordinates.size());
  mcv::floatsToHalves(f32.result.coordinates.data(), rounded.size(), rounded.data());
  EXPECT_EQ(halves, rounded);

  const std::size_t n = t.grid.voxelCount();
  std::vector<float> rows(n * 4);
  for (std::size_t i = 0; i < rows.size(); ++i)
    rows[i] = static_cast<float>((i * 7919) % 1013) / 101.0f + static_cast<float>(i % 4);
  mcv::ReductionOptions m = mt::isomapOptions(600, Device::GPU);
  const mcv::ReductionResult m32 = mcv::reduceDimension(mcv::FeatureMatrix{ rows.data(), n, 4 }, m);
  ASSERT_TRUE(m32.ok()) << m32.error;
  EXPECT_EQ(m32.deviceUsed, Device::GPU);
  std::vector<std::uint16_t> matrixHalves(n * 3, 0xFFFF);
  m.coordinatesHalfOutput = matrixHalves.data();
  const mcv::ReductionResult m16 = mcv::reduceDimension(mcv::FeatureMatrix{ rows.data(), n, 4 }, m);
  ASSERT_TRUE(m16.ok()) << m16.error;
  EXPECT_EQ(m16.deviceUsed, Device::GPU);
  rounded.resize(m32.coordinates.size());
  mcv::floatsToHalves(m32.coordinates.data(), rounded.size(), rounded.data());
  EXPECT_EQ(matrixHalves, rounded);
}

TEST(FusedGPU, RealBrainManySlabsMatchesTheCpu)
{
  MCV_REQUIRE_GPU();
  if (!mt::haveBrain())
    GTEST_SKIP() << "brain volumes not in " << mt::dataDir() << " (scripts/fetch-data.sh)";
  const mt::BrainPieceChannels brain = mt::loadBrainPiece();
  const mt::FusedRun cpu =
    mt::runFused(brain.views(), brain.grid, mt::isomapOptions(2000, Device::CPU), 0);
  const std::size_t budget = mt::budgetForSlices(brain.grid, 3, 24, 2000, 3, 4);
  const mt::FusedRun gpu =
    mt::runFused(brain.views(), brain.grid, mt::isomapOptions(2000, Device::GPU), budget);
  EXPECT_GE(gpu.stats.slabs, 8u);
  expectSameCoordinates(cpu, gpu);
}

} // namespace
