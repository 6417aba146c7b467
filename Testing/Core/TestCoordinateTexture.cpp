// The 16-bit coordinate texture of per-sample classification: what the shader decodes
// (min + extent * t) must give back each coordinate within half a quantum, and voxels that
// are masked out or not finite must be flagged as not drawn.
#include "CoordinateTexture.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <limits>
#include <random>
#include <vector>

namespace
{
double decode(const mcv::CoordinateRange& range, int c, std::uint16_t t)
{
  return range.min[c] + range.Extent(c) * (t / 65535.0);
}
} // namespace

TEST(CoordinateTexture, RoundTripWithinHalfAQuantum)
{
  std::mt19937 rng(7);
  std::uniform_real_distribution<float> u(-3.f, 11.f);
  const std::size_t n = 5000;
  std::vector<float> x(3 * n);
  for (float& v : x)
  {
    v = u(rng);
  }
  mcv::CoordinateRange range;
  range.Add(x.data(), n, 3);
  std::vector<std::uint16_t> t(4 * n);
  EXPECT_EQ(mcv::quantizeCoordinates(x.data(), n, 3, nullptr, range, t.data()), n);
  for (std::size_t i = 0; i < n; ++i)
  {
    for (int c = 0; c < 3; ++c)
    {
      const double quantum = range.Extent(c) / 65535.0;
      EXPECT_NEAR(decode(range, c, t[4 * i + c]), x[3 * i + c], 0.5 * quantum + 1e-9);
    }
    EXPECT_EQ(t[4 * i + 3], 65535);
  }
}

TEST(CoordinateTexture, MaskAndNonFiniteAreNotDrawnNorInTheRange)
{
  const float nan = std::numeric_limits<float>::quiet_NaN();
  // 2D coordinates; voxel 1 masked (its value 100 must not stretch the range), voxel 2 NaN.
  const std::vector<float> x = { 0.f, 1.f, 100.f, 100.f, nan, 0.f, 4.f, 3.f };
  const std::vector<std::uint8_t> mask = { 1, 0, 1, 1 };
  mcv::CoordinateRange range;
  range.Add(x.data(), 4, 2, mask.data());
  EXPECT_DOUBLE_EQ(range.min[0], 0.0);
  EXPECT_DOUBLE_EQ(range.max[0], 4.0);
  EXPECT_DOUBLE_EQ(range.min[1], 1.0);
  EXPECT_DOUBLE_EQ(range.max[1], 3.0);
  std::vector<std::uint16_t> t(16, 7);
  EXPECT_EQ(mcv::quantizeCoordinates(x.data(), 4, 2, mask.data(), range, t.data()), 2u);
  EXPECT_EQ(t[3], 65535);
  EXPECT_EQ(t[7], 0);
  EXPECT_EQ(t[11], 0);
  EXPECT_EQ(t[15], 65535);
  EXPECT_EQ(t[12], 65535); // x = 4: the top of the range
  EXPECT_EQ(t[13], 65535); // y = 3
  EXPECT_EQ(t[14], 0);     // the missing third component
}

TEST(CoordinateTexture, ConstantComponentDecodesToItsValue)
{
  const std::vector<float> x = { 2.5f, 0.f, 2.5f, 1.f };
  mcv::CoordinateRange range;
  range.Add(x.data(), 2, 2);
  std::vector<std::uint16_t> t(8);
  mcv::quantizeCoordinates(x.data(), 2, 2, nullptr, range, t.data());
  EXPECT_DOUBLE_EQ(decode(range, 0, t[0]), 2.5);
  EXPECT_DOUBLE_EQ(decode(range, 0, t[4]), 2.5);
  EXPECT_DOUBLE_EQ(decode(range, 1, t[5]), 1.0);
}
