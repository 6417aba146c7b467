// Exact kNN of the out-of-sample placement: the kd-tree and the tiled brute force pick the
// same neighbours (and so the same coordinates, bit for bit) as a plain full scan, on random
// data (6D, 24D), on data full of exact distance ties, and on the real brain features.
#include "BrainFeatures.h"
#include "OutOfSampleData.h"
#include "ExactKnn.h"
#include "OutOfSample.h"
#include "ReferenceSample.h"
#include "TiledKnn.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <numeric>
#include <random>

namespace
{
namespace mt = mcv::testing;

// The reference answer: every reference, distances in long double (independent of the
// library's double rule; on random data no two distances are within double rounding).
std::vector<std::uint32_t> naiveKnn(const float* refs, std::size_t M, int D, const float* q, int k, bool longDouble)
{
  std::vector<std::pair<long double, std::uint32_t>> all(M);
  for (std::size_t j = 0; j < M; ++j)
  {
    long double s = 0;
    if (longDouble)
    {
      for (int c = 0; c < D; ++c)
      {
        const long double t = static_cast<long double>(q[c]) - static_cast<long double>(refs[j * D + c]);
        s += t * t;
      }
    }
    else
    {
      s = mcv::canonicalSquaredDistance(q, refs + j * D, D);
    }
    all[j] = { s, static_cast<std::uint32_t>(j) };
  }
  std::partial_sort(all.begin(), all.begin() + k, all.end());
  std::vector<std::uint32_t> out(static_cast<std::size_t>(k));
  for (int j = 0; j < k; ++j)
  {
    out[static_cast<std::size_t>(j)] = all[static_cast<std::size_t>(j)].second;
  }
  return out;
}

struct Placed
{
  std::vector<float> y;
  std::vector<std::uint32_t> nb;
  mcv::OutOfSampleReport report;
};

Placed place(const mcv::RowMatrixF& refX, const mcv::RowMatrixF& refY, const std::vector<float>& rows, int dim,
  const std::vector<int>& columns, mcv::KnnMethod method)
{
  const std::size_t n = rows.size() / static_cast<std::size_t>(dim);
  Placed p;
  p.y.assign(n * refY.cols(), 0.f);
  p.nb.assign(n * 3, 0);
  mcv::OutOfSampleOptions o;
  o.knn = method;
  p.report = mcv::placeOutOfSample(refX, refY, rows.data(), n, dim, columns, p.y.data(), o, p.nb.data());
  return p;
}

using mt::randomMatrix;

// Both backends against the naive scan; coordinates equal bit for bit between backends.
void expectSameAsNaive(const mcv::RowMatrixF& refX, const mcv::RowMatrixF& refY, const std::vector<float>& rows,
  bool longDouble, std::size_t* scans = nullptr)
{
  const int D = static_cast<int>(refX.cols());
  const std::size_t n = rows.size() / D;
  const Placed kd = place(refX, refY, rows, D, {}, mcv::KnnMethod::KdTree);
  const Placed bf = place(refX, refY, rows, D, {}, mcv::KnnMethod::BruteForce);
  EXPECT_EQ(kd.report.knnUsed, mcv::KnnMethod::KdTree);
  EXPECT_EQ(bf.report.knnUsed, mcv::KnnMethod::BruteForce);
  std::size_t wrongKd = 0, wrongBf = 0;
  for (std::size_t i = 0; i < n; ++i)
  {
    const auto want = naiveKnn(refX.data(), refX.rows(), D, rows.data() + i * D, 3, longDouble);
    wrongKd += !std::equal(want.begin(), want.end(), kd.nb.begin() + i * 3);
    wrongBf += !std::equal(want.begin(), want.end(), bf.nb.begin() + i * 3);
  }
  EXPECT_EQ(wrongKd, 0u) << "kd-tree rows whose neighbours differ from the full scan";
  EXPECT_EQ(wrongBf, 0u) << "brute-force rows whose neighbours differ from the full scan";
  EXPECT_TRUE(kd.y == bf.y) << "same neighbours must give the same coordinates, bit for bit";
  if (scans)
  {
    *scans = kd.report.radiusScans + bf.report.radiusScans;
  }
}

} // namespace

TEST(OutOfSample, TiledCandidatesAreTheFloatNearest)
{
  std::mt19937 rng(5);
  const mcv::RowMatrixF refs = randomMatrix(1003, 13, rng); // not a multiple of the blocks
  const mcv::RowMatrixF qs = randomMatrix(7, 13, rng);
  const mcv::TiledKnn t(refs.data(), 1003, 13);
  std::vector<std::uint32_t> ci(7 * 6);
  std::vector<float> cf(7 * 6);
  t.candidates(qs.data(), 7, 6, ci.data(), cf.data());
  std::vector<float> all(1003);
  for (int q = 0; q < 7; ++q)
  {
    t.distances(qs.data() + q * 13, all.data());
    std::vector<std::uint32_t> order(1003);
    std::iota(order.begin(), order.end(), 0u);
    std::stable_sort(order.begin(), order.end(), [&](std::uint32_t a, std::uint32_t b) { return all[a] < all[b]; });
    for (int s = 0; s < 6; ++s)
    {
      EXPECT_EQ(ci[q * 6 + s], order[s]) << "query " << q << " slot " << s;
      EXPECT_NEAR(cf[q * 6 + s], all[order[s]], 1e-5f * all[order[s]]);
    }
  }
  // More candidates than references: the rest are marked empty.
  std::vector<std::uint32_t> ci2(9);
  std::vector<float> cf2(9);
  const mcv::TiledKnn few(refs.data(), 4, 13);
  few.candidates(qs.data(), 1, 9, ci2.data(), cf2.data());
  for (int s = 0; s < 9; ++s)
  {
    EXPECT_EQ(ci2[s] == std::numeric_limits<std::uint32_t>::max(), s >= 4);
  }
}

TEST(OutOfSample, BruteForceAndKdTreeAgreeOnRandomData)
{
  for (int D : { 6, 24 })
  {
    SCOPED_TRACE("D = " + std::to_string(D));
    std::mt19937 rng(11 + D);
    const mcv::RowMatrixF refX = randomMatrix(3000, D, rng);
    const mcv::RowMatrixF refY = randomMatrix(3000, 3, rng);
    const mcv::RowMatrixF q = randomMatrix(3000, D, rng);
    std::vector<float> rows(q.data(), q.data() + q.size());
    // Some rows are reference points: they must land on their own embedding exactly.
    rows.insert(rows.end(), refX.data(), refX.data() + 200 * D);
    expectSameAsNaive(refX, refY, rows, true);
    const Placed bf = place(refX, refY, rows, D, {}, mcv::KnnMethod::BruteForce);
    for (int i = 0; i < 200; ++i)
    {
      for (int c = 0; c < 3; ++c)
      {
        EXPECT_EQ(bf.y[(3000 + i) * 3 + c], refY(i, c));
      }
    }
  }
}

TEST(OutOfSample, ExactTiesBreakByIndexOnEveryBackend)
{
  // Points of the integer lattice {0,1,2}^6: distances are small integers, so most queries
  // have many references at exactly the same distance; the float candidates cannot settle
  // those and the radius scan must.
  // Distinct references: a shuffled half of the lattice; queries on the half-integer
  // lattice (0, 0.5, 1): more ties.
  const mt::LatticeTies ties = mt::latticeTies(3, 360, 2000, 2, 2);
  std::size_t scans = 0;
  expectSameAsNaive(ties.refX, ties.refY, ties.rows, true, &scans);
  EXPECT_GT(scans, 100u) << "the tie case should exercise the radius scan";
}

TEST(OutOfSample, ColumnSelectionGathersTheUsedFeatures)
{
  std::mt19937 rng(8);
  const mcv::RowMatrixF refX = randomMatrix(500, 12, rng);
  const mcv::RowMatrixF refY = randomMatrix(500, 3, rng);
  const mcv::RowMatrixF q = randomMatrix(400, 12, rng);
  // The same rows inside a wider matrix (columns 0, 2, ..., 22 of 24).
  std::vector<float> wide(400 * 24, 99.f);
  std::vector<int> columns;
  for (int c = 0; c < 12; ++c)
  {
    columns.push_back(2 * c);
  }
  for (int i = 0; i < 400; ++i)
  {
    for (int c = 0; c < 12; ++c)
    {
      wide[i * 24 + 2 * c] = q(i, c);
    }
  }
  const std::vector<float> narrow(q.data(), q.data() + q.size());
  for (auto m : { mcv::KnnMethod::KdTree, mcv::KnnMethod::BruteForce })
  {
    const Placed a = place(refX, refY, narrow, 12, {}, m);
    const Placed b = place(refX, refY, wide, 24, columns, m);
    EXPECT_TRUE(a.y == b.y);
    EXPECT_TRUE(a.nb == b.nb);
  }
}

TEST(OutOfSample, AutoPicksBruteForceInHighDimension)
{
  EXPECT_EQ(mcv::chooseKnnMethod(6), mcv::KnnMethod::KdTree);
  EXPECT_EQ(mcv::chooseKnnMethod(24), mcv::KnnMethod::BruteForce);
}

TEST(OutOfSample, BruteForceAndKdTreeAgreeOnBrainFeatures)
{
  if (!mt::haveBrain())
  {
    GTEST_SKIP() << "Colin27 volumes missing (scripts/fetch-data.sh)";
  }
  // A central box of the real brain (about 0.5 M voxels: cortex, white matter, background).
  const auto ch = mt::cropBrain(mt::loadBrain(), { 40, 50, 60 }, { 140, 150, 110 });
  for (auto preset : { mcv::FeaturePreset::SixD, mcv::FeaturePreset::TwentyFourD })
  {
    const auto f = mt::brainFeatures(ch, preset, mcv::Device::CPU);
    ASSERT_TRUE(f.result.ok()) << f.result.error;
    const int D = f.cols;
    SCOPED_TRACE("D = " + std::to_string(D));
    const mcv::RowMatrixF refX = mt::referenceSampleRows(f, 3000);
    std::mt19937 rng(4);
    const mcv::RowMatrixF refY = randomMatrix(static_cast<std::size_t>(refX.rows()), 3, rng);
    // Every 97th voxel (4 quarters of the box and its background).
    std::vector<float> rows;
    for (std::size_t i = 0; i < f.rows; i += 97)
    {
      rows.insert(rows.end(), f.values.begin() + i * D, f.values.begin() + (i + 1) * D);
    }
    // Quantised label channels: exact ties are real here, so the reference is the rule itself.
    expectSameAsNaive(refX, refY, rows, false);
  }
}

TEST(OutOfSample, RunsOfEqualRowsArePlacedLikeSingleRows)
{
  // Rows repeated in runs of 1..300 (across the 256-row blocks, some with a column that is
  // not used), and the same distinct rows placed one by one: equal results, bit for bit.
  std::mt19937 rng(9);
  const mcv::RowMatrixF refX = randomMatrix(400, 8, rng);
  const mcv::RowMatrixF refY = randomMatrix(400, 3, rng);
  const mcv::RowMatrixF distinct = randomMatrix(40, 9, rng);
  std::uniform_int_distribution<int> runLength(1, 300);
  std::vector<float> runs, singles;
  std::vector<std::size_t> source;
  for (Eigen::Index i = 0; i < distinct.rows(); ++i)
  {
    singles.insert(singles.end(), distinct.row(i).data(), distinct.row(i).data() + 9);
    const int length = runLength(rng);
    for (int r = 0; r < length; ++r)
    {
      runs.insert(runs.end(), distinct.row(i).data(), distinct.row(i).data() + 9);
      runs.back() = static_cast<float>(r); // the unused 9th column differs along the run
      source.push_back(static_cast<std::size_t>(i));
    }
  }
  const std::vector<int> columns = { 0, 1, 2, 3, 4, 5, 6, 7 };
  for (mcv::KnnMethod method : { mcv::KnnMethod::KdTree, mcv::KnnMethod::BruteForce })
  {
    SCOPED_TRACE(mcv::knnMethodName(method));
    const Placed one = place(refX, refY, singles, 9, columns, method);
    const Placed all = place(refX, refY, runs, 9, columns, method);
    std::size_t differ = 0;
    for (std::size_t r = 0; r < source.size(); ++r)
    {
      const std::size_t i = source[r];
      differ += !std::equal(all.y.begin() + r * 3, all.y.begin() + (r + 1) * 3, one.y.begin() + i * 3) ||
        !std::equal(all.nb.begin() + r * 3, all.nb.begin() + (r + 1) * 3, one.nb.begin() + i * 3);
    }
    EXPECT_EQ(differ, 0u) << "rows of " << source.size() << " whose coordinates or neighbours differ";
  }
}
