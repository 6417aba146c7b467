// Best viewpoint, features (whole blocks, and slab by slab: FeatureBricks) and the background mask split over processes (threads standing in for MPI ranks) give
// what one process gives for the whole volume: the property the MPI-parallel filters rely
// on. Pieces are cut like vtkExtentTranslator's block mode (neighbouring pieces share one
// boundary layer) and padded with ghost layers.
#include "BackgroundMask.h"
#include "BestViewpoint.h"
#include "FeatureBricks.h"
#include "FeatureVectors.h"
#include "ThreadCommunicator.h"

#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <limits>
#include <mutex>
#include <random>
#include <vector>

namespace
{

using Extent = std::array<int, 6>; // inclusive point extent: x0 x1 y0 y1 z0 z1

// R pieces of `whole`, cut along z, then the last slab along y (so that 3 pieces exercise
// two axes, like the translator's 3-piece split of a cube).
std::vector<Extent> splitPieces(const Extent& whole, int R)
{
  std::vector<Extent> pieces;
  if (R == 1)
  {
    return { whole };
  }
  const int zMid = (whole[4] + whole[5]) / 2;
  Extent low = whole, high = whole;
  low[5] = zMid;
  high[4] = zMid;
  pieces.push_back(low);
  if (R == 2)
  {
    pieces.push_back(high);
    return pieces;
  }
  const int yMid = (whole[2] + whole[3]) / 2;
  Extent a = high, b = high;
  a[3] = yMid;
  b[2] = yMid;
  pieces.push_back(a);
  pieces.push_back(b);
  return pieces;
}

struct Block
{
  mcv::ImageGrid grid;
  mcv::GridPiece piece;
  Extent extent; // of the block, in whole-volume indices
  Extent pieceInBlock; // the piece, in block indices
};

// The piece padded by `ghost` layers (clipped to the volume) and what it owns: the piece
// without its upper boundary layer, unless that layer is the volume's last.
Block makeBlock(const Extent& whole, const Extent& piece, int ghost, const mcv::ImageGrid& wholeGrid)
{
  Block b;
  for (int a = 0; a < 3; ++a)
  {
    b.extent[2 * a] = std::max(whole[2 * a], piece[2 * a] - ghost);
    b.extent[2 * a + 1] = std::min(whole[2 * a + 1], piece[2 * a + 1] + ghost);
    b.grid.dims[a] = b.extent[2 * a + 1] - b.extent[2 * a] + 1;
    b.grid.spacing[a] = wholeGrid.spacing[a];
    b.grid.origin[a] = wholeGrid.origin[a] + b.extent[2 * a] * wholeGrid.spacing[a];
    b.piece.wholeDims[a] = whole[2 * a + 1] - whole[2 * a] + 1;
    b.piece.offset[a] = b.extent[2 * a];
    const int ownedHi = piece[2 * a + 1] == whole[2 * a + 1] ? piece[2 * a + 1] : piece[2 * a + 1] - 1;
    b.piece.ownedLo[a] = piece[2 * a] - b.extent[2 * a];
    b.piece.ownedHi[a] = ownedHi - b.extent[2 * a];
    b.pieceInBlock[2 * a] = piece[2 * a] - b.extent[2 * a];
    b.pieceInBlock[2 * a + 1] = piece[2 * a + 1] - b.extent[2 * a];
  }
  return b;
}

template <class T>
std::vector<T> cropValues(const std::vector<T>& values, int components, const mcv::ImageGrid& from,
  const Extent& box)
{
  std::vector<T> out;
  for (int k = box[4]; k <= box[5]; ++k)
    for (int j = box[2]; j <= box[3]; ++j)
      for (int i = box[0]; i <= box[1]; ++i)
      {
        const std::size_t v = i + static_cast<std::size_t>(from.dims[0]) * (j + static_cast<std::size_t>(from.dims[1]) * k);
        out.insert(out.end(), values.begin() + v * components, values.begin() + (v + 1) * components);
      }
  return out;
}

// Every channel cropped to a block's extent (its piece plus ghost layers).
std::vector<std::vector<float>> cropChannels(const std::vector<std::vector<float>>& channels,
  const mcv::ImageGrid& from, const Extent& box)
{
  std::vector<std::vector<float>> out;
  for (const auto& c : channels)
  {
    out.push_back(cropValues(c, 1, from, box));
  }
  return out;
}

// Runs body(rank, options, block, channels) on R threads that share one communicator: each
// rank gets its piece of the volume padded by one ghost layer (makeBlock), the channels
// cropped to that block, and a copy of `options` with its communicator and piece set.
// Returns the pieces in rank order.
template <class Options, class Body>
std::vector<Extent> runOnPieces(const Extent& wholeExtent, const mcv::ImageGrid& whole, int R,
  const std::vector<std::vector<float>>& channels, const Options& options, Body body)
{
  const std::vector<Extent> pieces = splitPieces(wholeExtent, R);
  mcv::testing::ThreadGroup group(R);
  group.run([&](int rank, const mcv::Communicator& comm) {
    const Block b = makeBlock(wholeExtent, pieces[static_cast<std::size_t>(rank)], 1, whole);
    Options o = options;
    o.communicator = &comm;
    o.piece = b.piece;
    body(rank, o, b, cropChannels(channels, whole, b.extent));
  });
  return pieces;
}

// Smooth blobs plus noise: many corners, distinct responses.
std::vector<float> blobVolume(const mcv::ImageGrid& g, unsigned seed)
{
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> u(0.f, 1.f);
  std::vector<std::array<float, 4>> blobs;
  for (int b = 0; b < 12; ++b)
  {
    blobs.push_back({ u(rng) * g.dims[0], u(rng) * g.dims[1], u(rng) * g.dims[2], 2.f + 4.f * u(rng) });
  }
  std::vector<float> v(g.voxelCount());
  std::size_t n = 0;
  for (int k = 0; k < g.dims[2]; ++k)
    for (int j = 0; j < g.dims[1]; ++j)
      for (int i = 0; i < g.dims[0]; ++i)
      {
        float s = 0.05f * u(rng);
        for (const auto& b : blobs)
        {
          const float d2 = (i - b[0]) * (i - b[0]) + (j - b[1]) * (j - b[1]) + (k - b[2]) * (k - b[2]);
          s += std::exp(-d2 / (2 * b[3] * b[3]));
        }
        v[n++] = std::min(1.f, s);
      }
  return v;
}

class Distributed : public ::testing::TestWithParam<int>
{
};

TEST_P(Distributed, BestViewpointEqualsOneProcess)
{
  const int R = GetParam();
  mcv::ImageGrid whole;
  whole.dims = { 44, 38, 30 };
  whole.spacing = { 1.0, 1.2, 0.8 };
  whole.origin = { -3.0, 2.0, 5.0 };
  const Extent wholeExtent{ 0, 43, 0, 37, 0, 29 };
  const std::vector<float> opacity = blobVolume(whole, 7);
  mcv::BestViewpointOptions options;
  options.numberOfInterestPoints = 300;
  options.device = mcv::Device::CPU;
  const mcv::BestViewpointResult serial = mcv::computeBestViewpoint(opacity.data(), whole, options);
  ASSERT_TRUE(serial.ok()) << serial.error;
  ASSERT_EQ(serial.points.size(), 300u);
  ASSERT_TRUE(serial.view.valid);

  const int ghost = 1 + options.harris.kernelWidth / 2;
  const std::vector<Extent> pieces = splitPieces(wholeExtent, R);
  std::vector<mcv::BestViewpointResult> results(static_cast<std::size_t>(R));
  mcv::testing::ThreadGroup group(R);
  group.run([&](int rank, const mcv::Communicator& comm) {
    const Block b = makeBlock(wholeExtent, pieces[static_cast<std::size_t>(rank)], ghost, whole);
    const std::vector<float> local = cropValues(opacity, 1, whole, b.extent);
    mcv::BestViewpointOptions o = options;
    o.communicator = &comm;
    o.piece = b.piece;
    results[static_cast<std::size_t>(rank)] = mcv::computeBestViewpoint(local.data(), b.grid, o);
  });
  for (const mcv::BestViewpointResult& r : results)
  {
    ASSERT_TRUE(r.ok()) << r.error;
    EXPECT_EQ(r.points.indices, serial.points.indices);
    EXPECT_EQ(r.points.scores, serial.points.scores);
    ASSERT_TRUE(r.view.valid);
    EXPECT_LT(mcv::axisAngleDegrees(r.view.best, serial.view.best), 1e-6);
    for (int a = 0; a < 3; ++a)
    {
      EXPECT_NEAR(r.view.center[a], serial.view.center[a], 1e-9);
    }
  }
}

TEST_P(Distributed, FeaturesEqualOneProcess)
{
  const int R = GetParam();
  mcv::ImageGrid whole;
  whole.dims = { 21, 17, 16 };
  whole.spacing = { 0.9, 1.0, 1.3 };
  const Extent wholeExtent{ 0, 20, 0, 16, 0, 15 };
  std::vector<std::vector<float>> data;
  for (unsigned c = 0; c < 3; ++c)
  {
    data.push_back(blobVolume(whole, 11 + c));
    for (float& v : data.back())
    {
      v *= 100.f * (c + 1);
    }
  }
  data[1][5 + 21 * (4 + 17 * 12)] = std::numeric_limits<float>::quiet_NaN(); // in one piece only
  auto views = [](const std::vector<std::vector<float>>& d) {
    std::vector<mcv::ChannelView> v;
    for (const auto& c : d)
    {
      mcv::ChannelView view;
      view.data = c.data();
      view.type = mcv::ScalarType::Float32;
      v.push_back(view);
    }
    return v;
  };
  for (bool slabs : { false, true })
  for (mcv::FeatureNormalization norm : { mcv::FeatureNormalization::ZScore, mcv::FeatureNormalization::MinMax })
  {
    mcv::FeatureOptions options;
    options.preset = mcv::FeaturePreset::TwentyFourD;
    options.normalization = norm;
    options.device = mcv::Device::CPU;
    const int F = mcv::featureCount(3, options);
    std::vector<float> serialOut(whole.voxelCount() * F);
    mcv::FeatureResult serial;
    ASSERT_TRUE(mcv::computeFeatures(views(data), whole, options, { serialOut.data(), whole.voxelCount(), F }, serial));
    ASSERT_EQ(serial.nonFiniteVoxels, 1u);

    std::vector<mcv::FeatureResult> results(static_cast<std::size_t>(R));
    std::vector<std::vector<float>> pieceFeatures(static_cast<std::size_t>(R));
    const std::vector<Extent> pieces = runOnPieces(wholeExtent, whole, R, data, options,
      [&](int rank, const mcv::FeatureOptions& o, const Block& b, const std::vector<std::vector<float>>& local) {
      std::vector<float> out(b.grid.voxelCount() * F);
      if (slabs)
      {
        // Slabs of 2 z slices of the block, with the statistics of the whole volume.
        mcv::FeatureBricks bricks(views(local), b.grid, o, 2 * b.grid.dims[0] * b.grid.dims[1] * F * sizeof(float));
        if (bricks.prepare(results[static_cast<std::size_t>(rank)]))
        {
          for (std::size_t s = 0; s < bricks.blockCount(); ++s)
          {
            const float* rows = bricks.block(s);
            std::copy(rows, rows + (bricks.blockBegin(s + 1) - bricks.blockBegin(s)) * F,
              out.begin() + static_cast<std::ptrdiff_t>(bricks.blockBegin(s) * F));
          }
        }
      }
      else
      {
        mcv::computeFeatures(views(local), b.grid, o, { out.data(), b.grid.voxelCount(), F },
          results[static_cast<std::size_t>(rank)]);
      }
      pieceFeatures[static_cast<std::size_t>(rank)] = cropValues(out, F, b.grid, b.pieceInBlock);
    });
    for (int r = 0; r < R; ++r)
    {
      const mcv::FeatureResult& res = results[static_cast<std::size_t>(r)];
      ASSERT_TRUE(res.ok()) << res.error;
      EXPECT_EQ(res.nonFiniteVoxels, serial.nonFiniteVoxels);
      EXPECT_EQ(res.warnings, serial.warnings);
      const std::vector<float> expected = cropValues(serialOut, F, whole, pieces[static_cast<std::size_t>(r)]);
      const std::vector<float>& got = pieceFeatures[static_cast<std::size_t>(r)];
      ASSERT_EQ(got.size(), expected.size());
      double worst = 0;
      for (std::size_t i = 0; i < got.size(); ++i)
      {
        worst = std::max(worst, std::abs(double(got[i]) - expected[i]));
      }
      EXPECT_LT(worst, 1e-5) << "rank " << r << " normalisation " << int(norm) << " slabs " << slabs;
      for (std::size_t c = 0; c < serial.columnOffset.size(); ++c)
      {
        EXPECT_NEAR(res.columnOffset[c], serial.columnOffset[c], 1e-9 * (1 + std::abs(serial.columnOffset[c])));
        EXPECT_NEAR(res.columnScale[c], serial.columnScale[c], 1e-9 * (1 + std::abs(serial.columnScale[c])));
      }
    }
  }
}

TEST_P(Distributed, BackgroundMaskEqualsOneProcess)
{
  // The channels' extremes lie in different pieces (channel 0's maximum near z = 0,
  // channel 1's near the top), so a mask from local ranges would differ from the whole's.
  const int R = GetParam();
  mcv::ImageGrid whole;
  whole.dims = { 13, 11, 10 };
  const Extent wholeExtent{ 0, 12, 0, 10, 0, 9 };
  std::vector<std::vector<float>> data(2, std::vector<float>(whole.voxelCount(), 0.f));
  std::mt19937 rng(5);
  std::uniform_real_distribution<float> u(0.f, 1.f);
  for (std::size_t v = 0; v < whole.voxelCount(); ++v)
  {
    data[0][v] = u(rng) < 0.5f ? 0.f : 10.f * u(rng);
    data[1][v] = u(rng) < 0.5f ? 0.f : 10.f * u(rng);
  }
  data[0][3] = 100.f;
  data[1][whole.voxelCount() - 4] = 50.f;
  auto views = [](const std::vector<std::vector<float>>& d) {
    std::vector<mcv::ChannelView> v(d.size());
    for (std::size_t c = 0; c < d.size(); ++c)
    {
      v[c].data = d[c].data();
    }
    return v;
  };
  mcv::BackgroundMaskOptions options;
  options.threshold = 0.04; // cuts at 4 and 2: the local maxima would move them
  std::vector<unsigned char> serialMask(whole.voxelCount());
  mcv::BackgroundMaskResult serial;
  ASSERT_TRUE(mcv::computeBackgroundMask(views(data), whole, options, serialMask.data(), serial));
  ASSERT_GT(serial.backgroundVoxels, 0u);
  ASSERT_LT(serial.backgroundVoxels, whole.voxelCount());

  std::vector<mcv::BackgroundMaskResult> results(static_cast<std::size_t>(R));
  std::vector<std::vector<unsigned char>> pieceMasks(static_cast<std::size_t>(R));
  const std::vector<Extent> pieces = runOnPieces(wholeExtent, whole, R, data, options,
    [&](int rank, const mcv::BackgroundMaskOptions& o, const Block& b, const std::vector<std::vector<float>>& local) {
    std::vector<unsigned char> out(b.grid.voxelCount());
    mcv::computeBackgroundMask(views(local), b.grid, o, out.data(), results[static_cast<std::size_t>(rank)]);
    pieceMasks[static_cast<std::size_t>(rank)] = cropValues(out, 1, b.grid, b.pieceInBlock);
  });
  for (int r = 0; r < R; ++r)
  {
    const mcv::BackgroundMaskResult& res = results[static_cast<std::size_t>(r)];
    ASSERT_TRUE(res.ok()) << res.error;
    EXPECT_EQ(res.channelMax, serial.channelMax);
    EXPECT_EQ(res.backgroundVoxels, serial.backgroundVoxels) << "each voxel counted once";
    EXPECT_EQ(res.voxels, whole.voxelCount());
    EXPECT_EQ(pieceMasks[static_cast<std::size_t>(r)],
      cropValues(serialMask, 1, whole, pieces[static_cast<std::size_t>(r)]))
      << "rank " << r;
  }
}

TEST_P(Distributed, AnErrorOnOneProcessStopsAll)
{
  const int R = GetParam();
  if (R == 1)
  {
    GTEST_SKIP() << "needs several processes";
  }
  mcv::ImageGrid g;
  g.dims = { 12, 12, 12 };
  std::vector<float> opacity(g.voxelCount(), 0.5f);
  std::vector<mcv::BestViewpointResult> results(static_cast<std::size_t>(R));
  mcv::testing::ThreadGroup group(R);
  group.run([&](int rank, const mcv::Communicator& comm) {
    mcv::BestViewpointOptions o;
    o.device = mcv::Device::CPU;
    o.communicator = &comm;
    o.piece = mcv::GridPiece::whole(g);
    o.numberOfInterestPoints = rank == 1 ? 0 : 10; // bad on rank 1 only
    results[static_cast<std::size_t>(rank)] = mcv::computeBestViewpoint(opacity.data(), g, o);
  });
  for (int r = 0; r < R; ++r)
  {
    EXPECT_FALSE(results[static_cast<std::size_t>(r)].ok()) << "rank " << r;
  }
  EXPECT_NE(results[1].error.find("NumberOfInterestPoints"), std::string::npos);
  EXPECT_NE(results[0].error.find("another process"), std::string::npos);
}

INSTANTIATE_TEST_SUITE_P(Ranks, Distributed, ::testing::Values(1, 2, 3));

} // namespace
