// float16 coordinates (HalfCoordinates.h): the conversions against IEEE
// binary16's known answers, and every reader of float16 coordinates (the reduction's
// output, the coordinate texture, the per-voxel transfer function) against the same
// values read as float32.
#include "CoordinateTexture.h"
#include "CpuReduction.h"
#include "DimensionReduction.h"
#include "GaussianTransferFunction.h"
#include "HalfCoordinates.h"
#include "MemoryBudget.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <limits>
#include <random>
#include <vector>

namespace
{

std::uint16_t half(float x)
{
  std::uint16_t h = 0;
  mcv::floatsToHalves(&x, 1, &h);
  return h;
}

float widen(std::uint16_t h)
{
  float x = 0;
  mcv::halvesToFloats(&h, 1, &x);
  return x;
}

std::vector<std::uint16_t> halves(const std::vector<float>& x)
{
  std::vector<std::uint16_t> h(x.size());
  mcv::floatsToHalves(x.data(), x.size(), h.data());
  return h;
}

std::vector<float> floats(const std::vector<std::uint16_t>& h)
{
  std::vector<float> x(h.size());
  mcv::halvesToFloats(h.data(), h.size(), x.data());
  return x;
}

} // namespace

TEST(HalfCoordinates, KnownBitPatterns)
{
  EXPECT_EQ(half(1.0f), 0x3C00);
  EXPECT_EQ(half(-2.0f), 0xC000);
  EXPECT_EQ(half(0.0f), 0x0000);
  EXPECT_EQ(half(-0.0f), 0x8000);
  EXPECT_EQ(half(65504.0f), 0x7BFF);          // the largest finite half
  EXPECT_EQ(half(0.1f), 0x2E66);              // 0.0999755859375
  EXPECT_EQ(half(std::ldexp(1.0f, -14)), 0x0400); // the smallest normal
  EXPECT_EQ(half(std::ldexp(1.0f, -24)), 0x0001); // the smallest subnormal
  // Round to nearest, ties to even: 1 + 2^-11 lies halfway between 1 and 1 + 2^-10.
  EXPECT_EQ(half(1.0f + std::ldexp(1.0f, -11)), 0x3C00);
  EXPECT_EQ(half(1.0f + 3 * std::ldexp(1.0f, -11)), 0x3C02);
  EXPECT_FLOAT_EQ(widen(0x2E66), 0.0999755859375f);
  EXPECT_FLOAT_EQ(widen(0xC248), -3.140625f);
}

TEST(HalfCoordinates, EveryHalfIsExactAsFloat)
{
  // All 65536 patterns: a finite half widens to a float that rounds back to the same bits.
  for (std::uint32_t bits = 0; bits <= 0xFFFF; ++bits)
  {
    const std::uint16_t h = static_cast<std::uint16_t>(bits);
    const float x = widen(h);
    if (std::isnan(x))
    {
      EXPECT_EQ(h & 0x7C00, 0x7C00) << bits;
      continue;
    }
    ASSERT_EQ(half(x), h) << "pattern " << bits << " value " << x;
  }
}

TEST(HalfCoordinates, RoundTripWithinHalfPrecision)
{
  std::mt19937 rng(7);
  std::uniform_real_distribution<float> exponent(-14.0f, 15.9f);
  std::bernoulli_distribution negative(0.5);
  std::vector<float> x(200000);
  for (float& v : x)
  {
    v = std::exp2(exponent(rng)) * (negative(rng) ? -1.0f : 1.0f);
  }
  const std::vector<float> back = floats(halves(x));
  for (std::size_t i = 0; i < x.size(); ++i)
  {
    // Normal range: half an ulp of an 11-bit significand, 2^-11 of the value.
    ASSERT_LE(std::abs(back[i] - x[i]), std::ldexp(std::abs(x[i]), -11)) << x[i];
  }
  // Subnormal range: an absolute 2^-25 (half the smallest subnormal step).
  std::uniform_real_distribution<float> tiny(-6e-5f, 6e-5f);
  for (int i = 0; i < 10000; ++i)
  {
    const float v = tiny(rng);
    ASSERT_LE(std::abs(widen(half(v)) - v), std::ldexp(1.0f, -25)) << v;
  }
}

TEST(HalfCoordinates, OverflowIsCounted)
{
  const std::vector<float> x{ 1.0f, 65504.0f, 65519.0f, 65520.0f, -1e6f, std::numeric_limits<float>::infinity(),
    std::numeric_limits<float>::quiet_NaN() };
  std::vector<std::uint16_t> h(x.size());
  // 65519 still rounds to 65504; 65520 and -1e6 overflow; inf and NaN were not finite.
  EXPECT_EQ(mcv::floatsToHalves(x.data(), x.size(), h.data()), 2u);
  EXPECT_EQ(h[2], 0x7BFF);
  EXPECT_EQ(h[3], 0x7C00);
  EXPECT_EQ(h[4], 0xFC00);
}

TEST(HalfCoordinates, MemoryBudgetCountsSixBytesPerVoxel)
{
  const std::size_t n = 10u << 20; // beyond one placement chunk
  const std::size_t scratch = mcv::kHalfPlacementRows * 3 * sizeof(float);
  EXPECT_EQ(mcv::coordinateBytes(n, 3, false), n * 12);
  EXPECT_EQ(mcv::coordinateBytes(n, 3, true), n * 6 + scratch);
  EXPECT_EQ(mcv::coordinateBytes(1000, 3, true), 1000u * 6 + 1000 * 12); // scratch of the rows only
  EXPECT_EQ(mcv::reductionBytes(n, 24, 3, true, true), n * 6 + scratch);
  EXPECT_EQ(mcv::fusedReductionBytes(n, 3, 4096, true), n * 6 + scratch + 2 * n + 4096);
  EXPECT_EQ(mcv::fusedReductionBytes(n, 3, 4096, false), n * 12 + 2 * n + 4096);
}

TEST(HalfCoordinates, ReductionWritesTheFloatCoordinatesRounded)
{
  // More rows than one placement chunk, so the chunked float16 path meets a boundary; PCA
  // and the out-of-sample placement (Isomap) each write the output.
  const std::size_t n = mcv::kHalfPlacementRows + 4321;
  std::mt19937 rng(3);
  std::normal_distribution<float> g(0.0f, 1.0f);
  std::vector<float> x(n * 4);
  for (std::size_t i = 0; i < n; ++i)
  {
    const float a = g(rng), b = g(rng);
    x[4 * i] = 3 * a;
    x[4 * i + 1] = a + 0.5f * b;
    x[4 * i + 2] = b * b;
    x[4 * i + 3] = 0.1f * g(rng);
  }
  const mcv::FeatureMatrix features{ x.data(), n, 4 };
  for (mcv::ReductionMethod method : { mcv::ReductionMethod::PCA, mcv::ReductionMethod::Isomap })
  {
    SCOPED_TRACE(static_cast<int>(method));
    mcv::ReductionOptions o = mcv::testing::cpuReduction(method, 3, 10, 100, 800);
    o.trustworthinessSample = 0;
    const mcv::ReductionResult f32 = mcv::reduceDimension(features, o);
    ASSERT_TRUE(f32.ok()) << f32.error;
    std::vector<std::uint16_t> h(n * 3, 0xFFFF);
    o.coordinatesHalfOutput = h.data();
    const mcv::ReductionResult f16 = mcv::reduceDimension(features, o);
    ASSERT_TRUE(f16.ok()) << f16.error;
    EXPECT_TRUE(f16.coordinates.empty());
    EXPECT_EQ(f16.referenceIndices, f32.referenceIndices);
    EXPECT_EQ(h, halves(f32.coordinates)); // bit for bit
  }
}

TEST(HalfCoordinates, ReductionRefusesCoordinatesBeyondHalfRange)
{
  std::mt19937 rng(5);
  std::normal_distribution<float> g(0.0f, 1e5f);
  std::vector<float> x(2000 * 3);
  for (float& v : x)
  {
    v = g(rng);
  }
  mcv::ReductionOptions o;
  o.method = mcv::ReductionMethod::PCA;
  o.device = mcv::Device::CPU;
  o.referenceSampleSize = 500;
  std::vector<std::uint16_t> h(2000 * 3);
  o.coordinatesHalfOutput = h.data();
  const mcv::ReductionResult r = mcv::reduceDimension(mcv::FeatureMatrix{ x.data(), 2000, 3 }, o);
  ASSERT_FALSE(r.ok());
  EXPECT_NE(r.error.find("float16's range"), std::string::npos) << r.error;
  // Both destinations at once are an error, not a choice.
  std::vector<float> f(2000 * 3);
  o.coordinatesOutput = f.data();
  const mcv::ReductionResult both = mcv::reduceDimension(mcv::FeatureMatrix{ x.data(), 2000, 3 }, o);
  EXPECT_NE(both.error.find("one destination"), std::string::npos) << both.error;
}

TEST(HalfCoordinates, ReadersGiveWhatTheyGiveForTheDecodedFloats)
{
  // 3D coordinates with a mask, NaN and voxels beyond one decode chunk.
  const std::size_t n = 3 * mcv::kHalfChunkVoxels + 77;
  std::mt19937 rng(11);
  std::uniform_real_distribution<float> u(-12.0f, 9.0f);
  std::vector<float> x(n * 3);
  for (float& v : x)
  {
    v = u(rng);
  }
  x[3 * 100 + 1] = std::numeric_limits<float>::quiet_NaN();
  std::vector<std::uint8_t> mask(n, 1);
  for (std::size_t i = 0; i < n; i += 7)
  {
    mask[i] = 0;
  }
  const std::vector<std::uint16_t> h = halves(x);
  const std::vector<float> decoded = floats(h);

  mcv::CoordinateRange fromFloats, fromHalves;
  fromFloats.Add(decoded.data(), n, 3, mask.data());
  fromHalves.AddHalf(h.data(), n, 3, mask.data());
  for (int c = 0; c < 3; ++c)
  {
    EXPECT_EQ(fromHalves.min[c], fromFloats.min[c]);
    EXPECT_EQ(fromHalves.max[c], fromFloats.max[c]);
  }
  std::vector<std::uint16_t> t32(n * 4), t16(n * 4);
  const std::size_t drawn32 = mcv::quantizeCoordinates(decoded.data(), n, 3, mask.data(), fromFloats, t32.data());
  const std::size_t drawn16 = mcv::quantizeHalfCoordinates(h.data(), n, 3, mask.data(), fromFloats, t16.data());
  EXPECT_EQ(drawn16, drawn32);
  EXPECT_EQ(t16, t32);

  std::vector<mcv::GaussianWidget> widgets(2);
  widgets[0].center[0] = 2;
  widgets[0].sigma = 3;
  widgets[0].color[1] = 0;
  widgets[0].opacity = 0.7;
  widgets[1].center[1] = -5;
  widgets[1].sigma = 1.5;
  widgets[1].opacity = 0.4;
  mcv::CoordinateView asFloats{ decoded.data(), n, 3 };
  mcv::CoordinateView asHalves{ nullptr, n, 3 };
  asHalves.halves = h.data();
  std::vector<unsigned char> rgba32(n * 4), rgba16(n * 4);
  ASSERT_TRUE(mcv::applyGaussianWidgets(asFloats, widgets, rgba32.data(), mcv::Device::CPU).ok());
  const mcv::TransferFunctionRun run = mcv::applyGaussianWidgets(asHalves, widgets, rgba16.data(), mcv::Device::CPU);
  ASSERT_TRUE(run.ok()) << run.error;
  EXPECT_EQ(rgba16, rgba32);
  EXPECT_EQ(rgba16[4 * 100 + 3], 0); // the NaN voxel: transparent
  // Device GPU: float16 gives what float32 gives on the same device (on the GPU the halves
  // are widened there, exactly; without one both run on the CPU).
  std::vector<unsigned char> gpu32(n * 4), gpu16(n * 4);
  const mcv::TransferFunctionRun run32 = mcv::applyGaussianWidgets(asFloats, widgets, gpu32.data(), mcv::Device::GPU);
  const mcv::TransferFunctionRun run16 = mcv::applyGaussianWidgets(asHalves, widgets, gpu16.data(), mcv::Device::GPU);
  ASSERT_TRUE(run32.ok() && run16.ok());
  EXPECT_EQ(run16.deviceUsed, run32.deviceUsed);
  EXPECT_EQ(gpu16, gpu32);
}
