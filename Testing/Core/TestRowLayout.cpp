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

// expectSameRuns on 300 random ranges of rows (seeded).
void expectSameRunsInRandomRanges(const mcv::RowLayout& rows, unsigned seed)
{
  std::mt19937 random(seed);
  for (int trial = 0; trial < 300; ++trial)
  {
    std::size_t a = random() % (rows.size() + 1), b = random() % (rows.size() + 1);
    expectSameRuns(rows, std::min(a, b), std::max(a, b));
  }
}

// A 9 x 7 x 11 block of a 20 x 20 x 30 volume whose owned box leaves ghost layers on
// every side.
struct SplitBlock
{
  mcv::ImageGrid block;
  mcv::GridPiece piece;
};

SplitBlock splitBlock()
{
  SplitBlock s;
  s.block.dims = { 9, 7, 11 };
  s.piece.wholeDims = { 20, 20, 30 };
  s.piece.offset = { 3, 4, 5 };
  s.piece.ownedLo = { 1, 1, 2 };
  s.piece.ownedHi = { 7, 5, 9 };
  return s;
}
} // namespace

TEST(RowLayout, RunsWithinABlockOfASplitVolume)
{
  const SplitBlock s = splitBlock();
  const mcv::RowLayout rows = mcv::RowLayout::grid(s.piece, s.block);
  ASSERT_EQ(rows.size(), s.block.voxelCount());
  const std::size_t slice = 9 * 7;
  expectSameRunsInRandomRanges(rows, 3);
  for (std::size_t z = 0; z + 2 <= 11; ++z) // slabs of two slices, as FeatureBricks cuts them
  {
    expectSameRuns(rows, z * slice, (z + 2) * slice);
  }
}

TEST(RowLayout, RunsWithinPlainRows)
{
  const mcv::RowLayout rows = mcv::RowLayout::plain(100003, 17);
  ASSERT_EQ(rows.size(), 100003u);
  expectSameRunsInRandomRanges(rows, 5);
  expectSameRuns(rows, 0, 100003);
}

TEST(RowLayout, TimeStepsRepeatTheBlock)
{
  // Three time steps of one 9 x 7 x 11 block: step s's runs are step 0's, shifted by s
  // blocks in rows and by s whole volumes in global indices; runsWithin still agrees with a
  // scan of every run.
  const SplitBlock s = splitBlock();
  const int steps = 3;
  const mcv::RowLayout one = mcv::RowLayout::grid(s.piece, s.block);
  const mcv::RowLayout three = mcv::RowLayout::grid(s.piece, s.block, steps);
  const std::size_t blockVoxels = s.block.voxelCount(), wholeVoxels = 20 * 20 * 30;
  ASSERT_EQ(three.size(), steps * blockVoxels);
  ASSERT_EQ(three.ownedCount(), steps * one.ownedCount());
  ASSERT_EQ(three.runCount(), steps * one.runCount());
  for (std::size_t r = 0; r < three.runCount(); ++r)
  {
    const std::size_t step = r / one.runCount();
    const mcv::RowLayout::Run base = one.run(r % one.runCount()), got = three.run(r);
    EXPECT_EQ(got.row, base.row + step * blockVoxels);
    EXPECT_EQ(got.global, base.global + static_cast<std::int64_t>(step * wholeVoxels));
    EXPECT_EQ(got.count, base.count);
  }
  expectSameRunsInRandomRanges(three, 5);
}
