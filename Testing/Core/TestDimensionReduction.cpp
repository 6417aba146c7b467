// Dimension reduction (PCA, landmark Isomap, LLE, out-of-sample placement) against known
// answers on synthetic data, where the answer is the point: a direct SVD, a swiss roll, an
// S-curve (scikit-learn's generators, re-implemented).
#include "CpuReduction.h"
#include "DimensionReduction.h"
#include "IsomapEmbedding.h"
#include "LLEEmbedding.h"
#include "OutOfSample.h"
#include "Trustworthiness.h"
#include "UMAPEmbedding.h"

#include <Eigen/SVD>
#include <gtest/gtest.h>
#include <omp.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <numeric>
#include <random>

namespace
{

struct Manifold
{
  std::vector<float> x; // n x 3
  std::vector<double> t; // the manifold parameter
  std::size_t n = 0;
  mcv::FeatureMatrix matrix() const { return { x.data(), n, 3 }; }
};

// n points of a 2D manifold in 3D: for uniform u, v in [0, 1), drawn in that order,
// t = tOf(u) is the manifold parameter and the point is point(t, v).
template <class ParameterOf, class PointOf>
Manifold sampleManifold(std::size_t n, unsigned seed, ParameterOf tOf, PointOf point)
{
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  Manifold m;
  m.n = n;
  for (std::size_t i = 0; i < n; ++i)
  {
    const double t = tOf(u(rng));
    const std::array<double, 3> p = point(t, u(rng));
    m.t.push_back(t);
    m.x.insert(m.x.end(), { static_cast<float>(p[0]), static_cast<float>(p[1]), static_cast<float>(p[2]) });
  }
  return m;
}

// scikit-learn's make_swiss_roll: t = 1.5 pi (1 + 2u), (t cos t, 21 v, t sin t).
Manifold swissRoll(std::size_t n, unsigned seed)
{
  return sampleManifold(
    n, seed, [](double u) { return 1.5 * M_PI * (1.0 + 2.0 * u); },
    [](double t, double v) { return std::array<double, 3>{ t * std::cos(t), 21.0 * v, t * std::sin(t) }; });
}

// scikit-learn's make_s_curve: t = 3 pi (u - 1/2), (sin t, 2 v, sign(t)(cos t - 1)).
Manifold sCurve(std::size_t n, unsigned seed)
{
  return sampleManifold(n, seed, [](double u) { return 3.0 * M_PI * (u - 0.5); },
    [](double t, double v) {
      return std::array<double, 3>{ std::sin(t), 2.0 * v, (t < 0 ? -1.0 : 1.0) * (std::cos(t) - 1.0) };
    });
}

double correlation(const std::vector<float>& coords, int d, int column, const std::vector<double>& t)
{
  const std::size_t n = t.size();
  double ma = 0, mb = 0;
  for (std::size_t i = 0; i < n; ++i)
  {
    ma += coords[i * d + column];
    mb += t[i];
  }
  ma /= n;
  mb /= n;
  double sab = 0, saa = 0, sbb = 0;
  for (std::size_t i = 0; i < n; ++i)
  {
    const double a = coords[i * d + column] - ma, b = t[i] - mb;
    sab += a * b;
    saa += a * a;
    sbb += b * b;
  }
  return sab / std::sqrt(saa * sbb);
}

bool hasWarning(const mcv::ReductionResult& r, const std::string& part)
{
  for (const auto& w : r.warnings)
  {
    if (w.find(part) != std::string::npos)
    {
      return true;
    }
  }
  return false;
}

bool allFinite(const std::vector<float>& values)
{
  return std::all_of(values.begin(), values.end(), [](float v) { return std::isfinite(v); });
}

mcv::ReductionOptions cpu(mcv::ReductionMethod method, int d = 2)
{
  mcv::ReductionOptions o;
  o.method = method;
  o.outputDimension = d;
  o.device = mcv::Device::CPU;
  return o;
}

} // namespace

TEST(DimensionReduction, PCAEqualsDirectSVD)
{
  const std::size_t n = 400;
  const int D = 6;
  std::mt19937 rng(3);
  std::normal_distribution<double> g(0.0, 1.0);
  Eigen::MatrixXd mix = Eigen::MatrixXd::Zero(D, D);
  for (int i = 0; i < D; ++i)
  {
    for (int j = 0; j < D; ++j)
    {
      mix(i, j) = g(rng) * (j + 1);
    }
  }
  Eigen::MatrixXd X(n, D);
  for (std::size_t i = 0; i < n; ++i)
  {
    for (int j = 0; j < D; ++j)
    {
      X(i, j) = g(rng);
    }
  }
  X = (X * mix).eval();
  X.rowwise() += Eigen::RowVectorXd::LinSpaced(D, 5.0, 10.0);
  std::vector<float> data(n * D);
  for (std::size_t i = 0; i < n; ++i)
  {
    for (int j = 0; j < D; ++j)
    {
      data[i * D + j] = static_cast<float>(X(i, j));
      X(i, j) = data[i * D + j]; // compare on the float data
    }
  }
  mcv::ReductionOptions o = cpu(mcv::ReductionMethod::PCA, 3);
  o.referenceSampleSize = n; // fit on every row
  const auto r = mcv::reduceDimension({ data.data(), n, D }, o);
  ASSERT_TRUE(r.ok()) << r.error;
  ASSERT_EQ(r.coordinates.size(), n * 3);

  const Eigen::MatrixXd C = X.rowwise() - X.colwise().mean();
  Eigen::JacobiSVD<Eigen::MatrixXd> svd(C, Eigen::ComputeThinU);
  const Eigen::MatrixXd scores = svd.matrixU() * svd.singularValues().asDiagonal();
  for (int k = 0; k < D; ++k)
  {
    const double expected = svd.singularValues()[k] * svd.singularValues()[k] / (n - 1);
    EXPECT_NEAR(r.eigenvalues[k], expected, 1e-6 * svd.singularValues()[0] * svd.singularValues()[0] / (n - 1));
  }
  for (int k = 0; k < 3; ++k)
  {
    double sign = 0;
    double worst = 0;
    for (std::size_t i = 0; i < n; ++i)
    {
      const double ours = r.coordinates[i * 3 + k];
      if (sign == 0 && std::abs(scores(i, k)) > 1e-3)
      {
        sign = ours * scores(i, k) > 0 ? 1 : -1;
      }
      worst = std::max(worst, std::abs(ours - sign * scores(i, k)));
    }
    EXPECT_LT(worst, 1e-3 * svd.singularValues()[0] / std::sqrt(double(n))) << "component " << k;
  }
  double top = 0, all = 0;
  for (int k = 0; k < D; ++k)
  {
    all += r.eigenvalues[k];
    top += k < 3 ? r.eigenvalues[k] : 0;
  }
  EXPECT_NEAR(r.varianceRetained, top / all, 1e-9);
}

// Isomap, LLE and UMAP refuse a neighbourhood size outside [1, n - 1] with the same message.
TEST(DimensionReduction, GraphMethodsNameAnOutOfRangeNeighbourCount)
{
  const mcv::RowMatrixF X = mcv::RowMatrixF::Random(20, 3);
  for (int K : { 0, 20 })
  {
    const std::string tail = ": the number of neighbours (" + std::to_string(K) +
      ") must be at least 1 and less than the number of reference points (20).";
    mcv::IsomapOptions io;
    io.outputDimension = 2;
    io.numberOfNeighbors = K;
    EXPECT_EQ(mcv::fitIsomap(X, io).error, "Isomap" + tail);
    mcv::LLEOptions lo;
    lo.outputDimension = 2;
    lo.numberOfNeighbors = K;
    EXPECT_EQ(mcv::fitLLE(X, lo).error, "LLE" + tail);
    mcv::UMAPOptions uo;
    uo.outputDimension = 2;
    uo.numberOfNeighbors = K;
    EXPECT_EQ(mcv::fitUMAP(X, uo).error, "UMAP" + tail);
  }
}

TEST(DimensionReduction, IsomapUnrollsSwissRoll)
{
  const Manifold m = swissRoll(1500, 7);
  mcv::ReductionOptions o = mcv::testing::cpuReduction(mcv::ReductionMethod::Isomap, 2, 10, 150, m.n);
  const auto r = mcv::reduceDimension(m.matrix(), o);
  ASSERT_TRUE(r.ok()) << r.error;
  ASSERT_TRUE(allFinite(r.coordinates));
  const double c = correlation(r.coordinates, 2, 0, m.t);
  EXPECT_GE(std::abs(c), 0.95) << "corr(first coordinate, roll parameter)";
  EXPECT_GT(r.varianceRetained, 0.9);
  EXPECT_GT(r.trustworthiness, 0.95);
}

TEST(DimensionReduction, IsomapJoinsDisconnectedGraph)
{
  // Two swiss rolls far apart: the kNN graph has (at least) two components.
  Manifold a = swissRoll(400, 1);
  const Manifold b = swissRoll(400, 2);
  for (std::size_t i = 0; i < b.n; ++i)
  {
    a.x.insert(a.x.end(), { b.x[3 * i] + 500.f, b.x[3 * i + 1], b.x[3 * i + 2] });
  }
  a.n += b.n;
  mcv::ReductionOptions o = mcv::testing::cpuReduction(mcv::ReductionMethod::Isomap, 2, 8, 100, a.n);
  const auto r = mcv::reduceDimension(a.matrix(), o);
  ASSERT_TRUE(r.ok()) << r.error;
  EXPECT_TRUE(hasWarning(r, "connected components")) << "a warning names the components";
  ASSERT_TRUE(allFinite(r.coordinates));
}

TEST(DimensionReduction, LLEOnSCurveIsTrustworthy)
{
  const Manifold m = sCurve(1500, 11);
  // 300 landmarks: locally linear landmarks; as many as points: exact LLE.
  for (int landmarks : { 300, static_cast<int>(m.n) })
  {
    SCOPED_TRACE("landmarks " + std::to_string(landmarks));
    mcv::ReductionOptions o = mcv::testing::cpuReduction(mcv::ReductionMethod::LLE, 2, 12, landmarks, m.n);
    o.trustworthinessSample = m.n;
    const auto r = mcv::reduceDimension(m.matrix(), o);
    ASSERT_TRUE(r.ok()) << r.error;
    EXPECT_TRUE(r.warnings.empty()) << r.warnings.front();
    EXPECT_GE(r.trustworthiness, 0.95);
    ASSERT_EQ(r.eigenvalues.size(), 2u);
    EXPECT_LE(r.eigenvalues[0], r.eigenvalues[1]);
    ASSERT_TRUE(allFinite(r.coordinates));
  }
}

TEST(DimensionReduction, OutOfSamplePlacesReferencePointsOnThemselves)
{
  const Manifold m = swissRoll(300, 5);
  mcv::RowMatrixF refX(static_cast<Eigen::Index>(m.n), 3);
  mcv::RowMatrixF refY(static_cast<Eigen::Index>(m.n), 3);
  std::mt19937 rng(9);
  std::normal_distribution<float> g;
  for (std::size_t i = 0; i < m.n; ++i)
  {
    for (int c = 0; c < 3; ++c)
    {
      refX(i, c) = m.x[3 * i + c];
      refY(i, c) = g(rng);
    }
  }
  std::vector<float> out(m.n * 3);
  mcv::placeOutOfSample(refX, refY, refX.data(), m.n, 3, {}, out.data());
  for (std::size_t i = 0; i < m.n; ++i)
  {
    for (int c = 0; c < 3; ++c)
    {
      ASSERT_EQ(out[3 * i + c], refY(i, c)) << "reference point " << i;
    }
  }
}

TEST(DimensionReduction, OutOfSampleUsesBarycentricWeights)
{
  // Three reference points far from a fourth: a point in their plane is their affine
  // combination, and lands on the same combination of their embeddings.
  mcv::RowMatrixF refX(4, 4);
  refX << 0, 0, 0, 0, //
    1, 0, 0, 0,       //
    0, 1, 0, 0,       //
    50, 50, 50, 50;
  mcv::RowMatrixF refY(4, 2);
  refY << 0, 0, 10, 0, 0, 10, 99, 99;
  const float w1 = 0.3f, w2 = 0.25f; // w0 = 0.45
  // Features with a constant column in front: columns {1..4} are used.
  std::vector<float> x = { 7.f, w1, w2, 0.f, 0.f };
  float y[2];
  mcv::placeOutOfSample(refX, refY, x.data(), 1, 5, { 1, 2, 3, 4 }, y);
  EXPECT_NEAR(y[0], 10 * w1, 0.01);
  EXPECT_NEAR(y[1], 10 * w2, 0.01);
}

TEST(DimensionReduction, SameSeedSameResult)
{
  const Manifold m = swissRoll(1200, 3);
  for (auto method : { mcv::ReductionMethod::PCA, mcv::ReductionMethod::Isomap, mcv::ReductionMethod::LLE })
  {
    // 500 references, a real sample: the seed matters
    mcv::ReductionOptions o = mcv::testing::cpuReduction(method, 2, 10, 60, 500);
    o.randomSeed = 42;
    const auto a = mcv::reduceDimension(m.matrix(), o);
    const auto b = mcv::reduceDimension(m.matrix(), o);
    ASSERT_TRUE(a.ok()) << a.error;
    EXPECT_EQ(a.referenceIndices, b.referenceIndices);
    EXPECT_EQ(a.coordinates, b.coordinates);
    EXPECT_EQ(a.trustworthiness, b.trustworthiness);
    EXPECT_EQ(a.referenceIndices.size(), 500u);
    o.randomSeed = 43;
    const auto c = mcv::reduceDimension(m.matrix(), o);
    ASSERT_TRUE(c.ok()) << c.error;
    EXPECT_NE(a.referenceIndices, c.referenceIndices);
  }
}

TEST(DimensionReduction, ReferenceSampleKeepsRareBrightVoxels)
{
  // 100000 dim voxels and 200 bright ones (0.2 %): a uniform sample of 1000 would hold
  // about 2 of them; the norm-stratified one about 17 (the top 0.8 % by norm get 1/16 of
  // the sample, and the bright voxels are a quarter of that stratum).
  std::mt19937 rng(1);
  std::normal_distribution<float> g;
  const std::size_t n = 100200;
  std::vector<float> data(n * 2);
  for (std::size_t i = 0; i < n; ++i)
  {
    const float s = i < 200 ? 20.f : 1.f;
    data[2 * i] = s + 0.1f * g(rng);
    data[2 * i + 1] = s + 0.1f * g(rng);
  }
  mcv::ReductionOptions o = cpu(mcv::ReductionMethod::PCA, 2);
  o.referenceSampleSize = 1000;
  const auto r = mcv::reduceDimension({ data.data(), n, 2 }, o);
  ASSERT_TRUE(r.ok()) << r.error;
  std::size_t bright = 0;
  for (auto i : r.referenceIndices)
  {
    bright += i < 200;
  }
  EXPECT_GE(bright, 10u);
}

TEST(DimensionReduction, DuplicateVoxelsAreFittedOnce)
{
  // Half the voxels share one feature vector (a background): they are fitted once and
  // all land on that one point.
  Manifold m = swissRoll(600, 4);
  for (int i = 0; i < 600; ++i)
  {
    m.x.insert(m.x.end(), { 0.f, 0.f, 0.f });
  }
  m.n = 1200;
  mcv::ReductionOptions o = mcv::testing::cpuReduction(mcv::ReductionMethod::Isomap, 2, 10, 50, 2000);
  const auto r = mcv::reduceDimension(m.matrix(), o);
  ASSERT_TRUE(r.ok()) << r.error;
  EXPECT_EQ(r.referenceIndices.size(), 601u);
  for (std::size_t i = 601; i < 1200; ++i)
  {
    EXPECT_EQ(r.coordinates[2 * i], r.coordinates[2 * 600]);
    EXPECT_EQ(r.coordinates[2 * i + 1], r.coordinates[2 * 600 + 1]);
  }
}

TEST(DimensionReduction, BadInputsGiveClearErrors)
{
  const Manifold m = swissRoll(300, 8);
  auto run = [](const mcv::FeatureMatrix& f, const mcv::ReductionOptions& o) { return mcv::reduceDimension(f, o); };
  mcv::ReductionOptions o = cpu(mcv::ReductionMethod::Isomap, 2);
  o.numberOfNeighbors = 10;
  o.numberOfLandmarks = 50;

  // No rows.
  auto r = run({ nullptr, 0, 3 }, o);
  EXPECT_FALSE(r.ok());
  EXPECT_NE(r.error.find("no rows"), std::string::npos) << r.error;
  // One feature: nothing to reduce.
  r = run({ m.x.data(), 100, 1 }, o);
  EXPECT_NE(r.error.find("nothing to reduce"), std::string::npos) << r.error;
  // Output dimension not 2 or 3.
  for (int d : { 0, 1, 4 })
  {
    mcv::ReductionOptions od = o;
    od.outputDimension = d;
    r = run(m.matrix(), od);
    EXPECT_NE(r.error.find("OutputDimension"), std::string::npos) << r.error;
  }
  // K >= M.
  mcv::ReductionOptions ok = o;
  ok.referenceSampleSize = 10;
  r = run(m.matrix(), ok);
  EXPECT_NE(r.error.find("NumberOfNeighbors"), std::string::npos) << r.error;
  ok.method = mcv::ReductionMethod::LLE;
  r = run(m.matrix(), ok);
  EXPECT_NE(r.error.find("NumberOfNeighbors"), std::string::npos) << r.error;
  // A reference sample too small for the embedding: said about ReferenceSampleSize, not the data.
  for (std::size_t size : { 1, 3 })
  {
    mcv::ReductionOptions os = cpu(mcv::ReductionMethod::PCA, 2);
    os.referenceSampleSize = size;
    r = run(m.matrix(), os);
    EXPECT_NE(r.error.find("ReferenceSampleSize (" + std::to_string(size) + ") is too small"), std::string::npos)
      << r.error;
  }
  // Fewer landmarks than landmark LLE needs: raised, with a warning (as Isomap does).
  mcv::ReductionOptions ol = o;
  ol.method = mcv::ReductionMethod::LLE;
  ol.numberOfLandmarks = 1;
  ol.referenceSampleSize = m.n;
  r = run(m.matrix(), ol);
  EXPECT_TRUE(r.ok()) << r.error;
  EXPECT_TRUE(hasWarning(r, "LLE: 1 landmarks asked for, 13 used"));
  // M > rows: all rows, with a warning.
  mcv::ReductionOptions om = o;
  om.referenceSampleSize = 100000;
  r = run(m.matrix(), om);
  EXPECT_TRUE(r.ok()) << r.error;
  EXPECT_TRUE(hasWarning(r, "exceeds the number of voxels"));
  EXPECT_EQ(r.referenceIndices.size(), m.n);
  // A constant feature: dropped with a warning, the rest reduced.
  std::vector<float> withConstant;
  for (std::size_t i = 0; i < m.n; ++i)
  {
    withConstant.insert(withConstant.end(), { m.x[3 * i], 4.5f, m.x[3 * i + 1], m.x[3 * i + 2] });
  }
  r = run({ withConstant.data(), m.n, 4 }, om);
  EXPECT_TRUE(r.ok()) << r.error;
  EXPECT_TRUE(hasWarning(r, "Constant feature component(s) 1"));
  EXPECT_EQ(r.usedColumns, (std::vector<int>{ 0, 2, 3 }));
  // Only constant features: nothing to reduce.
  std::vector<float> flat(600, 1.f);
  r = run({ flat.data(), 300, 2 }, o);
  EXPECT_NE(r.error.find("nothing to reduce"), std::string::npos) << r.error;
  // NaN and Inf.
  for (float bad : { std::numeric_limits<float>::quiet_NaN(), std::numeric_limits<float>::infinity() })
  {
    std::vector<float> x = m.x;
    x[3 * 17 + 2] = bad;
    r = run({ x.data(), m.n, 3 }, o);
    EXPECT_NE(r.error.find("non-finite"), std::string::npos) << r.error;
    EXPECT_NE(r.error.find("voxel 17"), std::string::npos) << r.error;
    EXPECT_TRUE(r.coordinates.empty());
  }
}

TEST(DimensionReduction, TrustworthinessKnownValues)
{
  // The identity embedding is perfectly trustworthy; a random one is not.
  const Manifold m = swissRoll(300, 6);
  EXPECT_DOUBLE_EQ(mcv::trustworthiness(m.x.data(), 3, m.x.data(), 3, m.n, 10), 1.0);
  std::vector<float> noise(m.n * 2);
  std::mt19937 rng(2);
  std::normal_distribution<float> g;
  for (float& v : noise)
  {
    v = g(rng);
  }
  const double t = mcv::trustworthiness(m.x.data(), 3, noise.data(), 2, m.n, 10);
  EXPECT_LT(t, 0.7);
  EXPECT_GT(t, 0.3);
  EXPECT_TRUE(std::isnan(mcv::trustworthiness(m.x.data(), 3, m.x.data(), 3, 10, 10)));
}

// scikit-learn's definition, the straightforward way: every point's full ranking in the
// original space (stable sort: ties by index), then the ranks of its k nearest in the
// embedding.
double trustworthinessBySorting(const std::vector<float>& X, int D, const std::vector<float>& Y, int d, std::size_t n, int k)
{
  double penalty = 0;
  for (std::size_t i = 0; i < n; ++i)
  {
    std::vector<double> dx(n), dy(n);
    for (std::size_t j = 0; j < n; ++j)
    {
      for (int c = 0; c < D; ++c)
      {
        const double t = static_cast<double>(X[i * D + c]) - X[j * D + c];
        dx[j] += t * t;
      }
      for (int c = 0; c < d; ++c)
      {
        const double t = static_cast<double>(Y[i * d + c]) - Y[j * d + c];
        dy[j] += t * t;
      }
    }
    dx[i] = dy[i] = std::numeric_limits<double>::infinity();
    std::vector<std::size_t> byX(n), byY(n), rank(n);
    std::iota(byX.begin(), byX.end(), 0);
    std::stable_sort(byX.begin(), byX.end(), [&](std::size_t a, std::size_t b) { return dx[a] < dx[b]; });
    for (std::size_t r = 0; r < n; ++r)
    {
      rank[byX[r]] = r + 1;
    }
    std::iota(byY.begin(), byY.end(), 0);
    std::stable_sort(byY.begin(), byY.end(), [&](std::size_t a, std::size_t b) { return dy[a] < dy[b]; });
    for (int j = 0; j < k; ++j)
    {
      penalty += std::max(0.0, static_cast<double>(rank[byY[j]]) - k);
    }
  }
  const double nn = static_cast<double>(n);
  return 1.0 - penalty * (2.0 / (nn * k * (2.0 * nn - 3.0 * k - 1.0)));
}

TEST(DimensionReduction, TrustworthinessMatchesTheDefinition)
{
  std::mt19937 rng(4);
  std::normal_distribution<float> g;
  std::uniform_int_distribution<int> level(0, 3);
  const std::size_t n = 400;
  for (bool ties : { false, true })
  {
    SCOPED_TRACE(ties ? "quantised: many equal distances" : "random");
    std::vector<float> X(n * 5), Y(n * 2);
    for (float& v : X)
    {
      v = ties ? static_cast<float>(level(rng)) : g(rng);
    }
    for (std::size_t i = 0; i < n; ++i)
    {
      // A noisy projection: neither perfect nor random.
      Y[i * 2] = X[i * 5] + 0.3f * (ties ? static_cast<float>(level(rng)) : g(rng));
      Y[i * 2 + 1] = X[i * 5 + 1] + X[i * 5 + 2];
    }
    for (int k : { 1, 5, 12 })
    {
      const double expected = trustworthinessBySorting(X, 5, Y, 2, n, k);
      EXPECT_NEAR(mcv::trustworthiness(X.data(), 5, Y.data(), 2, n, k), expected, 1e-12) << "k " << k;
    }
  }
}

TEST(DimensionReduction, SameCoordinatesForAnyThreadCount)
{
  // Every parallel step sums in an order that does not depend on the threads (per row, or
  // per entry as in the landmark pencil's Gram), so the threads change nothing, bit for bit.
  const Manifold m = sCurve(1200, 5);
  const int threads = omp_get_max_threads();
  for (const auto method : { mcv::ReductionMethod::LLE, mcv::ReductionMethod::Isomap })
  {
    SCOPED_TRACE(method == mcv::ReductionMethod::LLE ? "LLE" : "Isomap");
    // 900 references: the other rows are placed out of sample
    mcv::ReductionOptions o = mcv::testing::cpuReduction(method, 2, 12, 150, 900);
    std::vector<std::vector<float>> coordinates;
    std::vector<std::vector<double>> eigenvalues;
    for (int t : { 1, 3 })
    {
      omp_set_num_threads(t);
      const auto r = mcv::reduceDimension(m.matrix(), o);
      ASSERT_TRUE(r.ok()) << r.error;
      coordinates.push_back(r.coordinates);
      eigenvalues.push_back(r.eigenvalues);
    }
    omp_set_num_threads(threads);
    EXPECT_EQ(coordinates[0], coordinates[1]);
    EXPECT_EQ(eigenvalues[0], eigenvalues[1]);
  }
}

TEST(DimensionReduction, CallerBufferReceivesTheCoordinates)
{
  // PCA's projection, the out-of-sample placement (500 of 800 rows fitted) and the fit's own
  // coordinates (all rows fitted) each write into it.
  const Manifold m = swissRoll(800, 3);
  for (const auto& [method, fitted] : { std::pair(mcv::ReductionMethod::PCA, std::size_t(500)),
         std::pair(mcv::ReductionMethod::Isomap, std::size_t(500)), std::pair(mcv::ReductionMethod::Isomap, m.n) })
  {
    SCOPED_TRACE(std::to_string(static_cast<int>(method)) + ", fitted on " + std::to_string(fitted));
    mcv::ReductionOptions o = mcv::testing::cpuReduction(method, 3, 10, 60, fitted);
    const auto inVector = mcv::reduceDimension(m.matrix(), o);
    ASSERT_TRUE(inVector.ok()) << inVector.error;
    std::vector<float> buffer(m.n * 3, std::numeric_limits<float>::quiet_NaN());
    o.coordinatesOutput = buffer.data();
    const auto inBuffer = mcv::reduceDimension(m.matrix(), o);
    ASSERT_TRUE(inBuffer.ok()) << inBuffer.error;
    EXPECT_TRUE(inBuffer.coordinates.empty());
    EXPECT_EQ(buffer, inVector.coordinates);
  }
}

TEST(DimensionReduction, ProgressCoversEveryStage)
{
  const Manifold m = swissRoll(500, 2);
  mcv::ReductionOptions o = cpu(mcv::ReductionMethod::Isomap, 3);
  o.numberOfNeighbors = 10;
  o.numberOfLandmarks = 40;
  std::vector<double> fractions;
  o.progress = [&](const char*, double f) { fractions.push_back(f); };
  const auto r = mcv::reduceDimension(m.matrix(), o);
  ASSERT_TRUE(r.ok()) << r.error;
  ASSERT_GE(fractions.size(), 5u);
  EXPECT_EQ(fractions.back(), 1.0);
  for (std::size_t i = 1; i < fractions.size(); ++i)
  {
    EXPECT_GE(fractions[i], fractions[i - 1]);
  }
  EXPECT_EQ(r.outputDimension, 3);
  EXPECT_GE(r.totalMs, r.fitMs);
}
