// Feature vectors (Filters/Core/features/FeatureVectors.h) against hand-computed values: a linear
// ramp (known gradient, zero Laplacian inside, known 3x3x3 variance), a single bright voxel
// (known mean, variance, Laplacian, gradient around it), anisotropic spacing, replicated
// borders, presets and names, normalisation, constant columns, NaN/Inf, scalar types.
#include "FeatureVectors.h"

#include "TestVolumes.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <string>
#include <vector>

namespace
{

namespace mt = mcv::testing;
using mcv::ChannelView;
using mcv::FeatureNormalization;
using mcv::FeatureOptions;
using mcv::FeaturePreset;
using mcv::FeatureResult;
using mcv::ImageGrid;

ChannelView view(const std::vector<float>& v)
{
  ChannelView c;
  c.data = v.data();
  c.type = mcv::ScalarType::Float32;
  return c;
}

FeatureOptions rawAll()
{
  FeatureOptions o;
  o.preset = FeaturePreset::TwentyFourD;
  o.normalization = FeatureNormalization::None;
  o.device = mcv::Device::CPU;
  return o;
}

struct Computed
{
  std::vector<float> m;
  FeatureResult r;
  int cols = 0;
  float at(std::size_t voxel, int col) const { return m[voxel * cols + col]; }
};

Computed compute(const std::vector<std::vector<float>*>& chans, const ImageGrid& g,
  const FeatureOptions& o)
{
  Computed c;
  std::vector<ChannelView> views;
  for (auto* v : chans)
    views.push_back(view(*v));
  c.cols = mcv::featureCount(views.size(), o);
  c.m.assign(g.voxelCount() * c.cols, -1.0f);
  mcv::FeatureOutput out{ c.m.data(), g.voxelCount(), c.cols };
  EXPECT_TRUE(mcv::computeFeatures(views, g, o, out, c.r)) << c.r.error;
  return c;
}

std::size_t idx(const ImageGrid& g, int i, int j, int k)
{
  return (static_cast<std::size_t>(k) * g.dims[1] + j) * g.dims[0] + i;
}

// 24D column order of one channel.
enum Col
{
  Intensity = 0,
  GradX,
  GradY,
  GradZ,
  GradMag,
  Laplacian,
  Mean,
  Variance
};

mt::Volume ramp(const ImageGrid& g, double a, double b, double c, double d)
{
  mt::Volume v;
  v.grid = g;
  v.values.resize(g.voxelCount());
  mt::forEachVoxel(g, [&](int, int, int, double x, double y, double z, std::size_t n) {
    v.values[n] = static_cast<float>(a * x + b * y + c * z + d);
  });
  return v;
}

void checkRamp(const std::array<double, 3>& spacing)
{
  const ImageGrid g = mt::makeGrid(7, 6, 5, spacing, { -1.0, 2.0, 0.5 });
  const double a = 2.0, b = -3.0, c = 0.5;
  mt::Volume v = ramp(g, a, b, c, 10.0);
  const Computed f = compute({ &v.values }, g, rawAll());
  ASSERT_EQ(f.cols, 8);
  const double h0 = spacing[0], h1 = spacing[1], h2 = spacing[2];
  const double var = 2.0 / 3.0 * (a * a * h0 * h0 + b * b * h1 * h1 + c * c * h2 * h2);
  for (int k = 1; k < 4; ++k)
    for (int j = 1; j < 5; ++j)
      for (int i = 1; i < 6; ++i)
      {
        const std::size_t n = idx(g, i, j, k);
        const double tol = 1e-4 * (1 + std::fabs(v.values[n]));
        EXPECT_NEAR(f.at(n, Intensity), v.values[n], 1e-6);
        EXPECT_NEAR(f.at(n, GradX), a, tol);
        EXPECT_NEAR(f.at(n, GradY), b, tol);
        EXPECT_NEAR(f.at(n, GradZ), c, tol);
        EXPECT_NEAR(f.at(n, GradMag), std::sqrt(a * a + b * b + c * c), tol);
        EXPECT_NEAR(f.at(n, Laplacian), 0.0, tol);
        EXPECT_NEAR(f.at(n, Mean), v.values[n], tol);
        EXPECT_NEAR(f.at(n, Variance), var, 1e-3 * var);
      }
  // Replicated border: (f[1] - f[0]) / (2h) is half the slope; Laplacian/6 (index units)
  // is the one missing neighbour's step / 6.
  const std::size_t left = idx(g, 0, 2, 2), right = idx(g, 6, 2, 2);
  EXPECT_NEAR(f.at(left, GradX), a / 2, 1e-4);
  EXPECT_NEAR(f.at(right, GradX), a / 2, 1e-4);
  EXPECT_NEAR(f.at(left, GradY), b, 1e-4);
  EXPECT_NEAR(f.at(left, Laplacian), a * h0 / 6.0, 1e-4);
  EXPECT_NEAR(f.at(right, Laplacian), -a * h0 / 6.0, 1e-4);
  const std::size_t bottom = idx(g, 3, 2, 0);
  EXPECT_NEAR(f.at(bottom, GradZ), c / 2, 1e-4);
  EXPECT_NEAR(f.at(bottom, Laplacian), c * h2 / 6.0, 1e-4);
  // Border mean: the replicated layer counts three times along x at i = 0.
  EXPECT_NEAR(f.at(left, Mean), v.values[left] + a * h0 / 3.0, 1e-4);
}

TEST(FeatureVectors, LinearRampIsotropic)
{
  checkRamp({ 1.0, 1.0, 1.0 });
}

TEST(FeatureVectors, LinearRampAnisotropicSpacing)
{
  // Gradient in world units stays (a, b, c); variance and Laplacian follow index steps.
  checkRamp({ 0.5, 2.0, 1.5 });
}

TEST(FeatureVectors, SingleBrightVoxel)
{
  const ImageGrid g = mt::makeGrid(7, 7, 7, { 1.0, 2.0, 0.5 });
  std::vector<float> v(g.voxelCount(), 0.0f);
  v[idx(g, 3, 3, 3)] = 27.0f;
  const Computed f = compute({ &v }, g, rawAll());
  const std::size_t c = idx(g, 3, 3, 3);
  EXPECT_FLOAT_EQ(f.at(c, Intensity), 27.0f);
  EXPECT_FLOAT_EQ(f.at(c, GradX), 0.0f);
  EXPECT_FLOAT_EQ(f.at(c, GradMag), 0.0f);
  EXPECT_FLOAT_EQ(f.at(c, Laplacian), -27.0f);
  EXPECT_FLOAT_EQ(f.at(c, Mean), 1.0f);
  // (27 - 1)^2 / 27 + 26 (0 - 1)^2 / 27 = 26
  EXPECT_NEAR(f.at(c, Variance), 26.0f, 1e-4);
  // Face neighbours: Laplacian/6 = 27/6; gradient -27 / (2 h) pointing back to the voxel.
  const std::size_t px = idx(g, 4, 3, 3), my = idx(g, 3, 2, 3), pz = idx(g, 3, 3, 4);
  EXPECT_NEAR(f.at(px, Laplacian), 4.5, 1e-5);
  EXPECT_NEAR(f.at(px, GradX), -27.0 / 2.0, 1e-5);
  EXPECT_NEAR(f.at(my, GradY), 27.0 / 4.0, 1e-5);
  EXPECT_NEAR(f.at(pz, GradZ), -27.0 / 1.0, 1e-5);
  EXPECT_NEAR(f.at(pz, GradMag), 27.0, 1e-5);
  // Any voxel of the 3x3x3 block around it: mean 1, variance 26; a corner has Laplacian 0.
  const std::size_t corner = idx(g, 2, 4, 2);
  EXPECT_NEAR(f.at(corner, Mean), 1.0, 1e-5);
  EXPECT_NEAR(f.at(corner, Variance), 26.0, 1e-4);
  EXPECT_NEAR(f.at(corner, Laplacian), 0.0, 1e-6);
  EXPECT_NEAR(f.at(corner, GradMag), 0.0, 1e-6);
  // Two voxels away: nothing.
  const std::size_t far = idx(g, 5, 3, 3);
  EXPECT_EQ(f.at(far, Mean), 0.0f);
  EXPECT_EQ(f.at(far, Variance), 0.0f);
  EXPECT_EQ(f.at(far, Laplacian), 0.0f);
}

TEST(FeatureVectors, PresetsColumnsAndNames)
{
  const ImageGrid g = mt::makeGrid(5, 4, 3);
  mt::Volume a = mt::randomVolume(g, 1), b = mt::randomVolume(g, 2), c = mt::randomVolume(g, 3);
  FeatureOptions o;
  o.device = mcv::Device::CPU;
  o.channelNames = { "T1", "aal", "brodmann" };
  o.preset = FeaturePreset::SixD;
  Computed six = compute({ &a.values, &b.values, &c.values }, g, o);
  ASSERT_EQ(six.cols, 6);
  const std::vector<std::string> sixNames = { "T1.intensity", "T1.gradMag", "aal.intensity",
    "aal.gradMag", "brodmann.intensity", "brodmann.gradMag" };
  EXPECT_EQ(six.r.names, sixNames);

  o.preset = FeaturePreset::TwentyFourD;
  o.channelNames.clear();
  Computed all = compute({ &a.values, &b.values, &c.values }, g, o);
  ASSERT_EQ(all.cols, 24);
  ASSERT_EQ(all.r.names.size(), 24u);
  const std::vector<std::string> ch1 = { "ch1.intensity", "ch1.gradX", "ch1.gradY", "ch1.gradZ",
    "ch1.gradMag", "ch1.laplacian", "ch1.mean", "ch1.variance" };
  for (int i = 0; i < 8; ++i)
  {
    EXPECT_EQ(all.r.names[i], ch1[i]);
  }
  EXPECT_EQ(all.r.names[8], "ch2.intensity");
  EXPECT_EQ(all.r.names[23], "ch3.variance");

  // 6D columns are the matching 24D columns.
  for (std::size_t n = 0; n < g.voxelCount(); ++n)
    for (int ch = 0; ch < 3; ++ch)
    {
      EXPECT_FLOAT_EQ(six.at(n, 2 * ch), all.at(n, 8 * ch + Intensity));
      EXPECT_FLOAT_EQ(six.at(n, 2 * ch + 1), all.at(n, 8 * ch + GradMag));
    }

  o.preset = FeaturePreset::Custom;
  o.custom = mcv::FeatureSelection();
  o.custom.intensity = false;
  o.custom.gradientMagnitude = false;
  o.custom.laplacian = true;
  o.custom.localVariance = true;
  Computed custom = compute({ &a.values, &b.values }, g, o);
  ASSERT_EQ(custom.cols, 4);
  EXPECT_EQ(custom.r.names[0], "ch1.laplacian");
  EXPECT_EQ(custom.r.names[3], "ch2.variance");
}

TEST(FeatureVectors, ZScoreMinMaxNone)
{
  const ImageGrid g = mt::makeGrid(12, 10, 8, { 1.0, 0.7, 1.3 });
  mt::Volume a = mt::randomVolume(g, 5);
  mt::Volume b = mt::gaussianBlobs(g, { { { 4, 3, 4 }, 2.0, 1.0 } }, false);
  for (float& x : b.values)
    x = 1000.0f + 500.0f * x; // large offset: the statistics must not cancel
  FeatureOptions o = rawAll();
  const Computed raw = compute({ &a.values, &b.values }, g, o);
  o.normalization = FeatureNormalization::ZScore;
  const Computed z = compute({ &a.values, &b.values }, g, o);
  o.normalization = FeatureNormalization::MinMax;
  const Computed mm = compute({ &a.values, &b.values }, g, o);
  EXPECT_TRUE(z.r.constantColumns.empty());
  const std::size_t n = g.voxelCount();
  for (int col = 0; col < 16; ++col)
  {
    double s = 0, s2 = 0, lo = 1e30, hi = -1e30, rs = 0, rs2 = 0;
    for (std::size_t v = 0; v < n; ++v)
    {
      s += z.at(v, col);
      s2 += double(z.at(v, col)) * z.at(v, col);
      lo = std::min(lo, double(mm.at(v, col)));
      hi = std::max(hi, double(mm.at(v, col)));
      rs += raw.at(v, col);
    }
    const double mean = s / n, sd = std::sqrt(s2 / n - mean * mean);
    EXPECT_NEAR(mean, 0.0, 1e-5) << z.r.names[col];
    EXPECT_NEAR(sd, 1.0, 1e-4) << z.r.names[col];
    EXPECT_NEAR(lo, 0.0, 1e-6) << z.r.names[col];
    EXPECT_NEAR(hi, 1.0, 1e-6) << z.r.names[col];
    const double rawMean = rs / n;
    for (std::size_t v = 0; v < n; ++v)
      rs2 += (raw.at(v, col) - rawMean) * (raw.at(v, col) - rawMean);
    const double rawSd = std::sqrt(rs2 / n);
    // z = (raw - mean) / sd, voxel by voxel.
    for (std::size_t v = 0; v < n; v += 37)
      EXPECT_NEAR(z.at(v, col), (raw.at(v, col) - rawMean) / rawSd, 1e-3);
    EXPECT_NEAR(z.r.columnOffset[col], rawMean, 1e-6 * (1 + std::fabs(rawMean)));
  }
  EXPECT_TRUE(raw.r.warnings.empty());
}

TEST(FeatureVectors, ConstantColumnsStayZeroWithWarning)
{
  const ImageGrid g = mt::makeGrid(6, 5, 4);
  mt::Volume flat = mt::constantVolume(g, 7.0f);
  mt::Volume a = mt::randomVolume(g, 9);
  for (FeatureNormalization norm : { FeatureNormalization::ZScore, FeatureNormalization::MinMax })
  {
    FeatureOptions o = rawAll();
    o.normalization = norm;
    o.channelNames = { "noise", "flat" };
    const Computed f = compute({ &a.values, &flat.values }, g, o);
    // Every column of the flat channel (8..15) is constant.
    ASSERT_EQ(f.r.constantColumns.size(), 8u);
    EXPECT_EQ(f.r.constantColumns.front(), 8);
    for (std::size_t v = 0; v < g.voxelCount(); ++v)
      for (int col = 8; col < 16; ++col)
        ASSERT_EQ(f.at(v, col), 0.0f);
    bool warned = false;
    for (const std::string& w : f.r.warnings)
      warned = warned || (w.find("constant") != std::string::npos &&
                           w.find("flat.intensity") != std::string::npos &&
                           w.find("flat.variance") != std::string::npos);
    EXPECT_TRUE(warned);
  }
  // None: raw values, no warning.
  FeatureOptions o = rawAll();
  const Computed f = compute({ &flat.values }, g, o);
  EXPECT_TRUE(f.r.constantColumns.empty());
  EXPECT_TRUE(f.r.warnings.empty());
  EXPECT_EQ(f.at(3, Intensity), 7.0f);
  EXPECT_EQ(f.at(3, Mean), 7.0f);
}

TEST(FeatureVectors, NonFiniteVoxelsGiveZeroRowsAndAWarning)
{
  const ImageGrid g = mt::makeGrid(8, 7, 6);
  mt::Volume a = mt::randomVolume(g, 11), b = mt::randomVolume(g, 12);
  const std::size_t nanAt = idx(g, 3, 3, 3), infAt = idx(g, 0, 0, 0), both = idx(g, 6, 5, 4);
  a.values[nanAt] = std::numeric_limits<float>::quiet_NaN();
  b.values[infAt] = std::numeric_limits<float>::infinity();
  a.values[both] = -std::numeric_limits<float>::infinity();
  b.values[both] = std::numeric_limits<float>::quiet_NaN();
  for (FeatureNormalization norm :
    { FeatureNormalization::ZScore, FeatureNormalization::MinMax, FeatureNormalization::None })
  {
    FeatureOptions o = rawAll();
    o.normalization = norm;
    const Computed f = compute({ &a.values, &b.values }, g, o);
    EXPECT_EQ(f.r.nonFiniteVoxels, 3u);
    for (float x : f.m)
      ASSERT_TRUE(std::isfinite(x));
    for (std::size_t v : { nanAt, infAt, both })
      for (int col = 0; col < f.cols; ++col)
        EXPECT_EQ(f.at(v, col), 0.0f) << v << " " << f.r.names[col];
    bool warned = false;
    for (const std::string& w : f.r.warnings)
      warned = warned || (w.find("3 voxel") != std::string::npos && w.find("NaN") != std::string::npos);
    EXPECT_TRUE(warned);
    if (norm == FeatureNormalization::None)
    {
      // A NaN neighbour counts as the centre value: the +x neighbour of nanAt sees a
      // replicated value on its -x side.
      const std::size_t nb = idx(g, 4, 3, 3);
      const float expect = (a.values[idx(g, 5, 3, 3)] - a.values[nb]) * 0.5f;
      EXPECT_NEAR(f.at(nb, GradX), expect, 1e-6);
    }
  }
  // Every voxel non-finite: everything 0, constant-column warning, no NaN.
  std::vector<float> allNan(g.voxelCount(), std::numeric_limits<float>::quiet_NaN());
  FeatureOptions o = rawAll();
  o.normalization = FeatureNormalization::ZScore;
  const Computed f = compute({ &allNan }, g, o);
  for (float x : f.m)
    ASSERT_EQ(x, 0.0f);
  EXPECT_EQ(f.r.nonFiniteVoxels, g.voxelCount());
}

TEST(FeatureVectors, ScalarTypesAndInterleavedComponents)
{
  const ImageGrid g = mt::makeGrid(6, 5, 4, { 0.8, 1.0, 1.2 });
  const std::size_t n = g.voxelCount();
  std::vector<std::uint8_t> u8(n);
  std::vector<std::int16_t> interleaved(2 * n);
  std::vector<double> f64(n);
  std::vector<float> asFloat(n);
  mt::SplitMix64 rng(3);
  for (std::size_t v = 0; v < n; ++v)
  {
    u8[v] = static_cast<std::uint8_t>(rng.next() >> 56);
    asFloat[v] = u8[v];
    interleaved[2 * v] = static_cast<std::int16_t>(-7);
    interleaved[2 * v + 1] = static_cast<std::int16_t>(u8[v]) - 100;
    f64[v] = u8[v];
  }
  FeatureOptions o = rawAll();
  const Computed ref = compute({ &asFloat }, g, o);

  auto run = [&](const ChannelView& c, float shift) {
    std::vector<float> m(n * 8);
    FeatureResult r;
    EXPECT_TRUE(mcv::computeFeatures({ c }, g, o, { m.data(), n, 8 }, r)) << r.error;
    for (std::size_t v = 0; v < n; ++v)
      for (int col = 0; col < 8; ++col)
      {
        const float expect =
          ref.at(v, col) + ((col == Intensity || col == Mean) ? shift : 0.0f);
        ASSERT_NEAR(m[v * 8 + col], expect, 1e-3) << col;
      }
  };
  ChannelView c;
  c.data = u8.data();
  c.type = mcv::ScalarType::UInt8;
  run(c, 0.0f);
  c.data = f64.data();
  c.type = mcv::ScalarType::Float64;
  run(c, 0.0f);
  c.data = interleaved.data();
  c.type = mcv::ScalarType::Int16;
  c.numComponents = 2;
  c.component = 1;
  run(c, -100.0f);
}

TEST(FeatureVectors, BadArguments)
{
  const ImageGrid g = mt::makeGrid(4, 4, 4);
  std::vector<float> v(g.voxelCount(), 1.0f), m(g.voxelCount() * 2);
  FeatureOptions o;
  o.device = mcv::Device::CPU;
  FeatureResult r;
  const mcv::FeatureOutput out{ m.data(), g.voxelCount(), 2 };
  EXPECT_FALSE(mcv::computeFeatures({}, g, o, out, r));
  EXPECT_NE(r.error.find("no channel"), std::string::npos);
  EXPECT_FALSE(mcv::computeFeatures({ view(v) }, mt::makeGrid(0, 4, 4), o, out, r));
  EXPECT_NE(r.error.find("empty"), std::string::npos);
  EXPECT_FALSE(mcv::computeFeatures({ view(v) }, mt::makeGrid(4, 4, 4, { 1, 0, 1 }), o, out, r));
  EXPECT_NE(r.error.find("spacing"), std::string::npos);
  EXPECT_FALSE(mcv::computeFeatures({ view(v) }, g, o, { m.data(), g.voxelCount(), 3 }, r));
  EXPECT_NE(r.error.find("output buffer"), std::string::npos);
  o.channelNames = { "a", "b" };
  EXPECT_FALSE(mcv::computeFeatures({ view(v) }, g, o, out, r));
  EXPECT_NE(r.error.find("names"), std::string::npos);
  o.channelNames.clear();
  o.preset = FeaturePreset::Custom;
  o.custom.intensity = o.custom.gradientMagnitude = false;
  EXPECT_FALSE(mcv::computeFeatures({ view(v) }, g, o, out, r));
  EXPECT_NE(r.error.find("no feature"), std::string::npos);
  ChannelView bad = view(v);
  bad.component = 1;
  o.preset = FeaturePreset::SixD;
  EXPECT_FALSE(mcv::computeFeatures({ bad }, g, o, out, r));
  EXPECT_NE(r.error.find("component"), std::string::npos);
  // The good call works, and a 1-voxel volume too (all gradients 0).
  EXPECT_TRUE(mcv::computeFeatures({ view(v) }, g, o, out, r)) << r.error;
  std::vector<float> one(1, 3.0f), oneOut(2);
  o.normalization = FeatureNormalization::None;
  EXPECT_TRUE(mcv::computeFeatures({ view(one) }, mt::makeGrid(1, 1, 1), o, { oneOut.data(), 1, 2 }, r));
  EXPECT_EQ(oneOut[0], 3.0f);
  EXPECT_EQ(oneOut[1], 0.0f);
}

TEST(FeatureVectors, GpuRequestWithoutGpuFallsBack)
{
  std::string why;
  if (mcv::gpuUsable(&why))
    GTEST_SKIP() << "a GPU is usable here (see Testing/gpu/TestFeaturesGPU.cpp)";
  const ImageGrid g = mt::makeGrid(5, 5, 5);
  mt::Volume a = mt::randomVolume(g, 4);
  FeatureOptions o;
  o.device = mcv::Device::GPU;
  const Computed f = compute({ &a.values }, g, o);
  EXPECT_EQ(f.r.deviceUsed, mcv::Device::CPU);
  ASSERT_FALSE(f.r.warnings.empty());
  EXPECT_NE(f.r.warnings[0].find("CPU"), std::string::npos);
}

} // namespace
