// RowLayout::runsWithin: the runs that hold rows of a block, against a scan of every run,
// for a block of a split volume (owned box inside ghost layers) and for plain rows.
#include "ReferenceSample.h"

#include <gtest/gtest.h>

#include <random>
#include <utility>

namespace
{
// The runs [first, last) that hold a row of [begin, end), by looking at every run.
std::pair<std::size_t, std::size_t> scanRuns(const mcv::RowLayout& rows, std::size_t begin, std::size_t end)
{
  std::size_t first = rows.runCount(), last = 0;
  for (std::size_t r = 0; r < rows.runCount(); ++r)
  {
    const mcv::RowLayout::Run run = rows.run(r);
    if (run.row < end && run.row + run.count > begin)
    {
      first = std::min(first, r);
      last = r + 1;
    }
  }
  return first < last ? std::make_pair(first, last) : std::make_pair(std::size_t(0), std::size_t(0));
}

void expectSameRuns(const mcv::RowLayout& rows, std::size_t begin, std::size_t end)
{
  const std::pair<std::size_t, std::size_t> got = rows.runsWithin(begin, end);
  const std::pair<std::size_t, std::size_t> want = scanRuns(rows, begin, end);
  if (want.first == want.second)
  {
    EXPECT_EQ(got.first, got.second) << "rows [" << begin << ", " << end << ") hold no run";
  }
  else
  {
    EXPECT_EQ(got, want) << "rows [" << begin << ", " << end << ")";
  }
}
} // namespace

TEST(RowLayout, RunsWithinABlockOfASplitVolume)
{
  // A 9 x 7 x 11 block whose owned box leaves ghost layers on every side.
  mcv::ImageGrid block;
  block.dims = { 9, 7, 11 };
  mcv::GridPiece piece;
  piece.wholeDims = { 20, 20, 30 };
  piece.offset = { 3, 4, 5 };
  piece.ownedLo = { 1, 1, 2 };
  piece.ownedHi = { 7, 5, 9 };
  const mcv::RowLayout rows = mcv::RowLayout::grid(piece, block);
  const std::size_t n = block.voxelCount(), slice = 9 * 7;
  std::mt19937 random(3);
  for (int trial = 0; trial < 300; ++trial)
  {
    std::size_t a = random() % (n + 1), b = random() % (n + 1);
    expectSameRuns(rows, std::min(a, b), std::max(a, b));
  }
  for (std::size_t z = 0; z + 2 <= 11; ++z) // slabs of two slices, as FeatureBricks cuts them
  {
    expectSameRuns(rows, z * slice, (z + 2) * slice);
  }
}

TEST(RowLayout, RunsWithinPlainRows)
{
  const mcv::RowLayout rows = mcv::RowLayout::plain(100003, 17);
  std::mt19937 random(5);
  for (int trial = 0; trial < 300; ++trial)
  {
    std::size_t a = random() % 100004, b = random() % 100004;
    expectSameRuns(rows, std::min(a, b), std::max(a, b));
  }
  expectSameRuns(rows, 0, 100003);
}

TEST(RowLayout, TimeStepsRepeatTheBlock)
{
  // Three time steps of one 9 x 7 x 11 block: step s's runs are step 0's, shifted by s
  // blocks in rows and by s whole volumes in global indices; runsWithin still agrees with a
  // scan of every run.
  mcv::ImageGrid block;
  block.dims = { 9, 7, 11 };
  mcv::GridPiece piece;
  piece.wholeDims = { 20, 20, 30 };
  piece.offset = { 3, 4, 5 };
  piece.ownedLo = { 1, 1, 2 };
  piece.ownedHi = { 7, 5, 9 };
  const int steps = 3;
  const mcv::RowLayout one = mcv::RowLayout::grid(piece, block);
  const mcv::RowLayout three = mcv::RowLayout::grid(piece, block, steps);
  const std::size_t blockVoxels = block.voxelCount(), wholeVoxels = 20 * 20 * 30;
  ASSERT_EQ(three.size(), steps * blockVoxels);
  ASSERT_EQ(three.ownedCount(), steps * one.ownedCount());
  ASSERT_EQ(three.runCount(), steps * one.runCount());
  for (std::size_t r = 0; r < three.runCount(); ++r)
  {
    const std::size_t s = r / one.runCount();
    const mcv::RowLayout::Run base = one.run(r % one.runCount()), got = three.run(r);
    EXPECT_EQ(got.row, base.row + s * blockVoxels);
    EXPECT_EQ(got.global, base.global + static_cast<std::int64_t>(s * wholeVoxels));
    EXPECT_EQ(got.count, base.count);
  }
  std::mt19937 random(5);
  for (int trial = 0; trial < 300; ++trial)
  {
    std::size_t a = random() % (three.size() + 1), b = random() % (three.size() + 1);
    expectSameRuns(three, std::min(a, b), std::max(a, b));
  }
}
