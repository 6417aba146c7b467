// The fused reduction's passes over the whole volume on the GPU (features/cuda/FusedPassesCuda.h)
// against the CPU: the statistics of the normalisation agree to rounding (the sums are added
// in another order); the column check's exact sums and extremes and the sample's strata are
// the CPU's, bit for bit; the whole chain with every pass on the GPU gives the CPU's reference
// sample and coordinates within 1e-5 of their range; the pinned staging handed from pass to
// pass keeps its size. Random 3-channel volumes of mixed scalar
// types with NaN voxels and the real Colin27 brain (a 40-slice piece). Skips without a GPU.
#include "FusedRuns.h"
#include "BrainFeatures.h"
#include "RequireGpu.h"
#include "cuda/FusedPlacementCuda.h"

#include <cuda_runtime.h>

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <random>
#include <vector>

namespace
{

namespace mt = mcv::testing;
using mcv::Device;

double relativeDifference(const std::vector<double>& a, const std::vector<double>& b)
{
  double worst = a.size() == b.size() ? 0.0 : INFINITY;
  for (std::size_t i = 0; i < std::min(a.size(), b.size()); ++i)
  {
    const double scale = std::max(std::abs(a[i]), std::abs(b[i]));
    worst = std::max(worst, scale > 0 ? std::abs(a[i] - b[i]) / scale : 0.0);
  }
  return worst;
}

// Slabs of a few slices on the GPU (a budget that fits three slabs of the placement), the
// default CPU slabs: the two sides cut the volume differently.
void expectSameStatistics(const std::vector<mcv::ChannelView>& views, const mcv::ImageGrid& grid)
{
  mcv::FeatureBricks cpu(views, grid, mt::fused24D(Device::CPU));
  mcv::FeatureBricks gpu(views, grid, mt::fused24D(Device::GPU));
  gpu.setDeviceBytes(mt::budgetForSlices(grid, 3, 24, 0, 3, 3));
  mcv::FeatureResult c, g;
  ASSERT_TRUE(cpu.prepare(c)) << c.error;
  ASSERT_TRUE(gpu.prepare(g)) << g.error;
  EXPECT_EQ(c.deviceUsed, Device::CPU);
  EXPECT_EQ(g.deviceUsed, Device::GPU);
  EXPECT_EQ(gpu.passesOnDevice(), 1);
  const double offsets = relativeDifference(c.columnOffset, g.columnOffset);
  const double scales = relativeDifference(c.columnScale, g.columnScale);
  std::printf("[ passes ] statistics of %zu voxels: offsets and scales differ by %.2g and %.2g (relative)\n",
    grid.voxelCount(), offsets, scales);
  // Sums of ~1e6 doubles in two orders: ~1e-13 apart on the brain piece.
  EXPECT_LE(offsets, 1e-10);
  EXPECT_LE(scales, 1e-10);
  EXPECT_EQ(g.nonFiniteVoxels, c.nonFiniteVoxels);
  EXPECT_EQ(g.constantColumns, c.constantColumns);
  EXPECT_EQ(g.warnings, c.warnings);
}

TEST(FusedPassesGPU, StatisticsAgreeWithTheCpu)
{
  MCV_REQUIRE_GPU();
  const mt::TypedChannels t = mt::randomChannels({ 37, 29, 26 }, 11); // NaN voxels in one channel
  expectSameStatistics(t.views(), t.grid);
  if (!mt::haveBrain())
    GTEST_SKIP() << "brain volumes not in " << mt::dataDir() << " (scripts/fetch-data.sh)";
  const mt::BrainPieceChannels brain = mt::loadBrainPiece();
  expectSameStatistics(brain.views(), brain.grid);
}

// The reference of the column check: DimensionReduction.cpp's exact sums, from the CPU blocks.
struct ExactSums
{
  std::vector<std::int64_t> bins;
  std::vector<double> minimum, maximum;
};

ExactSums cpuColumnSums(mcv::FeatureBricks& bricks)
{
  const int F = bricks.cols();
  ExactSums s{ std::vector<std::int64_t>(static_cast<std::size_t>(F) * 256, 0),
    std::vector<double>(static_cast<std::size_t>(F), INFINITY), std::vector<double>(static_cast<std::size_t>(F), -INFINITY) };
  for (std::size_t b = 0; b < bricks.blockCount(); ++b)
  {
    const float* rows = bricks.block(b);
    const std::size_t n = bricks.blockBegin(b + 1) - bricks.blockBegin(b);
    for (std::size_t i = 0; i < n * static_cast<std::size_t>(F); ++i)
    {
      const float v = rows[i];
      const std::size_t c = i % static_cast<std::size_t>(F);
      std::uint32_t bits;
      std::memcpy(&bits, &v, sizeof bits);
      const int e = static_cast<int>((bits >> 23) & 0xFFu);
      const std::int64_t m = static_cast<std::int64_t>((bits & 0x7FFFFFu) | (e != 0 ? 0x800000u : 0u));
      s.bins[c * 256 + static_cast<std::size_t>(std::max(e, 1))] += (bits >> 31) != 0 ? -m : m;
      s.minimum[c] = std::min<double>(s.minimum[c], v);
      s.maximum[c] = std::max<double>(s.maximum[c], v);
    }
  }
  return s;
}

// The reference of the strata: Sampler::norm and std::upper_bound over the CPU blocks.
std::vector<std::uint8_t> cpuStrata(mcv::FeatureBricks& bricks, const mcv::DeviceStrata& r)
{
  const std::size_t F = static_cast<std::size_t>(bricks.cols());
  std::vector<std::uint8_t> strata(bricks.rows(), r.notEligible);
  for (std::size_t b = 0; b < bricks.blockCount(); ++b)
  {
    const float* rows = bricks.block(b);
    for (std::size_t row = bricks.blockBegin(b); row < bricks.blockBegin(b + 1); ++row)
    {
      if (r.eligible && r.eligible[row] == 0)
        continue;
      const float* x = rows + (row - bricks.blockBegin(b)) * F;
      double s = 0;
      for (std::size_t k = 0; k < r.columns.size(); ++k)
      {
        const double v = x[r.columns[k]] - (r.center.empty() ? 0.0 : r.center[k]);
        s += v * v;
      }
      const float norm = static_cast<float>(std::sqrt(s));
      strata[row] = static_cast<std::uint8_t>(std::upper_bound(r.edges.begin(), r.edges.end(), norm) - r.edges.begin());
    }
  }
  return strata;
}

void expectSameColumnSumsAndStrata(const std::vector<mcv::ChannelView>& views, const mcv::ImageGrid& grid)
{
  mcv::FeatureBricks bricks(views, grid, mt::fused24D(Device::CPU), 3 * static_cast<std::size_t>(grid.dims[0]) *
      static_cast<std::size_t>(grid.dims[1]) * 24 * sizeof(float));
  bricks.setDeviceBytes(mt::budgetForSlices(grid, 3, 24, 0, 3, 4));
  mcv::FeatureResult prepared;
  ASSERT_TRUE(bricks.prepare(prepared)) << prepared.error;

  const mcv::DeviceColumnSums gpu = bricks.columnSumsOnDevice({});
  ASSERT_TRUE(gpu.attempted);
  ASSERT_TRUE(gpu.error.empty()) << gpu.error;
  const ExactSums cpu = cpuColumnSums(bricks);
  EXPECT_EQ(gpu.bins, cpu.bins);
  EXPECT_EQ(gpu.minimum, cpu.minimum);
  EXPECT_EQ(gpu.maximum, cpu.maximum);
  EXPECT_EQ(gpu.nonFinite, 0.0);
  EXPECT_TRUE(std::isinf(gpu.firstBad));

  // Strata of a subset of the columns, centred, among edges at spread quantiles of the norms;
  // a random half of the voxels eligible.
  mcv::DeviceStrata request;
  request.columns = { 0, 2, 3, 5, 7, 11, 13, 17, 19, 23 };
  for (std::size_t k = 0; k < request.columns.size(); ++k)
    request.center.push_back(0.01 * static_cast<double>(k) - 0.03);
  std::vector<std::uint8_t> eligible(bricks.rows());
  std::mt19937 random(7);
  for (std::uint8_t& e : eligible)
    e = static_cast<std::uint8_t>(random() & 1u);
  request.eligible = eligible.data();
  request.edges = { 0.5f, 1.0f, 1.5f, 2.0f, 3.0f, 4.5f, 7.0f };
  std::vector<std::uint8_t> onDevice(bricks.rows(), 0x7E);
  request.stratum = onDevice.data();
  const mcv::DevicePassReport report = bricks.strataOnDevice(request);
  ASSERT_TRUE(report.attempted);
  ASSERT_TRUE(report.error.empty()) << report.error;
  const std::vector<std::uint8_t> expected = cpuStrata(bricks, request);
  EXPECT_EQ(onDevice, expected);
  std::vector<std::size_t> perStratum(256, 0);
  for (std::uint8_t s : expected)
    ++perStratum[s];
  std::size_t used = 0;
  for (std::size_t s = 0; s <= request.edges.size(); ++s)
    used += perStratum[s] > 0;
  std::printf("[ passes ] %zu voxels: column sums and strata equal the CPU's; %zu of %zu strata hold voxels\n",
    bricks.rows(), used, request.edges.size() + 1);
  EXPECT_GE(used, 4u); // the edges split the volume, so the comparison means something
  EXPECT_EQ(bricks.passesOnDevice(), 2);
}

TEST(FusedPassesGPU, ColumnSumsAndStrataAreTheCpus)
{
  MCV_REQUIRE_GPU();
  const mt::TypedChannels t = mt::randomChannels({ 37, 29, 26 }, 11);
  expectSameColumnSumsAndStrata(t.views(), t.grid);
  if (!mt::haveBrain())
    GTEST_SKIP() << "brain volumes not in " << mt::dataDir() << " (scripts/fetch-data.sh)";
  const mt::BrainPieceChannels brain = mt::loadBrainPiece();
  expectSameColumnSumsAndStrata(brain.views(), brain.grid);
}

// Every pass on the GPU against every pass on the CPU.
void expectSameChain(const std::vector<mcv::ChannelView>& views, const mcv::ImageGrid& grid, std::size_t sample)
{
  const mt::FusedRun cpu = mt::runFused(views, grid, mt::isomapOptions(sample, Device::CPU), 0);
  const mt::FusedRun gpu = mt::runFused(views, grid, mt::isomapOptions(sample, Device::GPU),
    mt::budgetForSlices(grid, 3, 24, sample, 3, 4), mcv::FeatureBricks::kDefaultSlabBytes, Device::GPU);
  EXPECT_EQ(cpu.passesOnDevice, 0);
  EXPECT_EQ(gpu.passesOnDevice, 3);
  EXPECT_EQ(gpu.result.deviceUsed, Device::GPU);
  EXPECT_EQ(gpu.result.referenceIndices, cpu.result.referenceIndices);
  EXPECT_EQ(gpu.result.usedColumns, cpu.result.usedColumns);
  EXPECT_EQ(gpu.result.warnings, cpu.result.warnings);
  const float range = mt::coordinateRange(cpu.result.coordinates);
  const float diff = mt::maxDifference(gpu.result.coordinates, cpu.result.coordinates);
  std::printf("[ passes ] whole chain on %zu voxels, every pass on the GPU: max |GPU - CPU| = %.3g (range %.3g)\n",
    grid.voxelCount(), diff, range);
  EXPECT_LE(diff, 1e-5f * range);
}

TEST(FusedPassesGPU, WholeChainOnTheGpuMatchesTheCpu)
{
  MCV_REQUIRE_GPU();
  const mt::TypedChannels t = mt::randomChannels({ 37, 29, 26 }, 11);
  expectSameChain(t.views(), t.grid, 600);
  if (!mt::haveBrain())
    GTEST_SKIP() << "brain volumes not in " << mt::dataDir() << " (scripts/fetch-data.sh)";
  const mt::BrainPieceChannels brain = mt::loadBrainPiece();
  expectSameChain(brain.views(), brain.grid, 2000);
}

// The channels kept on the device from the statistics pass to the placement (a budget with
// room for them) against every pass streaming them up again (a budget without): the
// placement uploads no channel in the first, the same sample and coordinates (to the
// rounding of the statistics, whose slabs differ) in both.
TEST(FusedPassesGPU, ResidentChannelsGiveTheStreamedResult)
{
  MCV_REQUIRE_GPU();
  if (!mt::haveBrain())
    GTEST_SKIP() << "brain volumes not in " << mt::dataDir() << " (scripts/fetch-data.sh)";
  const mt::BrainPieceChannels brain = mt::loadBrainPiece();
  const std::vector<mcv::ChannelView> views = brain.views();
  const mcv::ImageGrid& grid = brain.grid;
  const std::size_t channelBytes = grid.voxelCount() * 3 * sizeof(float);
  // The thickest slabs whose budget leaves no room for the channels (they fit in half of it).
  int slices = 4;
  while (slices > 1 && mt::budgetForSlices(grid, 3, 24, 2000, 3, slices) >= 2 * channelBytes)
    --slices;
  const std::size_t streamedBudget = mt::budgetForSlices(grid, 3, 24, 2000, 3, slices);
  ASSERT_LT(streamedBudget, 2 * channelBytes);
  const std::size_t residentBudget = streamedBudget + 2 * channelBytes;
  const mcv::ReductionOptions o = mt::isomapOptions(2000, Device::GPU);
  const mt::FusedRun streamed =
    mt::runFused(views, grid, o, streamedBudget, mcv::FeatureBricks::kDefaultSlabBytes, Device::GPU);
  const mt::FusedRun resident =
    mt::runFused(views, grid, o, residentBudget, mcv::FeatureBricks::kDefaultSlabBytes, Device::GPU);
  EXPECT_EQ(streamed.passesOnDevice, 3);
  EXPECT_EQ(resident.passesOnDevice, 3);
  EXPECT_EQ(resident.result.deviceUsed, Device::GPU);
  std::printf("[ passes ] placement bytes up: %zu streamed, %zu with the channels resident (channels: %zu)\n",
    streamed.stats.bytesToDevice, resident.stats.bytesToDevice, channelBytes);
  EXPECT_GE(streamed.stats.bytesToDevice, channelBytes);
  EXPECT_LT(resident.stats.bytesToDevice, channelBytes / 4); // the references only
  EXPECT_LE(resident.stats.deviceBytes, residentBudget);
  EXPECT_EQ(resident.result.referenceIndices, streamed.result.referenceIndices);
  const float range = mt::coordinateRange(streamed.result.coordinates);
  EXPECT_LE(mt::maxDifference(resident.result.coordinates, streamed.result.coordinates), 1e-5f * range);
}

} // namespace

// The pinned staging the passes over a resident volume hand on to each other keeps its whole
// size: the strata pass borrows the statistics pass's channel staging for its one byte per
// voxel, and the placement must then still find it large enough for its coordinates (it
// pinned them again when the buffer came back recorded at the strata's size).
TEST(FusedPassesGPU, KeptPinnedBuffersKeepTheirCapacity)
{
  MCV_REQUIRE_GPU();
  mcv::cuda::ResidentChannels resident;
  void* staging = nullptr;
  ASSERT_EQ(cudaMallocHost(&staging, 1000), cudaSuccess);
  resident.keepPinned(staging, 1000); // freed with `resident`
  std::size_t capacity = 0;
  EXPECT_EQ(resident.takePinned(2000, &capacity), nullptr);
  ASSERT_EQ(resident.takePinned(10, &capacity), staging); // the strata's few bytes
  EXPECT_EQ(capacity, 1000u);
  resident.keepPinned(staging, capacity);
  ASSERT_EQ(resident.takePinned(900, &capacity), staging); // then the coordinates
  EXPECT_EQ(capacity, 1000u);
  resident.keepPinned(staging, capacity);
}
