// Shared by the fused-path GPU tests (TestFusedGPU.cpp, TestGpuFaults.cpp): channels held
// in their own scalar types, one fused reduction (FeatureBricks -> reduceDimension) on a
// chosen device with a chosen device budget, and the coordinate comparison.
#pragma once

#include "BrainFeatures.h"
#include "DimensionReduction.h"
#include "FeatureBricks.h"
#include "TestVolumes.h"
#include "cuda/FusedPlacementCuda.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <vector>

namespace mcv
{
namespace testing
{

// The piece of the real brain that the fused tests compare the CPU with (brainPiece, float
// channels as the loader gives them) and its grid.
struct BrainPieceChannels
{
  std::vector<Volume> volumes;
  ImageGrid grid;

  std::vector<ChannelView> views() const { return floatViews(this->volumes); }
};

inline BrainPieceChannels loadBrainPiece()
{
  BrainPieceChannels b;
  b.volumes = brainPiece();
  b.grid = b.volumes[0].grid;
  return b;
}

// Channels in the types a user's volume has; views() for FeatureBricks.
struct TypedChannels
{
  ImageGrid grid;
  std::vector<std::vector<std::uint8_t>> u8;
  std::vector<std::vector<std::uint16_t>> u16;
  std::vector<std::vector<float>> f32;
  std::vector<ChannelView> list;

  std::vector<ChannelView> views() const { return list; }
};

// A random 3-channel volume: uint8, uint16 and float32 channels of spatially smooth-ish
// random data (so features vary), the float one with a few NaN voxels (the guarded paths).
inline TypedChannels randomChannels(std::array<int, 3> dims, std::uint64_t seed)
{
  TypedChannels t;
  t.grid = makeGrid(dims[0], dims[1], dims[2], { 1.0, 1.2, 2.0 });
  const Volume a = randomVolume(t.grid, seed), b = randomVolume(t.grid, seed + 1), c = randomVolume(t.grid, seed + 2);
  const std::size_t n = t.grid.voxelCount();
  t.u8.emplace_back(n);
  t.u16.emplace_back(n);
  t.f32.emplace_back(n);
  for (std::size_t v = 0; v < n; ++v)
  {
    t.u8[0][v] = static_cast<std::uint8_t>(a.values[v] * 255.0f + 0.5f);
    t.u16[0][v] = static_cast<std::uint16_t>(b.values[v] * 4000.0f + 0.5f * a.values[v] * 4000.0f);
    t.f32[0][v] = c.values[v] * 3.0f - 1.0f;
  }
  for (std::size_t v = n / 7; v < n; v += n / 5)
  {
    t.f32[0][v] = std::nanf("");
  }
  ChannelView cv;
  cv.data = t.u8[0].data();
  cv.type = ScalarType::UInt8;
  t.list.push_back(cv);
  cv.data = t.u16[0].data();
  cv.type = ScalarType::UInt16;
  t.list.push_back(cv);
  cv.data = t.f32[0].data();
  cv.type = ScalarType::Float32;
  t.list.push_back(cv);
  return t;
}

// The statistics pass on `device` (the CPU by default: the reference the GPU is compared with).
inline FeatureOptions fused24D(Device device = Device::CPU)
{
  FeatureOptions o;
  o.preset = FeaturePreset::TwentyFourD;
  o.device = device;
  return o;
}

inline ReductionOptions isomapOptions(std::size_t sample, Device device)
{
  ReductionOptions ro;
  ro.method = ReductionMethod::Isomap;
  ro.referenceSampleSize = sample;
  ro.numberOfNeighbors = 10;
  ro.numberOfLandmarks = 150;
  ro.device = device;
  ro.trustworthinessSample = 0;
  return ro;
}

// The device bytes that give slabs of `slices` slices for this volume and reduction (an
// upper bound on the references: all `sample` of them, every feature used).
inline std::size_t budgetForSlices(const ImageGrid& grid, int channels, int cols, std::size_t sample, int d, int slices)
{
  cuda::FusedPlacementSetup s;
  s.grid = grid;
  s.channels = channels;
  s.cols = cols;
  s.references.M = sample;
  s.references.D = cols;
  s.references.d = d;
  return cuda::fusedPlacementBytes(s, slices);
}

struct FusedRun
{
  ReductionResult result;
  FeatureBricks::DeviceStats stats;
  FeatureResult prepared;
  int passesOnDevice = 0; // statistics, column sums, strata
};

// One fused reduction; deviceBytes 0: the default budget. statisticsDevice: where
// FeatureBricks::prepare runs (the column check and strata run where the reduction does).
inline FusedRun runFused(const std::vector<ChannelView>& channels, const ImageGrid& grid, const ReductionOptions& ro,
  std::size_t deviceBytes, std::size_t cpuSlabBytes = FeatureBricks::kDefaultSlabBytes,
  Device statisticsDevice = Device::CPU)
{
  FusedRun run;
  FeatureBricks bricks(channels, grid, fused24D(statisticsDevice), cpuSlabBytes);
  bricks.setDeviceBytes(deviceBytes);
  EXPECT_TRUE(bricks.prepare(run.prepared)) << run.prepared.error;
  run.result = reduceDimension(bricks, ro);
  EXPECT_TRUE(run.result.ok()) << run.result.error;
  run.stats = bricks.deviceStats();
  run.passesOnDevice = bricks.passesOnDevice();
  return run;
}

inline float coordinateRange(const std::vector<float>& c)
{
  if (c.empty())
    return 0.0f;
  const auto mm = std::minmax_element(c.begin(), c.end());
  return *mm.second - *mm.first;
}

inline float maxDifference(const std::vector<float>& a, const std::vector<float>& b)
{
  float m = a.size() == b.size() ? 0.0f : INFINITY;
  for (std::size_t i = 0; i < std::min(a.size(), b.size()); ++i)
    m = std::max(m, std::abs(a[i] - b[i]));
  return m;
}

} // namespace testing
} // namespace mcv
