// Scalars -> opacity for every supported scalar type, NaN/Inf handling, multichannel max.
#include "OpacityFunction.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <limits>
#include <vector>

namespace
{

TEST(OpacityFunction, PiecewiseLinearEvaluation)
{
  mcv::OpacityFunction f;
  f.x = { 0, 10, 20 };
  f.alpha = { 0, 1, 0.5 };
  EXPECT_DOUBLE_EQ(f.evaluate(-5), 0.0);
  EXPECT_DOUBLE_EQ(f.evaluate(5), 0.5);
  EXPECT_DOUBLE_EQ(f.evaluate(10), 1.0);
  EXPECT_DOUBLE_EQ(f.evaluate(15), 0.75);
  EXPECT_DOUBLE_EQ(f.evaluate(100), 0.5);
  const mcv::OpacityFunction ramp = mcv::OpacityFunction::ramp(2, 6);
  EXPECT_DOUBLE_EQ(ramp.evaluate(3), 0.25);
  const mcv::OpacityFunction constant = mcv::OpacityFunction::ramp(4, 4);
  EXPECT_DOUBLE_EQ(constant.evaluate(4), 1.0);
  EXPECT_DOUBLE_EQ(constant.evaluate(3), 0.0);
}

template <typename T>
void checkType(mcv::ScalarType type)
{
  // Two interleaved components; component 1 holds the ramp 0, 10, ..., 90.
  std::vector<T> data(20);
  for (int v = 0; v < 10; ++v)
  {
    data[2 * v] = static_cast<T>(1);
    data[2 * v + 1] = static_cast<T>(10 * v);
  }
  mcv::ChannelView channel{ data.data(), type, 2, 1 };
  const auto range = mcv::finiteRange(channel, 10);
  EXPECT_DOUBLE_EQ(range.first, 0.0);
  EXPECT_DOUBLE_EQ(range.second, 90.0);
  std::vector<float> opacity(10, 0.f);
  EXPECT_EQ(mcv::accumulateOpacity(channel, 10, mcv::OpacityFunction::ramp(0, 90), opacity.data()), 0u);
  for (int v = 0; v < 10; ++v)
  {
    EXPECT_NEAR(opacity[v], v / 9.0, 1e-6) << "voxel " << v;
  }
}

TEST(OpacityFunction, EveryScalarType)
{
  checkType<std::int8_t>(mcv::ScalarType::Int8);
  checkType<std::uint8_t>(mcv::ScalarType::UInt8);
  checkType<std::int16_t>(mcv::ScalarType::Int16);
  checkType<std::uint16_t>(mcv::ScalarType::UInt16);
  checkType<std::int32_t>(mcv::ScalarType::Int32);
  checkType<std::uint32_t>(mcv::ScalarType::UInt32);
  checkType<float>(mcv::ScalarType::Float32);
  checkType<double>(mcv::ScalarType::Float64);
}

TEST(OpacityFunction, NegativeSixteenBitValuesUseTheTable)
{
  std::vector<std::int16_t> data = { -1000, 0, 1000 };
  std::vector<float> opacity(3, 0.f);
  mcv::accumulateOpacity({ data.data(), mcv::ScalarType::Int16, 1, 0 }, 3,
    mcv::OpacityFunction::ramp(-1000, 1000), opacity.data());
  EXPECT_FLOAT_EQ(opacity[0], 0.f);
  EXPECT_FLOAT_EQ(opacity[1], 0.5f);
  EXPECT_FLOAT_EQ(opacity[2], 1.f);
}

TEST(OpacityFunction, NonFiniteVoxelsAreTransparentAndCounted)
{
  const float nan = std::numeric_limits<float>::quiet_NaN(), inf = std::numeric_limits<float>::infinity();
  std::vector<float> data = { 0.f, nan, 1.f, inf, -inf, 0.5f };
  const mcv::ChannelView channel{ data.data(), mcv::ScalarType::Float32, 1, 0 };
  const auto range = mcv::finiteRange(channel, data.size());
  EXPECT_FLOAT_EQ(range.first, 0.f);
  EXPECT_FLOAT_EQ(range.second, 1.f);
  std::vector<float> opacity(data.size(), 0.f);
  EXPECT_EQ(mcv::accumulateOpacity(channel, data.size(), mcv::OpacityFunction::ramp(0, 1), opacity.data()), 3u);
  EXPECT_FLOAT_EQ(opacity[1], 0.f);
  EXPECT_FLOAT_EQ(opacity[3], 0.f);
  EXPECT_FLOAT_EQ(opacity[5], 0.5f);
}

TEST(OpacityFunction, NonFiniteVoxelsAreCountedOncePerOwnedVoxel)
{
  // A 4 x 3 x 2 block split in two along x: owned columns 0-1 by the first process, 2-3 by the
  // second; each block here is the whole 4 x 3 x 2 (the other's part acts as a ghost layer).
  const float nan = std::numeric_limits<float>::quiet_NaN(), inf = std::numeric_limits<float>::infinity();
  mcv::ImageGrid grid;
  grid.dims = { 4, 3, 2 };
  auto at = [](int i, int j, int k) { return static_cast<std::size_t>(i + 4 * (j + 3 * k)); };
  // Two interleaved float components and an integer channel (which never counts).
  std::vector<double> two(2 * grid.voxelCount(), 1.0);
  two[2 * at(0, 0, 0)] = nan;     // channel 0 only
  two[2 * at(1, 2, 1)] = inf;     // both channels: one voxel
  two[2 * at(1, 2, 1) + 1] = nan;
  two[2 * at(3, 1, 0) + 1] = -inf; // channel 1, in the second process's part
  std::vector<std::int16_t> labels(grid.voxelCount(), 7);
  const std::vector<mcv::ChannelView> channels = { { two.data(), mcv::ScalarType::Float64, 2, 0 },
    { two.data(), mcv::ScalarType::Float64, 2, 1 }, { labels.data(), mcv::ScalarType::Int16, 1, 0 } };

  mcv::GridPiece whole = mcv::GridPiece::whole(grid);
  EXPECT_EQ(mcv::countNonFiniteVoxels(channels, grid, whole), 3u);
  mcv::GridPiece left = whole, right = whole;
  left.ownedHi[0] = 1;
  right.ownedLo[0] = 2;
  const std::size_t first = mcv::countNonFiniteVoxels(channels, grid, left);
  const std::size_t second = mcv::countNonFiniteVoxels(channels, grid, right);
  EXPECT_EQ(first, 2u);
  EXPECT_EQ(second, 1u);
  EXPECT_EQ(first + second, 3u) << "the split counts every voxel once";
  EXPECT_EQ(mcv::countNonFiniteVoxels({ channels[2] }, grid, whole), 0u);
}

TEST(OpacityFunction, SeveralChannelsTakeTheMaximum)
{
  std::vector<std::uint8_t> a = { 0, 255, 100 };
  std::vector<double> b = { 1.0, 0.0, 0.1 };
  std::vector<float> opacity(3, 0.f);
  mcv::accumulateOpacity({ a.data(), mcv::ScalarType::UInt8, 1, 0 }, 3, mcv::OpacityFunction::ramp(0, 255), opacity.data());
  mcv::accumulateOpacity({ b.data(), mcv::ScalarType::Float64, 1, 0 }, 3, mcv::OpacityFunction::ramp(0, 1), opacity.data());
  EXPECT_FLOAT_EQ(opacity[0], 1.f);
  EXPECT_FLOAT_EQ(opacity[1], 1.f);
  EXPECT_NEAR(opacity[2], 100 / 255.0, 1e-6);
}

} // namespace
