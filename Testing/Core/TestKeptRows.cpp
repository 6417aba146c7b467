// A box of the block as the coordinates output (ReductionOptions::outputLo/outputHi, a
// split run's piece without its ghost layers): KeptRows' runs against a scan of every row,
// and the reduction's boxed output against the same rows of its whole-block output, for
// float32 and float16, PCA and Isomap.
#include "CpuReduction.h"
#include "DimensionReduction.h"
#include "KeptRows.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <random>
#include <vector>

namespace
{
const std::array<int, 3> kDims{ 10, 8, 10 };
const std::array<int, 3> kLo{ 2, 1, 3 };
const std::array<int, 3> kHi{ 7, 6, 9 };

bool inBox(int i, int j, int k)
{
  return i >= kLo[0] && i <= kHi[0] && j >= kLo[1] && j <= kHi[1] && k >= kLo[2] && k <= kHi[2];
}

// Output row of every block row (-1: not kept), by looking at each one.
std::vector<long> scanRows()
{
  std::vector<long> out;
  long next = 0;
  for (int k = 0; k < kDims[2]; ++k)
  {
    for (int j = 0; j < kDims[1]; ++j)
    {
      for (int i = 0; i < kDims[0]; ++i)
      {
        out.push_back(inBox(i, j, k) ? next++ : -1);
      }
    }
  }
  return out;
}

// 800 points of a noisy 3D curve, one per voxel of kDims.
std::vector<float> curve()
{
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  std::vector<float> x;
  for (int r = 0; r < kDims[0] * kDims[1] * kDims[2]; ++r)
  {
    const double t = 3.0 * M_PI * u(rng);
    x.insert(x.end(), { static_cast<float>(std::cos(t)), static_cast<float>(std::sin(t)),
                        static_cast<float>(0.3 * t + 0.05 * u(rng)) });
  }
  return x;
}

mcv::ReductionOptions onGrid(mcv::ReductionMethod method)
{
  mcv::ReductionOptions o = mcv::testing::cpuReduction(method, 3, 10, 60, 300);
  o.block.dims = kDims;
  o.piece = mcv::GridPiece::whole(o.block);
  return o;
}
} // namespace

TEST(KeptRows, RunsCoverTheBoxInOrder)
{
  const std::vector<long> expected = scanRows();
  const mcv::KeptRows kept(kDims, kLo, kHi);
  EXPECT_FALSE(kept.all());
  EXPECT_EQ(kept.rows(), std::size_t(6 * 6 * 7));
  for (std::size_t chunk : { std::size_t(1), std::size_t(7), std::size_t(33), expected.size() })
  {
    std::vector<long> got(expected.size(), -1);
    for (std::size_t begin = 0; begin < expected.size(); begin += chunk)
    {
      const std::size_t count = std::min(chunk, expected.size() - begin);
      kept.runs(begin, count, [&](std::size_t from, std::size_t to, std::size_t n) {
        ASSERT_GE(from, begin);
        ASSERT_LE(from + n, begin + count);
        for (std::size_t r = 0; r < n; ++r)
        {
          got[from + r] = static_cast<long>(to + r);
        }
      });
    }
    EXPECT_EQ(got, expected) << "chunks of " << chunk << " rows";
  }
}

TEST(KeptRows, WholeOrUnsetBoxKeepsEveryRowInPlace)
{
  const std::size_t rows = static_cast<std::size_t>(kDims[0] * kDims[1] * kDims[2]);
  for (const mcv::KeptRows& kept : { mcv::KeptRows(kDims, { 0, 0, 0 }, { 9, 7, 9 }),
         mcv::KeptRows(kDims, { 0, 0, 0 }, { -1, -1, -1 }), mcv::KeptRows(rows) })
  {
    EXPECT_TRUE(kept.all());
    EXPECT_EQ(kept.rows(), rows);
    int calls = 0;
    kept.runs(5, 20, [&](std::size_t from, std::size_t to, std::size_t n) {
      ++calls;
      EXPECT_EQ(from, std::size_t(5));
      EXPECT_EQ(to, std::size_t(5));
      EXPECT_EQ(n, std::size_t(20));
    });
    EXPECT_EQ(calls, 1);
  }
}

TEST(KeptRows, ReductionWritesTheBoxOnly)
{
  const std::vector<float> x = curve();
  const std::vector<long> where = scanRows();
  const mcv::FeatureMatrix features{ x.data(), where.size(), 3 };
  for (mcv::ReductionMethod method : { mcv::ReductionMethod::PCA, mcv::ReductionMethod::Isomap })
  {
    SCOPED_TRACE(method == mcv::ReductionMethod::PCA ? "PCA" : "Isomap");
    mcv::ReductionOptions o = onGrid(method);
    const mcv::ReductionResult whole = mcv::reduceDimension(features, o);
    ASSERT_TRUE(whole.ok()) << whole.error;
    ASSERT_EQ(whole.coordinates.size(), where.size() * 3);

    // float32, in result.coordinates and in the caller's buffer.
    o.outputLo = kLo;
    o.outputHi = kHi;
    const mcv::ReductionResult boxed = mcv::reduceDimension(features, o);
    ASSERT_TRUE(boxed.ok()) << boxed.error;
    ASSERT_EQ(boxed.coordinates.size(), std::size_t(6 * 6 * 7 * 3));
    std::vector<float> buffer(boxed.coordinates.size(), std::nanf(""));
    o.coordinatesOutput = buffer.data();
    ASSERT_TRUE(mcv::reduceDimension(features, o).ok());
    for (std::size_t r = 0; r < where.size(); ++r)
    {
      if (where[r] < 0)
      {
        continue;
      }
      for (int c = 0; c < 3; ++c)
      {
        const std::size_t to = static_cast<std::size_t>(where[r]) * 3 + static_cast<std::size_t>(c);
        ASSERT_EQ(boxed.coordinates[to], whole.coordinates[r * 3 + static_cast<std::size_t>(c)]) << "row " << r;
        ASSERT_EQ(buffer[to], whole.coordinates[r * 3 + static_cast<std::size_t>(c)]) << "row " << r;
      }
    }

    // float16: the box's halves are the whole block's halves of the same rows.
    o.coordinatesOutput = nullptr;
    std::vector<std::uint16_t> wholeHalves(where.size() * 3), boxHalves(6 * 6 * 7 * 3, 0xFFFF);
    mcv::ReductionOptions h = onGrid(method);
    h.coordinatesHalfOutput = wholeHalves.data();
    ASSERT_TRUE(mcv::reduceDimension(features, h).ok());
    o.coordinatesHalfOutput = boxHalves.data();
    ASSERT_TRUE(mcv::reduceDimension(features, o).ok());
    for (std::size_t r = 0; r < where.size(); ++r)
    {
      for (int c = 0; c < 3 && where[r] >= 0; ++c)
      {
        ASSERT_EQ(boxHalves[static_cast<std::size_t>(where[r]) * 3 + static_cast<std::size_t>(c)],
          wholeHalves[r * 3 + static_cast<std::size_t>(c)])
          << "row " << r;
      }
    }
  }
}

TEST(KeptRows, BoxOutsideTheBlockIsAnError)
{
  const std::vector<float> x = curve();
  const mcv::FeatureMatrix features{ x.data(), x.size() / 3, 3 };
  mcv::ReductionOptions o = onGrid(mcv::ReductionMethod::PCA);
  o.outputLo = { 0, 0, 0 };
  o.outputHi = { 9, 8, 9 }; // y beyond the block's 8 voxels
  const mcv::ReductionResult r = mcv::reduceDimension(features, o);
  EXPECT_NE(r.error.find("output box"), std::string::npos) << r.error;
}
