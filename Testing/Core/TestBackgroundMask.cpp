// The background mask (BackgroundMask.h): a voxel is background when every channel is at or
// below min + threshold * (max - min) of that channel. Known answers on small volumes.
#include "BackgroundMask.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <limits>
#include <vector>

namespace
{

template <class T>
mcv::ChannelView view(const std::vector<T>& values, mcv::ScalarType type, int components = 1, int component = 0)
{
  mcv::ChannelView v;
  v.data = values.data();
  v.type = type;
  v.numComponents = components;
  v.component = component;
  return v;
}

mcv::ImageGrid grid(int nx, int ny, int nz)
{
  mcv::ImageGrid g;
  g.dims = { nx, ny, nz };
  return g;
}

std::vector<unsigned char> mask(const std::vector<mcv::ChannelView>& channels, const mcv::ImageGrid& g,
  double threshold, mcv::BackgroundMaskResult& result)
{
  mcv::BackgroundMaskOptions options;
  options.threshold = threshold;
  std::vector<unsigned char> out(g.voxelCount(), 7);
  EXPECT_TRUE(mcv::computeBackgroundMask(channels, g, options, out.data(), result)) << result.error;
  return out;
}

} // namespace

TEST(BackgroundMask, ZeroVoxelsAreBackgroundAtTheDefaultThreshold)
{
  // An MRI-like volume: a zero field with a few non-zero voxels.
  const std::vector<std::uint16_t> t1 = { 0, 0, 0, 5, 0, 120, 0, 0, 0, 1, 0, 0 };
  mcv::BackgroundMaskResult r;
  const std::vector<unsigned char> m = mask({ view(t1, mcv::ScalarType::UInt16) }, grid(3, 2, 2), 0.0, r);
  const std::vector<unsigned char> expected = { 0, 0, 0, 1, 0, 1, 0, 0, 0, 1, 0, 0 };
  EXPECT_EQ(m, expected);
  EXPECT_EQ(r.voxels, 12u);
  EXPECT_EQ(r.backgroundVoxels, 9u);
  EXPECT_DOUBLE_EQ(r.channelMin[0], 0.0);
  EXPECT_DOUBLE_EQ(r.channelMax[0], 120.0);
  EXPECT_TRUE(r.warnings.empty());
}

TEST(BackgroundMask, ThresholdIsAFractionOfTheRangeAboveTheMinimum)
{
  // Range [10, 110]: threshold 0.25 cuts at 35 (inclusive), 0.5 at 60.
  const std::vector<float> v = { 10, 20, 35, 36, 60, 61, 110, 10 };
  const auto channels = std::vector<mcv::ChannelView>{ view(v, mcv::ScalarType::Float32) };
  mcv::BackgroundMaskResult r;
  EXPECT_EQ(mask(channels, grid(8, 1, 1), 0.25, r), (std::vector<unsigned char>{ 0, 0, 0, 1, 1, 1, 1, 0 }));
  EXPECT_DOUBLE_EQ(r.cut[0], 35.0);
  EXPECT_EQ(r.backgroundVoxels, 4u);
  EXPECT_EQ(mask(channels, grid(8, 1, 1), 0.5, r), (std::vector<unsigned char>{ 0, 0, 0, 0, 0, 1, 1, 0 }));
  EXPECT_EQ(mask(channels, grid(8, 1, 1), 0.0, r), (std::vector<unsigned char>{ 0, 1, 1, 1, 1, 1, 1, 0 }));
  EXPECT_DOUBLE_EQ(mcv::backgroundCut(-4.0, 6.0, 0.1), -3.0);
}

TEST(BackgroundMask, ForegroundWhenAnyChannelIsAboveItsCut)
{
  // Three channels of one interleaved array plus a signed one: a voxel where only one
  // channel is non-zero is foreground; background only where all are at their minimum.
  const std::vector<std::int16_t> rgb = { 0, 0, 0, /**/ 0, 9, 0, /**/ 0, 0, 0, /**/ 3, 0, 0, /**/ 0, 0, 4 };
  const std::vector<double> signedChannel = { -2, -2, -2, -2, -2 };
  std::vector<mcv::ChannelView> channels;
  for (int c = 0; c < 3; ++c)
  {
    channels.push_back(view(rgb, mcv::ScalarType::Int16, 3, c));
  }
  channels.push_back(view(signedChannel, mcv::ScalarType::Float64)); // constant: empty everywhere
  mcv::BackgroundMaskResult r;
  EXPECT_EQ(mask(channels, grid(5, 1, 1), 0.0, r), (std::vector<unsigned char>{ 0, 1, 0, 1, 1 }));
  EXPECT_EQ(r.backgroundVoxels, 2u);
}

TEST(BackgroundMask, NonFiniteValuesCountAsEmpty)
{
  const float nan = std::numeric_limits<float>::quiet_NaN();
  const float inf = std::numeric_limits<float>::infinity();
  const std::vector<float> a = { 0, nan, 2, inf, 0 };
  const std::vector<float> b = { nan, nan, nan, nan, nan }; // no finite value at all
  mcv::BackgroundMaskResult r;
  EXPECT_EQ(mask({ view(a, mcv::ScalarType::Float32), view(b, mcv::ScalarType::Float32) }, grid(5, 1, 1), 0.0, r),
    (std::vector<unsigned char>{ 0, 0, 1, 0, 0 }));
  EXPECT_DOUBLE_EQ(r.channelMax[0], 2.0);
  EXPECT_TRUE(std::isnan(r.cut[1]));
}

TEST(BackgroundMask, AllBackgroundWarnsAndKeepsTheMask)
{
  const std::vector<std::uint8_t> flat(8, 3);
  mcv::BackgroundMaskResult r;
  EXPECT_EQ(mask({ view(flat, mcv::ScalarType::UInt8) }, grid(2, 2, 2), 0.0, r), std::vector<unsigned char>(8, 0));
  EXPECT_EQ(r.backgroundVoxels, 8u);
  ASSERT_EQ(r.warnings.size(), 1u);
  // A constant channel has no range to lower a threshold in: only MaskBackground helps.
  EXPECT_NE(r.warnings[0].find("every channel is constant"), std::string::npos) << r.warnings[0];
  EXPECT_NE(r.warnings[0].find("turn off MaskBackground"), std::string::npos) << r.warnings[0];
  EXPECT_EQ(r.warnings[0].find("lower BackgroundThreshold"), std::string::npos) << r.warnings[0];

  // A channel that varies, with the cut at its maximum: lowering the threshold helps.
  const std::vector<float> ramp = { 0, 1, 2, 3, 4, 5, 6, 7 };
  mcv::BackgroundMaskResult top;
  EXPECT_EQ(mask({ view(ramp, mcv::ScalarType::Float32) }, grid(2, 2, 2), 1.0, top), std::vector<unsigned char>(8, 0));
  ASSERT_EQ(top.warnings.size(), 1u);
  EXPECT_NE(top.warnings[0].find("lower BackgroundThreshold or turn off MaskBackground"), std::string::npos)
    << top.warnings[0];
}

TEST(BackgroundMask, BadArguments)
{
  const std::vector<float> v = { 0, 1 };
  std::vector<unsigned char> out(2);
  mcv::BackgroundMaskResult r;
  mcv::BackgroundMaskOptions o;
  EXPECT_FALSE(mcv::computeBackgroundMask({}, grid(2, 1, 1), o, out.data(), r));
  EXPECT_FALSE(r.error.empty());
  o.threshold = 1.5;
  EXPECT_FALSE(mcv::computeBackgroundMask({ view(v, mcv::ScalarType::Float32) }, grid(2, 1, 1), o, out.data(), r));
  EXPECT_NE(r.error.find("BackgroundThreshold"), std::string::npos);
  o.threshold = 0.0;
  EXPECT_FALSE(mcv::computeBackgroundMask({ view(v, mcv::ScalarType::Float32) }, grid(2, 1, 1), o, nullptr, r));
}
