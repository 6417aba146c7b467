// UMAP (UMAPEmbedding.h) against known answers: umap-learn's curve parameters and smooth
// kNN distances, two separated blobs, the order along a curve, determinism, bad inputs.
#include "DimensionReduction.h"
#include "FeatureKnn.h"
#include "ModelDistance.h"
#include "OutOfSample.h"
#include "UMAPEmbedding.h"
#include "UMAPGraph.h"
#include "UMAPLayout.h"

#include <gtest/gtest.h>
#include <omp.h>

#include <Eigen/QR>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <numeric>
#include <random>

namespace
{

mcv::ReductionOptions umapOptions(int d = 3)
{
  mcv::ReductionOptions o;
  o.method = mcv::ReductionMethod::UMAP;
  o.outputDimension = d;
  o.numberOfNeighbors = 15;
  o.device = mcv::Device::CPU;
  o.trustworthinessSample = 0;
  return o;
}

// Two isotropic Gaussian blobs (sigma 1) in 10D whose centres are 20 apart: rows 0..n-1
// around centre A, n..2n-1 around centre B.
struct Blobs
{
  mcv::RowMatrixF X;
  mcv::RowMatrixF centres; // 2 x 10
};
Blobs twoBlobs(int n, unsigned seed)
{
  std::mt19937 rng(seed);
  std::normal_distribution<float> g(0.f, 1.f);
  Blobs b;
  b.centres = mcv::RowMatrixF::Zero(2, 10);
  b.centres(1, 0) = 20.f;
  b.X.resize(2 * n, 10);
  for (int i = 0; i < 2 * n; ++i)
  {
    for (int c = 0; c < 10; ++c)
    {
      b.X(i, c) = b.centres(i < n ? 0 : 1, c) + g(rng);
    }
  }
  return b;
}

// The indices of the k rows of Y nearest to y.
std::vector<int> nearestRows(const mcv::RowMatrixF& Y, const float* y, int k)
{
  std::vector<std::pair<float, int>> d;
  for (Eigen::Index i = 0; i < Y.rows(); ++i)
  {
    float s = 0;
    for (Eigen::Index c = 0; c < Y.cols(); ++c)
    {
      s += (Y(i, c) - y[c]) * (Y(i, c) - y[c]);
    }
    d.emplace_back(s, static_cast<int>(i));
  }
  std::partial_sort(d.begin(), d.begin() + k, d.end());
  std::vector<int> out;
  for (int j = 0; j < k; ++j)
  {
    out.push_back(d[j].second);
  }
  return out;
}

std::vector<double> ranks(const std::vector<double>& v)
{
  std::vector<int> order(v.size());
  std::iota(order.begin(), order.end(), 0);
  std::sort(order.begin(), order.end(), [&](int a, int b) { return v[a] < v[b]; });
  std::vector<double> r(v.size());
  for (std::size_t i = 0; i < order.size(); ++i)
  {
    r[order[i]] = static_cast<double>(i);
  }
  return r;
}

double spearman(const std::vector<double>& a, const std::vector<double>& b)
{
  const std::vector<double> ra = ranks(a), rb = ranks(b);
  const double n = static_cast<double>(a.size());
  double s = 0;
  for (std::size_t i = 0; i < a.size(); ++i)
  {
    s += (ra[i] - rb[i]) * (ra[i] - rb[i]);
  }
  return 1.0 - 6.0 * s / (n * (n * n - 1.0));
}

// Distance along the embedded curve from its first point: the path length in the minimum
// spanning tree of the embedded points (Prim, O(n^2)), which follows the curve where the
// embedding keeps it in one piece and jumps between pieces where it is torn, so a piece
// put back out of order breaks the ranking.
std::vector<double> alongEmbeddedCurve(const std::vector<float>& Y, std::size_t n, int d, std::size_t first)
{
  auto dist = [&](std::size_t i, std::size_t j) {
    double s = 0;
    for (int c = 0; c < d; ++c)
    {
      const double v = double(Y[i * d + c]) - Y[j * d + c];
      s += v * v;
    }
    return std::sqrt(s);
  };
  std::vector<double> best(n, std::numeric_limits<double>::infinity()), along(n, 0.0);
  std::vector<std::size_t> parent(n, first);
  std::vector<bool> in(n, false);
  best[first] = 0;
  for (std::size_t step = 0; step < n; ++step)
  {
    std::size_t u = n;
    for (std::size_t i = 0; i < n; ++i)
    {
      if (!in[i] && (u == n || best[i] < best[u]))
      {
        u = i;
      }
    }
    in[u] = true;
    along[u] = u == first ? 0.0 : along[parent[u]] + best[u]; // the parent joined earlier
    for (std::size_t v = 0; v < n; ++v)
    {
      if (!in[v] && dist(u, v) < best[v])
      {
        best[v] = dist(u, v);
        parent[v] = u;
      }
    }
  }
  return along;
}

} // namespace

TEST(UMAP, CurveParametersMatchUmapLearn)
{
  // umap-learn 0.5.3's find_ab_params(1.0, min_dist) (scipy curve_fit).
  const double expected[][3] = { { 0.0, 1.9328083975546724, 0.7904949734010681 },
    { 0.1, 1.5769434601962196, 0.8950608779914887 }, { 0.5, 0.583030020479462, 1.3341669929263487 },
    { 1.0, 0.11497568285252263, 1.9292371466948077 } };
  for (const auto& e : expected)
  {
    SCOPED_TRACE(e[0]);
    const mcv::CurveParameters c = mcv::fitCurveParameters(e[0]);
    EXPECT_TRUE(c.converged);
    EXPECT_NEAR(c.a, e[1], 1e-5 * e[1]);
    EXPECT_NEAR(c.b, e[2], 1e-5 * e[2]);
  }
}

TEST(UMAP, SmoothKnnDistancesReachTheTarget)
{
  // Rows of sorted distances, one starting with a duplicate (distance 0).
  const int K = 14;
  std::mt19937 rng(3);
  std::uniform_real_distribution<float> u(0.5f, 3.f);
  std::vector<float> d;
  for (int i = 0; i < 50; ++i)
  {
    std::vector<float> row(K);
    for (float& v : row)
    {
      v = u(rng);
    }
    std::sort(row.begin(), row.end());
    if (i == 0)
    {
      row[0] = 0.f;
    }
    d.insert(d.end(), row.begin(), row.end());
  }
  std::vector<float> sigma(50), rho(50);
  mcv::smoothKnnDistances(d.data(), 50, K, sigma.data(), rho.data());
  for (int i = 0; i < 50; ++i)
  {
    const float* row = d.data() + i * K;
    EXPECT_EQ(rho[i], i == 0 ? row[1] : row[0]); // the nearest non-zero distance
    double s = 0;
    for (int j = 0; j < K; ++j)
    {
      s += row[j] > rho[i] ? std::exp(-(row[j] - rho[i]) / sigma[i]) : 1.0;
    }
    EXPECT_NEAR(s, std::log2(K + 1.0), 1e-3); // umap-learn's target, log2(n_neighbors)
  }
}

TEST(UMAP, FuzzyUnionIsSymmetric)
{
  const Blobs b = twoBlobs(100, 4);
  const mcv::KnnGraph knn = mcv::buildKnnGraph(b.X.data(), 200, 10, 10);
  const mcv::FuzzyGraph g = mcv::fuzzySimplicialSet(knn);
  auto weight = [&](std::size_t i, std::uint32_t j) {
    for (std::size_t e = g.start[i]; e < g.start[i + 1]; ++e)
    {
      if (g.to[e] == j)
      {
        return g.weight[e];
      }
    }
    return 0.f;
  };
  for (std::size_t i = 0; i < 200; ++i)
  {
    for (int j = 0; j < 10; ++j)
    {
      EXPECT_GT(weight(i, knn.neighbors[i * 10 + j]), 0.f); // every kNN edge is kept
    }
    EXPECT_FLOAT_EQ(weight(i, knn.neighbors[i * 10]), 1.f); // the nearest: p = 1, union 1
    for (std::size_t e = g.start[i]; e < g.start[i + 1]; ++e)
    {
      EXPECT_NE(g.to[e], i);
      EXPECT_LE(g.weight[e], 1.f);
      EXPECT_EQ(g.weight[e], weight(g.to[e], static_cast<std::uint32_t>(i)));
    }
  }
}

TEST(UMAP, TwoBlobsStaySeparated)
{
  const int n = 300;
  const Blobs b = twoBlobs(n, 7);
  mcv::UMAPOptions o;
  const mcv::Embedding e = mcv::fitUMAP(b.X, o);
  ASSERT_TRUE(e.error.empty()) << e.error;
  ASSERT_EQ(e.coordinates.rows(), 2 * n);
  ASSERT_TRUE(e.coordinates.allFinite());
  // The blobs' centres placed as every voxel is (3 nearest reference vectors).
  std::vector<float> centres(6);
  mcv::placeOutOfSample(b.X, e.coordinates, b.centres.data(), 2, 10, {}, centres.data());
  for (int c = 0; c < 2; ++c)
  {
    for (const int i : nearestRows(e.coordinates, centres.data() + 3 * c, 10))
    {
      EXPECT_EQ(i < n ? 0 : 1, c) << "point " << i << " among the 10 nearest of centre " << c;
    }
  }
}

// The reference radius (ModelDistance.h) that UMAP's kNN graph finds on the way is the one
// referenceRadius searches for, bit for bit, with and without duplicate rows; where the
// graph cannot know it (its kd-tree in low dimension), the fit leaves it to referenceRadius.
TEST(UMAP, ReferenceRadiusFromTheGraphIsTheSearchedOne)
{
  const Blobs b = twoBlobs(300, 11);
  mcv::UMAPOptions o;
  o.numberOfEpochs = 5;
  mcv::RowMatrixF dup(400, 10);
  dup << b.X.topRows(200), b.X.topRows(200);
  for (const mcv::RowMatrixF* X : std::vector<const mcv::RowMatrixF*>{ &b.X, &dup })
  {
    const mcv::KnnGraph g = mcv::buildKnnGraph(X->data(), static_cast<std::size_t>(X->rows()), 10, 15);
    if (g.largestFourthSquaredDistance < 0)
    {
      GTEST_SKIP() << "the graph of 10D points came from the kd-tree here";
    }
    const mcv::Embedding e = mcv::fitUMAP(*X, o);
    ASSERT_TRUE(e.error.empty()) << e.error;
    EXPECT_EQ(e.referenceRadius, mcv::referenceRadius(*X)) << X->rows() << " rows";
    EXPECT_GT(e.referenceRadius, 0.0);
  }
  const mcv::RowMatrixF low = b.X.leftCols(2);
  const mcv::KnnGraph g = mcv::buildKnnGraph(low.data(), static_cast<std::size_t>(low.rows()), 2, 15);
  if (g.largestFourthSquaredDistance < 0)
  {
    EXPECT_EQ(mcv::fitUMAP(low, o).referenceRadius, -1.0);
  }
  else
  {
    EXPECT_EQ(mcv::fitUMAP(low, o).referenceRadius, mcv::referenceRadius(low));
  }
}

TEST(UMAP, PointsOnACurveKeepTheirOrder)
{
  // A helix (3 turns) embedded in 24D by a random orthonormal 24 x 3 map.
  const std::size_t n = 800;
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  std::normal_distribution<double> g(0.0, 1.0);
  Eigen::MatrixXd A(24, 3);
  for (Eigen::Index i = 0; i < A.size(); ++i)
  {
    A.data()[i] = g(rng);
  }
  const Eigen::MatrixXd Q = Eigen::HouseholderQR<Eigen::MatrixXd>(A).householderQ() * Eigen::MatrixXd::Identity(24, 3);
  std::vector<double> t(n);
  std::vector<float> x(n * 24);
  for (std::size_t i = 0; i < n; ++i)
  {
    t[i] = 6.0 * M_PI * u(rng);
    const Eigen::Vector3d p(std::cos(t[i]), std::sin(t[i]), 0.15 * t[i]);
    const Eigen::VectorXd q = Q * p;
    for (int c = 0; c < 24; ++c)
    {
      x[i * 24 + c] = static_cast<float>(q[c]);
    }
  }
  mcv::ReductionOptions o = umapOptions();
  o.referenceSampleSize = n;
  const mcv::ReductionResult r = mcv::reduceDimension({ x.data(), n, 24 }, o);
  ASSERT_TRUE(r.ok()) << r.error;
  const std::size_t first = static_cast<std::size_t>(std::min_element(t.begin(), t.end()) - t.begin());
  const double rho = spearman(t, alongEmbeddedCurve(r.coordinates, n, 3, first));
  RecordProperty("spearman", std::to_string(rho));
  EXPECT_GE(rho, 0.99);
}

TEST(UMAP, SameSeedSameResultForAnyThreadCount)
{
  const Blobs b = twoBlobs(250, 9);
  const int threads = omp_get_max_threads();
  std::vector<std::vector<float>> runs;
  for (int t : { 1, 1, 3 })
  {
    omp_set_num_threads(t);
    mcv::ReductionOptions o = umapOptions(2);
    o.randomSeed = 5;
    const mcv::ReductionResult r = mcv::reduceDimension({ b.X.data(), 500, 10 }, o);
    ASSERT_TRUE(r.ok()) << r.error;
    runs.push_back(r.coordinates);
  }
  omp_set_num_threads(threads);
  EXPECT_EQ(runs[0], runs[1]); // one thread, twice
  EXPECT_EQ(runs[0], runs[2]); // the layout's tasks keep the serial order on 3 threads
  mcv::ReductionOptions o = umapOptions(2);
  o.randomSeed = 6;
  EXPECT_NE(mcv::reduceDimension({ b.X.data(), 500, 10 }, o).coordinates, runs[0]);
}

TEST(UMAP, VectorisedLayoutMatchesThePortableLoop)
{
  if (!mcv::layoutIsVectorised())
  {
    GTEST_SKIP() << "this CPU has no AVX2: the layout runs the portable loop only";
  }
  // Two touching blobs (one component), 2D and 3D layouts from the same random start. With
  // 400 points a task holds ~50 vertices, so many batches are cut short by a shared vertex
  // and padded; a negative sample often draws its own head; and the first 200 points start
  // on 5 positions, so negative samples meet points on top of the head.
  Blobs b = twoBlobs(200, 13);
  b.X.bottomRows(200).rowwise() -= (b.centres.row(1) - b.centres.row(0)) * 0.9f;
  const mcv::KnnGraph knn = mcv::buildKnnGraph(b.X.data(), 400, 10, 15);
  const mcv::FuzzyGraph g = mcv::fuzzySimplicialSet(knn);
  std::mt19937 rng(3);
  std::uniform_real_distribution<float> u(0.f, 10.f);
  for (const int d : { 2, 3 })
  {
    mcv::RowMatrixF start(400, d);
    for (Eigen::Index i = 0; i < start.size(); ++i)
    {
      start.data()[i] = u(rng);
    }
    for (Eigen::Index i = 5; i < 200; ++i) // points on top of each other: the fixed push
    {
      start.row(i) = start.row(i % 5);
    }
    mcv::LayoutOptions o;
    o.epochs = 200;
    o.seed = 4;
    mcv::RowMatrixF wide = start, portable = start;
    mcv::optimizeLayout(g, o, wide);
    o.vectorised = false;
    mcv::optimizeLayout(g, o, portable);
    ASSERT_TRUE(wide.allFinite());
    EXPECT_GT((wide - start).norm(), 1.f); // the layout moved
    EXPECT_EQ(std::memcmp(wide.data(), portable.data(), sizeof(float) * wide.size()), 0) << "d = " << d;
  }
}

TEST(UMAP, DisconnectedGraphStartsAtRandomWithAWarning)
{
  // Blobs 20 sigma apart never share a neighbour: two components.
  const Blobs b = twoBlobs(150, 12);
  mcv::UMAPOptions o;
  o.numberOfNeighbors = 5;
  const mcv::Embedding e = mcv::fitUMAP(b.X, o);
  ASSERT_TRUE(e.error.empty()) << e.error;
  ASSERT_EQ(e.warnings.size(), 1u);
  EXPECT_NE(e.warnings[0].find("2 connected components"), std::string::npos) << e.warnings[0];
  EXPECT_TRUE(e.eigenvalues.empty());
  EXPECT_TRUE(e.coordinates.allFinite());
}

TEST(UMAP, BadInputsGiveClearErrorsOrDocumentedResults)
{
  const Blobs b = twoBlobs(50, 2);
  const mcv::FeatureMatrix f{ b.X.data(), 100, 10 };
  // Fewer reference points than NumberOfNeighbors + 1.
  mcv::ReductionOptions o = umapOptions();
  o.referenceSampleSize = 15;
  mcv::ReductionResult r = mcv::reduceDimension(f, o);
  EXPECT_FALSE(r.ok());
  EXPECT_NE(r.error.find("NumberOfNeighbors"), std::string::npos) << r.error;
  mcv::UMAPOptions uo;
  EXPECT_NE(mcv::fitUMAP(b.X.topRows(15), uo).error.find("number of neighbours"), std::string::npos);
  // MinimumDistance outside [0, 1] (umap-learn: min_dist >= 0 and <= spread).
  for (double md : { -0.1, 1.5, std::nan("") })
  {
    o = umapOptions();
    o.minimumDistance = md;
    r = mcv::reduceDimension(f, o);
    EXPECT_NE(r.error.find("MinimumDistance"), std::string::npos) << md << ": " << r.error;
  }
  // MinimumDistance 0 is allowed (points may coincide), as in umap-learn.
  o = umapOptions();
  o.minimumDistance = 0.0;
  r = mcv::reduceDimension(f, o);
  EXPECT_TRUE(r.ok()) << r.error;
  // A negative number of epochs.
  o = umapOptions();
  o.numberOfEpochs = -1;
  EXPECT_NE(mcv::reduceDimension(f, o).error.find("NumberOfEpochs"), std::string::npos);
  // NaN features: an error that says where.
  mcv::RowMatrixF bad = b.X;
  bad(7, 3) = std::nanf("");
  r = mcv::reduceDimension({ bad.data(), 100, 10 }, umapOptions());
  EXPECT_NE(r.error.find("non-finite"), std::string::npos) << r.error;
  EXPECT_NE(mcv::fitUMAP(bad, uo).error.find("NaN"), std::string::npos);
  // Duplicate points: reduceDimension fits each distinct vector once and places the copies
  // on it; fitUMAP itself takes them and lays the copies out next to each other.
  mcv::RowMatrixF dup(200, 10);
  dup << b.X, b.X;
  r = mcv::reduceDimension({ dup.data(), 200, 10 }, umapOptions());
  ASSERT_TRUE(r.ok()) << r.error;
  for (int i = 0; i < 100; ++i)
  {
    for (int c = 0; c < 3; ++c)
    {
      EXPECT_EQ(r.coordinates[i * 3 + c], r.coordinates[(i + 100) * 3 + c]);
    }
  }
  const mcv::Embedding e = mcv::fitUMAP(dup, uo);
  ASSERT_TRUE(e.error.empty()) << e.error;
  ASSERT_TRUE(e.coordinates.allFinite());
  int near = 0;
  for (int i = 0; i < 100; ++i)
  {
    const std::vector<int> nearest = nearestRows(e.coordinates, e.coordinates.row(i).data(), 6);
    near += std::find(nearest.begin(), nearest.end(), i + 100) != nearest.end() ? 1 : 0;
  }
  EXPECT_GE(near, 98) << "copies among each other's 5 nearest";
}

TEST(UMAP, ProgressReachesTheEnd)
{
  const Blobs b = twoBlobs(100, 1);
  std::vector<std::string> stages;
  double last = -1;
  mcv::UMAPOptions o;
  o.numberOfEpochs = 30;
  o.progress = [&](const char* stage, double f) {
    if (stages.empty() || stages.back() != stage)
    {
      stages.push_back(stage);
    }
    EXPECT_GE(f, last);
    last = f;
  };
  ASSERT_TRUE(mcv::fitUMAP(b.X, o).error.empty());
  EXPECT_EQ(last, 1.0);
  EXPECT_NE(std::find(stages.begin(), stages.end(), "UMAP: layout"), stages.end());
}
