// The dimension reduction split over processes (threads playing MPI ranks, see
// ThreadCommunicator.h) gives the answer of one process: the same reference sample, the same
// embedding, the same coordinates for every voxel. The volume is synthetic on purpose: the
// point is a known answer (the serial run) on data with the traits that make a split hard:
// many voxels sharing one feature vector, a rare bright structure, blocks split as VTK
// splits image data (neighbouring pieces share a boundary layer) with and without ghosts.
#include "DimensionReduction.h"
#include "ReferenceSample.h"
#include "ThreadCommunicator.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <random>
#include <set>
#include <string>

namespace
{

constexpr int kFeatures = 6;

struct Volume
{
  std::array<int, 3> dims{ 0, 0, 0 };
  std::vector<float> values;       // voxels x kFeatures, x fastest
  std::vector<std::int64_t> blob;  // the rare bright voxels
  std::vector<unsigned char> foreground; // per voxel: 0 outside the ellipsoid (background)
  std::size_t voxels() const { return values.size() / kFeatures; }
  mcv::FeatureMatrix matrix() const { return { values.data(), voxels(), kFeatures }; }
};

// A multichannel-like volume: a background of three shared feature vectors outside an
// ellipsoid of smoothly varying "tissue" with a little noise, and a small bright blob
// (about 0.15 % of the voxels).
Volume syntheticVolume(std::array<int, 3> dims = { 40, 30, 20 })
{
  Volume v;
  v.dims = dims;
  std::mt19937 rng(5);
  std::uniform_real_distribution<float> noise(-0.02f, 0.02f);
  for (int k = 0; k < dims[2]; ++k)
  {
    for (int j = 0; j < dims[1]; ++j)
    {
      for (int i = 0; i < dims[0]; ++i)
      {
        const double x = (i - 0.5 * dims[0]) / (0.42 * dims[0]);
        const double y = (j - 0.5 * dims[1]) / (0.4 * dims[1]);
        const double z = (k - 0.5 * dims[2]) / (0.4 * dims[2]);
        const double bx = i - 0.72 * dims[0], by = j - 0.3 * dims[1], bz = k - 0.65 * dims[2];
        float f[kFeatures];
        if (bx * bx + by * by + bz * bz <= 4.0)
        {
          for (float& value : f)
          {
            value = 5.f + 10.f * noise(rng);
          }
          v.blob.push_back(static_cast<std::int64_t>(v.voxels()));
        }
        else if (x * x + y * y + z * z > 1.0)
        {
          v.foreground.push_back(0);
          const float level = 0.05f * static_cast<float>(i * 3 / dims[0]);
          f[0] = level;
          f[1] = 0.1f;
          f[2] = level;
          f[3] = 0.f;
          f[4] = 0.02f;
          f[5] = 0.f;
        }
        else
        {
          const double a = 0.5 + 0.4 * std::sin(i / 6.0) * std::cos(j / 5.0);
          const double b = 0.3 + 0.02 * k + 0.2 * std::cos(i / 7.0 + j / 9.0);
          f[0] = static_cast<float>(a) + noise(rng);
          f[1] = static_cast<float>(b) + noise(rng);
          f[2] = static_cast<float>(a * b) + noise(rng);
          f[3] = static_cast<float>(a - b) + noise(rng);
          f[4] = static_cast<float>(std::round(a * 8.0) / 8.0);
          f[5] = static_cast<float>(0.5 * z * z) + noise(rng);
        }
        v.foreground.resize(v.voxels() + 1, 1);
        v.values.insert(v.values.end(), f, f + kFeatures);
      }
    }
  }
  return v;
}

// vtkExtentTranslator::SplitExtent in BLOCK_MODE: the longest axis of the point extent is
// split recursively; the two halves share the layer they are split at.
std::array<int, 6> splitExtent(int piece, int pieces, std::array<int, 6> ext)
{
  while (pieces > 1)
  {
    const int size[3] = { ext[1] - ext[0], ext[3] - ext[2], ext[5] - ext[4] };
    int axis = -1;
    if (size[2] >= size[1] && size[2] >= size[0] && size[2] / 2 >= 1)
    {
      axis = 2;
    }
    else if (size[1] >= size[0] && size[1] / 2 >= 1)
    {
      axis = 1;
    }
    else if (size[0] / 2 >= 1)
    {
      axis = 0;
    }
    if (axis < 0)
    {
      return piece == 0 ? ext : std::array<int, 6>{ 0, -1, 0, -1, 0, -1 };
    }
    const int first = pieces / 2;
    const int mid = static_cast<int>(static_cast<long long>(size[axis]) * first / pieces) + ext[2 * axis];
    if (piece < first)
    {
      ext[2 * axis + 1] = mid;
      pieces = first;
    }
    else
    {
      ext[2 * axis] = mid;
      pieces -= first;
      piece -= first;
    }
  }
  return ext;
}

// One process's block: its piece grown by `ghost` layers (within the volume); it owns the
// piece minus the piece's upper boundary layer on each axis, unless that layer is the
// volume's last.
struct Block
{
  mcv::GridPiece piece;
  mcv::ImageGrid grid;
  std::vector<float> values;
  std::vector<std::int64_t> global; // per row
  std::vector<unsigned char> foreground; // per row
  mcv::FeatureMatrix matrix() const { return { values.empty() ? nullptr : values.data(), global.size(), kFeatures }; }
};

std::vector<Block> splitVolume(const Volume& v, int pieces, int ghost = 0)
{
  std::vector<Block> blocks;
  const std::array<int, 6> whole{ 0, v.dims[0] - 1, 0, v.dims[1] - 1, 0, v.dims[2] - 1 };
  for (int p = 0; p < pieces; ++p)
  {
    const std::array<int, 6> ext = splitExtent(p, pieces, whole);
    Block b;
    b.piece.wholeDims = v.dims;
    for (int a = 0; a < 3; ++a)
    {
      const int lo = std::max(whole[2 * a], ext[2 * a] - ghost);
      const int hi = std::min(whole[2 * a + 1], ext[2 * a + 1] + ghost);
      b.piece.offset[a] = lo;
      b.grid.dims[a] = hi - lo + 1;
      b.piece.ownedLo[a] = ext[2 * a] - lo;
      b.piece.ownedHi[a] = (ext[2 * a + 1] == whole[2 * a + 1] ? ext[2 * a + 1] : ext[2 * a + 1] - 1) - lo;
    }
    for (std::size_t r = 0; r < b.grid.voxelCount(); ++r)
    {
      const std::int64_t g = b.piece.globalIndex(static_cast<std::int64_t>(r), b.grid);
      b.global.push_back(g);
      b.values.insert(b.values.end(), v.values.begin() + g * kFeatures, v.values.begin() + (g + 1) * kFeatures);
      b.foreground.push_back(v.foreground[static_cast<std::size_t>(g)]);
    }
    blocks.push_back(std::move(b));
  }
  return blocks;
}

// Every block reduced by its own thread-rank (with its part of the foreground mask when
// options.sampleMask is set).
std::vector<mcv::ReductionResult> reduceSplit(const std::vector<Block>& blocks, const mcv::ReductionOptions& options)
{
  std::vector<mcv::ReductionResult> results(blocks.size());
  mcv::testing::ThreadGroup(static_cast<int>(blocks.size())).run([&](int rank, const mcv::Communicator& comm) {
    mcv::ReductionOptions o = options;
    o.communicator = &comm;
    o.piece = blocks[static_cast<std::size_t>(rank)].piece;
    o.block = blocks[static_cast<std::size_t>(rank)].grid;
    if (options.sampleMask)
    {
      o.sampleMask = blocks[static_cast<std::size_t>(rank)].foreground.data();
    }
    results[static_cast<std::size_t>(rank)] = mcv::reduceDimension(blocks[static_cast<std::size_t>(rank)].matrix(), o);
  });
  return results;
}

mcv::ReductionOptions options(mcv::ReductionMethod method)
{
  mcv::ReductionOptions o;
  o.method = method;
  o.outputDimension = method == mcv::ReductionMethod::PCA ? 3 : 2;
  o.device = mcv::Device::CPU;
  o.numberOfNeighbors = 12;
  o.numberOfLandmarks = 100;
  o.referenceSampleSize = 1500;
  o.randomSeed = 17;
  o.trustworthinessSample = 800;
  return o;
}

// Every process's answer equals the serial one: sample, spectrum, trustworthiness, and the
// coordinates of every voxel of its block (shared and ghost voxels included).
void expectSameAsSerial(const mcv::ReductionResult& serial, const std::vector<Block>& blocks,
  const std::vector<mcv::ReductionResult>& parts)
{
  ASSERT_TRUE(serial.ok()) << serial.error;
  const int d = serial.outputDimension;
  const auto range = std::minmax_element(serial.coordinates.begin(), serial.coordinates.end());
  const double tolerance = 1e-5 * (*range.second - *range.first);
  for (std::size_t r = 0; r < parts.size(); ++r)
  {
    SCOPED_TRACE("rank " + std::to_string(r) + " of " + std::to_string(parts.size()));
    const mcv::ReductionResult& part = parts[r];
    ASSERT_TRUE(part.ok()) << part.error;
    EXPECT_EQ(part.referenceIndices, serial.referenceIndices);
    EXPECT_EQ(part.usedColumns, serial.usedColumns);
    EXPECT_EQ(part.eigenvalues, serial.eigenvalues);
    EXPECT_EQ(part.varianceRetained, serial.varianceRetained);
    EXPECT_EQ(part.trustworthiness, serial.trustworthiness);
    ASSERT_EQ(part.coordinates.size(), blocks[r].global.size() * static_cast<std::size_t>(d));
    double worst = 0;
    std::size_t differing = 0;
    for (std::size_t i = 0; i < blocks[r].global.size(); ++i)
    {
      const std::size_t g = static_cast<std::size_t>(blocks[r].global[i]);
      for (int c = 0; c < d; ++c)
      {
        const float mine = part.coordinates[i * d + c], expected = serial.coordinates[g * d + c];
        worst = std::max(worst, static_cast<double>(std::abs(mine - expected)));
        differing += mine != expected;
      }
    }
    EXPECT_LE(worst, tolerance) << differing << " coordinates differ from the serial run";
  }
}

bool hasVoxel(const std::vector<std::int64_t>& sorted, std::int64_t g)
{
  return std::binary_search(sorted.begin(), sorted.end(), g);
}

} // namespace

TEST(DistributedReduction, BlocksSplitLikeVtk)
{
  // The examples vtkExtentTranslator gives (BLOCK_MODE).
  const std::array<int, 6> cube{ 0, 9, 0, 9, 0, 9 };
  EXPECT_EQ(splitExtent(0, 3, cube), (std::array<int, 6>{ 0, 9, 0, 9, 0, 3 }));
  EXPECT_EQ(splitExtent(1, 3, cube), (std::array<int, 6>{ 0, 9, 0, 4, 3, 9 }));
  EXPECT_EQ(splitExtent(2, 3, cube), (std::array<int, 6>{ 0, 9, 4, 9, 3, 9 }));
  EXPECT_EQ(splitExtent(0, 2, cube), (std::array<int, 6>{ 0, 9, 0, 9, 0, 4 }));
  EXPECT_EQ(splitExtent(1, 2, cube), (std::array<int, 6>{ 0, 9, 0, 9, 4, 9 }));
  // Owned voxels tile the volume: each exactly once, with or without ghosts.
  const Volume v = syntheticVolume();
  for (int ghost : { 0, 1 })
  {
    for (int pieces : { 2, 3, 4 })
    {
      std::vector<int> owners(v.voxels(), 0);
      for (const Block& b : splitVolume(v, pieces, ghost))
      {
        for (std::size_t r = 0; r < b.global.size(); ++r)
        {
          const std::int64_t nx = b.grid.dims[0], nxy = nx * b.grid.dims[1];
          const std::int64_t k = static_cast<std::int64_t>(r) / nxy, j = (static_cast<std::int64_t>(r) % nxy) / nx,
                             i = static_cast<std::int64_t>(r) % nx;
          owners[static_cast<std::size_t>(b.global[r])] += b.piece.owns(static_cast<int>(i), static_cast<int>(j), static_cast<int>(k));
        }
      }
      EXPECT_EQ(std::count(owners.begin(), owners.end(), 1), static_cast<long>(v.voxels()))
        << pieces << " pieces, " << ghost << " ghost layers";
    }
  }
}

TEST(DistributedReduction, SameAnswerAsSerial)
{
  const Volume v = syntheticVolume();
  for (auto method : { mcv::ReductionMethod::PCA, mcv::ReductionMethod::Isomap, mcv::ReductionMethod::LLE,
         mcv::ReductionMethod::UMAP })
  {
    const mcv::ReductionOptions o = options(method);
    const mcv::ReductionResult serial = mcv::reduceDimension(v.matrix(), o);
    ASSERT_TRUE(serial.ok()) << serial.error;
    ASSERT_EQ(serial.referenceIndices.size(), o.referenceSampleSize);
    for (int pieces : { 2, 3 })
    {
      for (int ghost : { 0, 1 })
      {
        const char* names[] = { "PCA", "Isomap", "LLE", "UMAP" };
        SCOPED_TRACE(std::string(names[static_cast<int>(method)]) +
          ", " + std::to_string(pieces) + " pieces, " + std::to_string(ghost) + " ghost layers");
        const std::vector<Block> blocks = splitVolume(v, pieces, ghost);
        expectSameAsSerial(serial, blocks, reduceSplit(blocks, o));
      }
    }
  }
}

TEST(DistributedReduction, ForegroundMaskKeepsTheSampleOffTheBackground)
{
  // The background (three shared vectors outside the ellipsoid, most of the volume) is
  // masked: no reference voxel is a background voxel, every voxel is still placed, and a
  // split run draws the same sample as one process.
  const Volume v = syntheticVolume();
  const std::size_t foreground = static_cast<std::size_t>(std::count(v.foreground.begin(), v.foreground.end(), 1));
  ASSERT_GT(foreground, 3000u);
  ASSERT_LT(foreground, v.voxels() / 2);
  for (auto method : { mcv::ReductionMethod::PCA, mcv::ReductionMethod::Isomap })
  {
    mcv::ReductionOptions o = options(method);
    o.sampleMask = v.foreground.data();
    const mcv::ReductionResult serial = mcv::reduceDimension(v.matrix(), o);
    ASSERT_TRUE(serial.ok()) << serial.error;
    EXPECT_EQ(serial.sampledVoxels, foreground);
    ASSERT_EQ(serial.referenceIndices.size(), o.referenceSampleSize);
    for (std::int64_t g : serial.referenceIndices)
    {
      ASSERT_EQ(v.foreground[static_cast<std::size_t>(g)], 1) << "voxel " << g << " is background";
    }
    EXPECT_TRUE(std::all_of(serial.coordinates.begin(), serial.coordinates.end(), [](float c) { return std::isfinite(c); }));
    EXPECT_EQ(serial.coordinates.size(), v.voxels() * static_cast<std::size_t>(serial.outputDimension));
    // Without the mask the same seed draws background voxels (the mask is what keeps them out).
    o.sampleMask = nullptr;
    const mcv::ReductionResult unmasked = mcv::reduceDimension(v.matrix(), o);
    ASSERT_TRUE(unmasked.ok()) << unmasked.error;
    EXPECT_TRUE(std::any_of(unmasked.referenceIndices.begin(), unmasked.referenceIndices.end(),
      [&](std::int64_t g) { return v.foreground[static_cast<std::size_t>(g)] == 0; }));
    o.sampleMask = v.foreground.data();
    for (int pieces : { 2, 3 })
    {
      SCOPED_TRACE(std::to_string(pieces) + " pieces");
      const std::vector<Block> blocks = splitVolume(v, pieces, 1);
      expectSameAsSerial(serial, blocks, reduceSplit(blocks, o));
    }
  }
}

TEST(DistributedReduction, ForegroundMaskWithFewOrNoForegroundVoxels)
{
  const Volume v = syntheticVolume();
  const std::size_t foreground = static_cast<std::size_t>(std::count(v.foreground.begin(), v.foreground.end(), 1));
  // More asked for than there are foreground voxels: all of them (their distinct vectors).
  mcv::ReductionOptions o = options(mcv::ReductionMethod::PCA);
  o.sampleMask = v.foreground.data();
  o.referenceSampleSize = v.voxels();
  const mcv::ReductionResult all = mcv::reduceDimension(v.matrix(), o);
  ASSERT_TRUE(all.ok()) << all.error;
  EXPECT_LE(all.referenceIndices.size(), foreground);
  EXPECT_GT(all.referenceIndices.size(), foreground * 9 / 10);
  for (std::int64_t g : all.referenceIndices)
  {
    ASSERT_EQ(v.foreground[static_cast<std::size_t>(g)], 1);
  }
  const auto mentions = [](const mcv::ReductionResult& r, const char* text) {
    return std::any_of(r.warnings.begin(), r.warnings.end(), [&](const std::string& w) { return w.find(text) != std::string::npos; });
  };
  EXPECT_TRUE(mentions(all, "exceeds the number of foreground voxels"));

  // A mask with no foreground at all: ignored, with a warning, on every process alike.
  const std::vector<unsigned char> none(v.voxels(), 0);
  o = options(mcv::ReductionMethod::PCA);
  o.sampleMask = none.data();
  const mcv::ReductionResult ignored = mcv::reduceDimension(v.matrix(), o);
  ASSERT_TRUE(ignored.ok()) << ignored.error;
  EXPECT_TRUE(mentions(ignored, "marks no voxel"));
  EXPECT_EQ(ignored.sampledVoxels, v.voxels());
  o.sampleMask = nullptr;
  EXPECT_EQ(ignored.referenceIndices, mcv::reduceDimension(v.matrix(), o).referenceIndices);
}

TEST(DistributedReduction, PlainRowsFollowOneAnotherInRankOrder)
{
  // No grid: each process passes a run of rows, unevenly sized; global index = rows of the
  // lower ranks + row. One process has no rows at all.
  const Volume v = syntheticVolume({ 24, 20, 12 });
  const mcv::ReductionOptions o = options(mcv::ReductionMethod::Isomap);
  const mcv::ReductionResult serial = mcv::reduceDimension(v.matrix(), o);
  const std::vector<std::size_t> counts{ 700, 0, 3000, v.voxels() - 3700 };
  std::vector<Block> blocks(counts.size());
  std::size_t first = 0;
  for (std::size_t r = 0; r < counts.size(); ++r)
  {
    for (std::size_t i = first; i < first + counts[r]; ++i)
    {
      blocks[r].global.push_back(static_cast<std::int64_t>(i));
    }
    blocks[r].values.assign(v.values.begin() + first * kFeatures, v.values.begin() + (first + counts[r]) * kFeatures);
    first += counts[r];
  }
  std::vector<mcv::ReductionResult> parts(blocks.size());
  mcv::testing::ThreadGroup(static_cast<int>(blocks.size())).run([&](int rank, const mcv::Communicator& comm) {
    mcv::ReductionOptions mine = o;
    mine.communicator = &comm;
    parts[static_cast<std::size_t>(rank)] = mcv::reduceDimension(blocks[static_cast<std::size_t>(rank)].matrix(), mine);
  });
  expectSameAsSerial(serial, blocks, parts);
}

TEST(DistributedReduction, SampleIsTheSameForAnySplit)
{
  // Small samples (the merge must ask for more candidates where duplicates crowd the lowest
  // keys), the usual size, and all voxels or more (every distinct vector: one process takes
  // a shortcut there, the split ones the stratified draw).
  const Volume v = syntheticVolume();
  std::set<std::vector<float>> distinct;
  for (std::size_t i = 0; i < v.voxels(); ++i)
  {
    distinct.insert(std::vector<float>(v.values.begin() + i * kFeatures, v.values.begin() + (i + 1) * kFeatures));
  }
  ASSERT_LT(distinct.size(), v.voxels() * 9 / 10) << "the volume should share feature vectors";
  const std::vector<double> center(kFeatures, 0.3);
  for (std::size_t size : { std::size_t(20), std::size_t(300), std::size_t(3000), v.voxels(), v.voxels() + 1 })
  {
    mcv::ReferenceSampleOptions so;
    so.size = size;
    so.seed = 3;
    const mcv::ReferenceSample serial =
      mcv::drawReferenceSample(v.values.data(), kFeatures, mcv::RowLayout::plain(v.voxels()), {}, center, so, nullptr);
    ASSERT_TRUE(serial.error.empty()) << serial.error;
    EXPECT_EQ(serial.indices.size(), std::min(size, distinct.size()));
    EXPECT_TRUE(std::is_sorted(serial.indices.begin(), serial.indices.end()));
    std::set<std::vector<float>> drawn;
    for (std::size_t i = 0; i < serial.indices.size(); ++i)
    {
      const auto row = v.values.begin() + serial.indices[i] * kFeatures;
      const std::vector<float> vec(row, row + kFeatures);
      EXPECT_EQ(vec, std::vector<float>(serial.vectors.begin() + i * kFeatures, serial.vectors.begin() + (i + 1) * kFeatures));
      drawn.insert(vec);
    }
    EXPECT_EQ(drawn.size(), serial.indices.size()) << "duplicate vectors are drawn once";

    for (int pieces : { 2, 3, 5 })
    {
      const std::vector<Block> blocks = splitVolume(v, pieces, 1);
      std::vector<mcv::ReferenceSample> parts(blocks.size());
      mcv::testing::ThreadGroup(pieces).run([&](int rank, const mcv::Communicator& comm) {
        const Block& b = blocks[static_cast<std::size_t>(rank)];
        parts[static_cast<std::size_t>(rank)] = mcv::drawReferenceSample(
          b.values.data(), kFeatures, mcv::RowLayout::grid(b.piece, b.grid), {}, center, so, &comm);
      });
      for (const mcv::ReferenceSample& part : parts)
      {
        EXPECT_TRUE(part.error.empty()) << part.error;
        EXPECT_EQ(part.indices, serial.indices) << "size " << size << ", " << pieces << " pieces";
        EXPECT_EQ(part.vectors, serial.vectors) << "size " << size << ", " << pieces << " pieces";
      }
    }
  }
}

// RowLayout::runsWithin (the block passes visit only their block's runs): for every row
// range, exactly the runs holding one of its rows, checked against a scan of all runs, for
// plain rows and for an owned box inside a block with ghost layers on every side.
TEST(DistributedReduction, RunsWithinAreTheRunsHoldingTheRows)
{
  mcv::ImageGrid block;
  block.dims = { 7, 5, 6 };
  mcv::GridPiece piece;
  piece.wholeDims = { 20, 20, 20 };
  piece.ownedLo = { 1, 1, 2 };
  piece.ownedHi = { 5, 3, 4 };
  for (const mcv::RowLayout& rows : { mcv::RowLayout::plain(100000), mcv::RowLayout::grid(piece, block) })
  {
    const std::size_t n = rows.size();
    std::size_t checked = 0;
    for (std::size_t begin = 0; begin <= n; begin += (n > 1000 ? 997 : 1))
      for (std::size_t end = begin; end <= n; end += (n > 1000 ? 4999 : 1))
      {
        std::size_t first = rows.runCount(), last = 0;
        for (std::size_t r = 0; r < rows.runCount(); ++r)
        {
          const mcv::RowLayout::Run run = rows.run(r);
          if (std::max(run.row, begin) < std::min(run.row + run.count, end)) // a row in both
          {
            first = std::min(first, r);
            last = r + 1;
          }
        }
        const std::pair<std::size_t, std::size_t> got = rows.runsWithin(begin, end);
        if (last == 0) // no run: an empty range
          EXPECT_EQ(got.first, got.second) << begin << ".." << end;
        else
          EXPECT_EQ(got, std::make_pair(first, last)) << begin << ".." << end;
        ++checked;
      }
    EXPECT_GT(checked, 1000u);
  }
  // The owned box's second run is its line j = 2, k = 2: rows 2 * 35 + 2 * 7 + 1 = 85 .. 89.
  const mcv::RowLayout grid = mcv::RowLayout::grid(piece, block);
  EXPECT_EQ(grid.runsWithin(85, 90), std::make_pair(std::size_t(1), std::size_t(2)));
  EXPECT_EQ(grid.runsWithin(90, 92), std::make_pair(std::size_t(2), std::size_t(2)));
}

TEST(DistributedReduction, SampleKeepsTheRareBrightBlob)
{
  // About 30 bright voxels among some 7000 distinct vectors: a uniform sample of 1000 holds
  // about 4 of them; the norm-stratified one puts them in the top stratum (1/128 of the
  // voxels), which gets 1/16 of the sample, so about 9. Summed over seeds, so that the
  // comparison is not one draw's luck.
  const Volume v = syntheticVolume();
  ASSERT_GE(v.blob.size(), 25u);
  const std::vector<Block> blocks = splitVolume(v, 3);
  auto countBlob = [&](double stratifiedFraction, std::uint64_t seed) {
    mcv::ReferenceSampleOptions so;
    so.size = 1000;
    so.seed = seed;
    so.stratifiedFraction = stratifiedFraction;
    std::vector<mcv::ReferenceSample> parts(blocks.size());
    mcv::testing::ThreadGroup(3).run([&](int rank, const mcv::Communicator& comm) {
      const Block& b = blocks[static_cast<std::size_t>(rank)];
      parts[static_cast<std::size_t>(rank)] = mcv::drawReferenceSample(
        b.values.data(), kFeatures, mcv::RowLayout::grid(b.piece, b.grid), {}, {}, so, &comm);
    });
    std::size_t n = 0;
    for (std::int64_t g : v.blob)
    {
      n += hasVoxel(parts[0].indices, g);
    }
    return n;
  };
  std::size_t stratified = 0, uniform = 0;
  for (std::uint64_t seed = 0; seed < 6; ++seed)
  {
    const std::size_t once = countBlob(0.5, seed);
    EXPECT_GE(once, 4u) << "seed " << seed;
    stratified += once;
    uniform += countBlob(0.0, seed);
  }
  EXPECT_GE(stratified, 6u * 7u);
  EXPECT_GE(2 * stratified, 3 * uniform) << "uniform samples: " << uniform;
}

TEST(DistributedReduction, NonFiniteValueInOneBlockGivesTheSameErrorEverywhere)
{
  Volume v = syntheticVolume();
  // One NaN deep in the last piece, one Inf in a boundary layer two pieces share (counted
  // once: it is owned once).
  const std::int64_t deep = v.voxels() - 3, shared = 40 * 30 * 9 + 40 * 14 + 7;
  v.values[deep * kFeatures + 4] = std::numeric_limits<float>::quiet_NaN();
  v.values[shared * kFeatures + 1] = std::numeric_limits<float>::infinity();
  const mcv::ReductionOptions o = options(mcv::ReductionMethod::Isomap);
  const mcv::ReductionResult serial = mcv::reduceDimension(v.matrix(), o);
  ASSERT_FALSE(serial.ok());
  EXPECT_NE(serial.error.find("2 non-finite"), std::string::npos) << serial.error;
  EXPECT_NE(serial.error.find("voxel " + std::to_string(shared) + ", component 1"), std::string::npos) << serial.error;
  for (int pieces : { 2, 3 })
  {
    const std::vector<Block> blocks = splitVolume(v, pieces, 1);
    for (const mcv::ReductionResult& part : reduceSplit(blocks, o))
    {
      EXPECT_EQ(part.error, serial.error) << pieces << " pieces";
      EXPECT_TRUE(part.coordinates.empty());
    }
  }
}

TEST(DistributedReduction, BadBlockOnOneProcessStopsAll)
{
  // Process 1 describes its block wrongly: all processes return its error instead of the
  // others waiting for it in a collective step.
  const Volume v = syntheticVolume();
  std::vector<Block> blocks = splitVolume(v, 3);
  blocks[1].grid.dims[0] -= 1;
  const std::vector<mcv::ReductionResult> parts = reduceSplit(blocks, options(mcv::ReductionMethod::PCA));
  for (const mcv::ReductionResult& part : parts)
  {
    EXPECT_FALSE(part.ok());
    EXPECT_EQ(part.error, parts[0].error);
  }
  EXPECT_NE(parts[0].error.find("Process 1 of 3"), std::string::npos) << parts[0].error;
  EXPECT_NE(parts[0].error.find("does not match"), std::string::npos) << parts[0].error;

  // Owned regions that overlap: caught by the global voxel count.
  blocks = splitVolume(v, 2);
  blocks[0].piece.ownedHi[0] += 1; // the first piece's upper layer, owned by the second too
  for (const mcv::ReductionResult& part : reduceSplit(blocks, options(mcv::ReductionMethod::PCA)))
  {
    EXPECT_NE(part.error.find("owned by exactly one process"), std::string::npos) << part.error;
  }
}
