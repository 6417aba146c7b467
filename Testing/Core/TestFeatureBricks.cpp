// The fused path: features a slab at a time (FeatureBricks.h) against the whole
// Features array of computeFeatures, and the reduction of those slabs against the
// reduction of the whole array, on a small synthetic 3-channel volume with a zero
// background, mixed scalar types and a NaN voxel.
#include "BackgroundMask.h"
#include "DimensionReduction.h"
#include "FeatureBricks.h"
#include "FeatureVectors.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <string>
#include <vector>

namespace
{

struct Volume
{
  mcv::ImageGrid grid;
  std::vector<float> a;
  std::vector<std::uint16_t> b;
  std::vector<double> c;
  std::vector<mcv::ChannelView> views() const
  {
    mcv::ChannelView va, vb, vc;
    va.data = a.data();
    va.type = mcv::ScalarType::Float32;
    vb.data = b.data();
    vb.type = mcv::ScalarType::UInt16;
    vc.data = c.data();
    vc.type = mcv::ScalarType::Float64;
    return { va, vb, vc };
  }
};

// A blob in a zero field: smooth, a ramp and a hash pattern, so the features vary.
Volume makeVolume(bool withNaN)
{
  Volume v;
  v.grid.dims = { 23, 19, 17 };
  v.grid.spacing = { 1.0, 0.8, 1.5 };
  const std::size_t n = v.grid.voxelCount();
  v.a.resize(n);
  v.b.resize(n);
  v.c.resize(n);
  std::size_t at = 0;
  for (int k = 0; k < v.grid.dims[2]; ++k)
    for (int j = 0; j < v.grid.dims[1]; ++j)
      for (int i = 0; i < v.grid.dims[0]; ++i, ++at)
      {
        const double x = (i - 11.0) / 8.0, y = (j - 9.0) / 7.0, z = (k - 8.0) / 6.0;
        const double r2 = x * x + y * y + z * z;
        const bool inside = r2 < 1.0;
        v.a[at] = inside ? static_cast<float>(std::exp(-2.0 * r2) * 100.0) : 0.0f;
        v.b[at] = inside ? static_cast<std::uint16_t>((i * 7 + j * 13 + k * 29) % 50) : 0;
        v.c[at] = inside ? 0.5 * i + 0.25 * j - 0.125 * k : 0.0;
      }
  if (withNaN)
  {
    v.a[(8 * 19 + 9) * 23 + 11] = std::numeric_limits<float>::quiet_NaN();
  }
  return v;
}

mcv::FeatureOptions options24D()
{
  mcv::FeatureOptions o;
  o.preset = mcv::FeaturePreset::TwentyFourD;
  o.device = mcv::Device::CPU;
  return o;
}

std::vector<float> wholeFeatures(const Volume& v, const mcv::FeatureOptions& o, mcv::FeatureResult& r)
{
  const int F = mcv::featureCount(3, o);
  std::vector<float> m(v.grid.voxelCount() * static_cast<std::size_t>(F));
  EXPECT_TRUE(mcv::computeFeatures(v.views(), v.grid, o, mcv::FeatureOutput{ m.data(), v.grid.voxelCount(), F }, r));
  return m;
}

// Slab by slab, with slabs of `slices` z slices.
std::vector<float> slabFeatures(mcv::FeatureBricks& bricks)
{
  std::vector<float> m(bricks.rows() * static_cast<std::size_t>(bricks.cols()));
  for (std::size_t b = 0; b < bricks.blockCount(); ++b)
  {
    const std::size_t begin = bricks.blockBegin(b), end = bricks.blockBegin(b + 1);
    const float* rows = bricks.block(b);
    std::copy(rows, rows + (end - begin) * bricks.cols(), m.begin() + static_cast<std::ptrdiff_t>(begin * bricks.cols()));
  }
  return m;
}

std::size_t sliceBytes(const Volume& v, int F)
{
  return static_cast<std::size_t>(v.grid.dims[0]) * v.grid.dims[1] * F * sizeof(float);
}

float maxDifference(const std::vector<float>& a, const std::vector<float>& b)
{
  float d = 0;
  for (std::size_t i = 0; i < a.size(); ++i)
  {
    d = std::max(d, std::abs(a[i] - b[i]));
  }
  return d;
}

TEST(FeatureBricks, SlabsEqualTheWholeArray)
{
  for (bool withNaN : { false, true })
  {
    const Volume v = makeVolume(withNaN);
    for (mcv::FeatureNormalization norm :
      { mcv::FeatureNormalization::ZScore, mcv::FeatureNormalization::MinMax, mcv::FeatureNormalization::None })
    {
      mcv::FeatureOptions o = options24D();
      o.normalization = norm;
      mcv::FeatureResult whole;
      const std::vector<float> expected = wholeFeatures(v, o, whole);
      for (int slices : { 1, 4, 17 })
      {
        mcv::FeatureBricks bricks(v.views(), v.grid, o, slices * sliceBytes(v, 24));
        ASSERT_EQ(bricks.slabSlices(), slices);
        mcv::FeatureResult r;
        ASSERT_TRUE(bricks.prepare(r)) << r.error;
        EXPECT_EQ(r.names, whole.names);
        EXPECT_EQ(r.nonFiniteVoxels, whole.nonFiniteVoxels);
        EXPECT_EQ(r.warnings, whole.warnings);
        for (std::size_t c = 0; c < r.columnOffset.size(); ++c)
        {
          EXPECT_NEAR(r.columnOffset[c], whole.columnOffset[c], 1e-12 * (1 + std::abs(whole.columnOffset[c])));
          EXPECT_NEAR(r.columnScale[c], whole.columnScale[c], 1e-12 * (1 + std::abs(whole.columnScale[c])));
        }
        EXPECT_LE(maxDifference(slabFeatures(bricks), expected), 1e-6f)
          << "slabs of " << slices << " slices, normalisation " << static_cast<int>(norm) << ", NaN " << withNaN;
      }
    }
  }
}

TEST(FeatureBricks, GatheredVoxelsEqualTheirRows)
{
  const Volume v = makeVolume(true);
  const mcv::FeatureOptions o = options24D();
  mcv::FeatureResult whole;
  const std::vector<float> expected = wholeFeatures(v, o, whole);
  mcv::FeatureBricks bricks(v.views(), v.grid, o, sliceBytes(v, 24));
  mcv::FeatureResult r;
  ASSERT_TRUE(bricks.prepare(r));
  // Corners, faces, the NaN voxel and its neighbours, and a stride through the volume.
  std::vector<std::size_t> index{ 0, v.grid.voxelCount() - 1, 22, 23 * 19 - 1, (8 * 19 + 9) * 23 + 11,
    (8 * 19 + 9) * 23 + 12, (7 * 19 + 9) * 23 + 11 };
  for (std::size_t i = 5; i < v.grid.voxelCount(); i += 37)
  {
    index.push_back(i);
  }
  std::vector<float> got(index.size() * 24);
  bricks.gather(index.data(), index.size(), got.data());
  for (std::size_t i = 0; i < index.size(); ++i)
  {
    for (int c = 0; c < 24; ++c)
    {
      ASSERT_LE(std::abs(got[i * 24 + c] - expected[index[i] * 24 + c]), 1e-6f) << "voxel " << index[i] << " column " << c;
    }
  }
}

// The fused reduction (FeatureBricks as the rows) against the reduction of the whole array:
// the same sample, fit and coordinates.
TEST(FeatureBricks, FusedReductionEqualsTheChain)
{
  const Volume v = makeVolume(false);
  const mcv::FeatureOptions o = options24D();
  mcv::FeatureResult whole;
  const std::vector<float> features = wholeFeatures(v, o, whole);
  std::vector<unsigned char> foreground(v.grid.voxelCount());
  mcv::BackgroundMaskResult mask;
  ASSERT_TRUE(mcv::computeBackgroundMask(v.views(), v.grid, {}, foreground.data(), mask));
  for (mcv::ReductionMethod method : { mcv::ReductionMethod::PCA, mcv::ReductionMethod::Isomap })
  {
    mcv::ReductionOptions ro;
    ro.method = method;
    ro.referenceSampleSize = 600;
    ro.numberOfNeighbors = 10;
    ro.numberOfLandmarks = 100;
    ro.device = mcv::Device::CPU;
    ro.sampleMask = foreground.data();
    const mcv::ReductionResult chain =
      mcv::reduceDimension(mcv::FeatureMatrix{ features.data(), v.grid.voxelCount(), 24 }, ro);
    ASSERT_TRUE(chain.ok()) << chain.error;
    mcv::FeatureBricks bricks(v.views(), v.grid, o, 3 * sliceBytes(v, 24));
    mcv::FeatureResult r;
    ASSERT_TRUE(bricks.prepare(r));
    const mcv::ReductionResult fused = mcv::reduceDimension(bricks, ro);
    ASSERT_TRUE(fused.ok()) << fused.error;
    EXPECT_EQ(fused.referenceIndices, chain.referenceIndices);
    EXPECT_EQ(fused.usedColumns, chain.usedColumns);
    ASSERT_EQ(fused.coordinates.size(), chain.coordinates.size());
    float lo = chain.coordinates[0], hi = lo;
    for (float x : chain.coordinates)
    {
      lo = std::min(lo, x);
      hi = std::max(hi, x);
    }
    EXPECT_LE(maxDifference(fused.coordinates, chain.coordinates), 1e-5f * (hi - lo));
  }
}

// The fused reduction with a box of the block as output (a split run's piece without its
// ghost layers) keeps exactly the box's rows of the whole block's coordinates, float32 and
// float16. Device Auto takes the GPU fused placement in a CUDA build (its block-sized
// staging array), the CPU's chunks otherwise.
TEST(FeatureBricks, BoxedOutputKeepsTheBlocksRows)
{
  const Volume v = makeVolume(false);
  const mcv::FeatureOptions o = options24D();
  const std::array<int, 3> lo{ 3, 2, 4 }, hi{ 18, 15, 12 };
  for (mcv::Device device : { mcv::Device::CPU, mcv::Device::Auto })
  {
    for (bool half : { false, true })
    {
      SCOPED_TRACE(std::string(device == mcv::Device::CPU ? "CPU" : "Auto") + (half ? ", float16" : ", float32"));
      mcv::ReductionOptions ro;
      ro.method = mcv::ReductionMethod::Isomap;
      ro.referenceSampleSize = 600;
      ro.numberOfNeighbors = 10;
      ro.numberOfLandmarks = 100;
      ro.device = device;
      ro.block = v.grid;
      ro.piece = mcv::GridPiece::whole(v.grid);
      const std::size_t n = v.grid.voxelCount();
      const std::size_t kept = std::size_t(16) * 14 * 9;
      std::vector<std::uint16_t> wholeHalves(n * 3), boxHalves(kept * 3, 0xFFFF);
      std::vector<float> wholeFloats(n * 3), boxFloats(kept * 3, std::nanf(""));
      for (bool boxed : { false, true })
      {
        mcv::FeatureBricks bricks(v.views(), v.grid, o, 3 * sliceBytes(v, 24));
        mcv::FeatureResult r;
        ASSERT_TRUE(bricks.prepare(r)) << r.error;
        mcv::ReductionOptions run = ro;
        if (boxed)
        {
          run.outputLo = lo;
          run.outputHi = hi;
        }
        if (half)
        {
          run.coordinatesHalfOutput = boxed ? boxHalves.data() : wholeHalves.data();
        }
        else
        {
          run.coordinatesOutput = boxed ? boxFloats.data() : wholeFloats.data();
        }
        const mcv::ReductionResult result = mcv::reduceDimension(bricks, run);
        ASSERT_TRUE(result.ok()) << result.error;
      }
      std::size_t to = 0;
      for (int k = lo[2]; k <= hi[2]; ++k)
        for (int j = lo[1]; j <= hi[1]; ++j)
          for (int i = lo[0]; i <= hi[0]; ++i, ++to)
          {
            const std::size_t from = (static_cast<std::size_t>(k) * 19 + static_cast<std::size_t>(j)) * 23 + static_cast<std::size_t>(i);
            for (std::size_t c = 0; c < 3; ++c)
            {
              if (half)
              {
                ASSERT_EQ(boxHalves[to * 3 + c], wholeHalves[from * 3 + c]) << "voxel " << i << " " << j << " " << k;
              }
              else
              {
                ASSERT_EQ(boxFloats[to * 3 + c], wholeFloats[from * 3 + c]) << "voxel " << i << " " << j << " " << k;
              }
            }
          }
      ASSERT_EQ(to, kept);
    }
  }
}

// The slab budget by default: the whole volume's 256 MiB shared out by the voxels a process
// owns, at least 4 slices, at most 256 MiB; the constructor takes it.
TEST(FeatureBricks, SlabBudgetFollowsTheOwnedShare)
{
  const Volume v = makeVolume(false);
  const std::size_t slice = sliceBytes(v, 24); // 23 x 19 voxels x 24 floats = 41952 bytes
  const std::size_t whole = mcv::FeatureBricks::kDefaultSlabBytes;
  // One process, the whole volume: 256 MiB; the constructor's 17 slices (all).
  mcv::GridPiece piece = mcv::GridPiece::whole(v.grid);
  EXPECT_EQ(mcv::FeatureBricks::slabBytesFor(v.grid, piece, 24), whole);
  EXPECT_EQ(mcv::FeatureBricks::slabBytesFor(v.grid, mcv::GridPiece(), 24), whole);
  // The block owned is 1/1000 of the volume: 268435 bytes, 6 slices.
  piece.wholeDims[2] = 17 * 1000;
  EXPECT_EQ(mcv::FeatureBricks::slabBytesFor(v.grid, piece, 24), whole / 1000);
  mcv::FeatureOptions o = options24D();
  o.piece = piece;
  EXPECT_EQ(mcv::FeatureBricks(v.views(), v.grid, o).slabSlices(), 6);
  // 1/100000: the floor of 4 slices.
  piece.wholeDims[2] = 17 * 100000;
  EXPECT_EQ(mcv::FeatureBricks::slabBytesFor(v.grid, piece, 24), 4 * slice);
  o.piece = piece;
  EXPECT_EQ(mcv::FeatureBricks(v.views(), v.grid, o).slabSlices(), 4);
  // Slices so large that 4 exceed 256 MiB: 256 MiB.
  mcv::ImageGrid huge;
  huge.dims = { 20000, 20000, 8 };
  mcv::GridPiece tiny = mcv::GridPiece::whole(huge);
  tiny.wholeDims[2] = 8000;
  EXPECT_EQ(mcv::FeatureBricks::slabBytesFor(huge, tiny, 24), whole);
}

TEST(FeatureBricks, BadArgumentsAreErrors)
{
  const Volume v = makeVolume(false);
  mcv::FeatureOptions o = options24D();
  o.preset = mcv::FeaturePreset::Custom;
  o.custom = mcv::FeatureSelection{ false, false, false, false, false, false };
  mcv::FeatureBricks bricks(v.views(), v.grid, o);
  mcv::FeatureResult r;
  EXPECT_FALSE(bricks.prepare(r));
  EXPECT_NE(r.error.find("no feature selected"), std::string::npos) << r.error;
}

} // namespace
