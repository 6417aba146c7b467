// Isomap's fit on the GPU (reduction/cuda/KnnCandidatesCuda.h, GeodesicsCuda.h) against the
// CPU: the neighbour graph bit for bit against the CPU's (random rows, and rows with exact
// ties that take the radius scan), the shortest paths bit for bit against Dijkstra (random
// graphs, graphs with exact ties, an unreachable vertex), the MDS eigenvalues against
// Eigen's, and the whole fit (random rows and the real brain's 24D features) against the CPU
// fit: the same coordinates, bit for bit; a failure injected in any of the three GPU steps
// leaves the CPU's answer with one warning. Skips without a GPU.
#include "BrainFeatures.h"
#include "FeatureKnn.h"
#include "IsomapEmbedding.h"
#include "ReferenceSample.h"
#include "RequireGpu.h"
#include "cuda/FaultInjection.h"
#include "cuda/GeodesicsCuda.h"

#include <Eigen/Eigenvalues>
#include <gtest/gtest.h>

#include <algorithm>
#include <vector>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <functional>
#include <limits>
#include <queue>
#include <random>
#include <string>
#include <tuple>
#include <utility>
#include <vector>

namespace
{

namespace mt = mcv::testing;

// n x D rows of independent standard normal values.
mcv::RowMatrixF normalRows(Eigen::Index n, Eigen::Index D, unsigned seed)
{
  std::mt19937 rng(seed);
  std::normal_distribution<float> normal;
  mcv::RowMatrixF X(n, D);
  for (Eigen::Index i = 0; i < X.size(); ++i)
    X.data()[i] = normal(rng);
  return X;
}

struct Csr
{
  std::vector<std::size_t> start;
  std::vector<std::uint32_t> to;
  std::vector<float> weight;
};

// Symmetric graph from undirected edges (a, b, length).
Csr csrFromEdges(std::size_t n, const std::vector<std::tuple<std::uint32_t, std::uint32_t, float>>& edges)
{
  std::vector<std::vector<std::pair<std::uint32_t, float>>> rows(n);
  for (const auto& [a, b, w] : edges)
  {
    rows[a].emplace_back(b, w);
    rows[b].emplace_back(a, w);
  }
  Csr g;
  g.start.push_back(0);
  for (const auto& row : rows)
  {
    for (const auto& [t, w] : row)
    {
      g.to.push_back(t);
      g.weight.push_back(w);
    }
    g.start.push_back(g.to.size());
  }
  return g;
}

// Textbook Dijkstra (binary heap, lazy deletion), the lengths summed in double from the source
// as Boost's is: the reference the device must match bit for bit.
std::vector<double> dijkstra(const Csr& g, std::uint32_t source)
{
  const std::size_t n = g.start.size() - 1;
  std::vector<double> d(n, std::numeric_limits<double>::infinity());
  using Item = std::pair<double, std::uint32_t>;
  std::priority_queue<Item, std::vector<Item>, std::greater<Item>> heap;
  d[source] = 0.0;
  heap.emplace(0.0, source);
  while (!heap.empty())
  {
    const auto [du, u] = heap.top();
    heap.pop();
    if (du > d[u])
      continue;
    for (std::size_t e = g.start[u]; e < g.start[u + 1]; ++e)
    {
      const double c = du + static_cast<double>(g.weight[e]);
      if (c < d[g.to[e]])
      {
        d[g.to[e]] = c;
        heap.emplace(c, g.to[e]);
      }
    }
  }
  return d;
}

void expectGeodesicsAreDijkstras(const Csr& g, const std::vector<std::uint32_t>& sources)
{
  const std::size_t n = g.start.size() - 1;
  std::vector<double> gpu(sources.size() * n, -1.0);
  std::string error;
  ASSERT_TRUE(mcv::cuda::geodesicDistances(n, g.start.data(), g.to.data(), g.weight.data(), sources.data(),
    static_cast<int>(sources.size()), gpu.data(), &error))
    << error;
  std::size_t differing = 0;
  for (std::size_t s = 0; s < sources.size(); ++s)
  {
    const std::vector<double> cpu = dijkstra(g, sources[s]);
    differing += static_cast<std::size_t>(std::memcmp(cpu.data(), gpu.data() + s * n, n * sizeof(double)) != 0);
  }
  EXPECT_EQ(differing, 0u) << "sources whose distances differ from Dijkstra's in some bit";
}

void expectSameGraph(const mcv::RowMatrixF& X, int k)
{
  const std::size_t n = static_cast<std::size_t>(X.rows());
  const int D = static_cast<int>(X.cols());
  std::string error;
  const mcv::KnnGraph gpu = mcv::buildKnnGraph(X.data(), n, D, k, mcv::Device::GPU, &error);
  EXPECT_EQ(error, "");
  const mcv::KnnGraph cpu = mcv::buildKnnGraph(X.data(), n, D, k, mcv::Device::CPU);
  EXPECT_EQ(gpu.neighbors, cpu.neighbors);
  EXPECT_EQ(gpu.distances, cpu.distances);
  EXPECT_EQ(gpu.largestFourthSquaredDistance, cpu.largestFourthSquaredDistance);
}

TEST(IsomapGPU, NeighbourGraphIsTheCpusBitForBit)
{
  MCV_REQUIRE_GPU();
  std::mt19937 rng(9);
  std::normal_distribution<float> normal;
  {
    SCOPED_TRACE("random 24D rows, K = 50");
    mcv::RowMatrixF X(5000, 24);
    for (Eigen::Index i = 0; i < X.size(); ++i)
      X.data()[i] = normal(rng);
    expectSameGraph(X, 50);
  }
  {
    // Values on a coarse lattice: many equal distances, so the float bound rarely settles a
    // row and the radius scan decides, ties by index.
    SCOPED_TRACE("quantised 12D rows, K = 20");
    std::uniform_int_distribution<int> level(0, 2);
    mcv::RowMatrixF X(3000, 12);
    for (Eigen::Index i = 0; i < X.size(); ++i)
      X.data()[i] = 0.5f * static_cast<float>(level(rng));
    expectSameGraph(X, 20);
  }
}

TEST(IsomapGPU, ShortestPathsAreDijkstrasBitForBit)
{
  MCV_REQUIRE_GPU();
  std::mt19937 rng(7);
  // Random points in 8D, each joined to 6 random others and to the next (connected), with
  // float Euclidean lengths: sums that round differently in different orders.
  {
    const std::size_t n = 6000;
    std::normal_distribution<float> normal;
    std::vector<float> p(n * 8);
    for (float& x : p)
      x = normal(rng);
    auto length = [&](std::size_t a, std::size_t b) {
      float s = 0;
      for (int k = 0; k < 8; ++k)
        s += (p[a * 8 + k] - p[b * 8 + k]) * (p[a * 8 + k] - p[b * 8 + k]);
      return std::sqrt(s);
    };
    std::uniform_int_distribution<std::uint32_t> pick(0, n - 1);
    std::vector<std::tuple<std::uint32_t, std::uint32_t, float>> edges;
    for (std::uint32_t a = 0; a + 1 < n; ++a)
    {
      edges.emplace_back(a, a + 1, length(a, a + 1));
      for (int j = 0; j < 6; ++j)
      {
        const std::uint32_t b = pick(rng);
        if (b != a)
          edges.emplace_back(a, b, length(a, b));
      }
    }
    std::vector<std::uint32_t> sources{ 0, static_cast<std::uint32_t>(n - 1) };
    for (int s = 0; s < 62; ++s)
      sources.push_back(pick(rng));
    SCOPED_TRACE("random 8D graph");
    expectGeodesicsAreDijkstras(csrFromEdges(n, edges), sources);
  }
  // A 60 x 60 grid with unit and 0.1 lengths (many equal path sums), one isolated vertex
  // (+inf from every source) and one source that reaches nothing.
  {
    const std::uint32_t side = 60, n = side * side + 1;
    std::vector<std::tuple<std::uint32_t, std::uint32_t, float>> edges;
    for (std::uint32_t y = 0; y < side; ++y)
      for (std::uint32_t x = 0; x < side; ++x)
      {
        const std::uint32_t v = y * side + x;
        if (x + 1 < side)
          edges.emplace_back(v, v + 1, (x + y) % 3 == 0 ? 0.1f : 1.0f);
        if (y + 1 < side)
          edges.emplace_back(v, v + side, 1.0f);
      }
    SCOPED_TRACE("grid with ties and an isolated vertex");
    expectGeodesicsAreDijkstras(csrFromEdges(n, edges), { 0, 1234, side * side - 1, side * side });
  }
}

TEST(IsomapGPU, MdsEigenvaluesAreEigens)
{
  MCV_REQUIRE_GPU();
  std::mt19937 rng(3);
  std::normal_distribution<double> normal;
  const int L = 500;
  Eigen::MatrixXd X(L, 24);
  for (Eigen::Index i = 0; i < X.size(); ++i)
    X.data()[i] = normal(rng);
  Eigen::MatrixXd noise(L, L);
  for (Eigen::Index i = 0; i < noise.size(); ++i)
    noise.data()[i] = 0.01 * normal(rng);
  const Eigen::MatrixXd B = X * X.transpose() + 0.5 * (noise + noise.transpose());
  Eigen::VectorXd gpu(L);
  std::string error;
  const bool ok = mcv::cuda::symmetricEigenvalues(B.data(), L, gpu.data(), &error);
  if (!ok && error == "this build has no cuSOLVER")
    GTEST_SKIP() << error;
  ASSERT_TRUE(ok) << error;
  const Eigen::VectorXd cpu = Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd>(B, Eigen::EigenvaluesOnly).eigenvalues();
  EXPECT_LE((gpu - cpu).cwiseAbs().maxCoeff(), 1e-10 * cpu.cwiseAbs().maxCoeff());
}

struct FitPair
{
  mcv::Embedding cpu, gpu;
};

FitPair fitBoth(const mcv::RowMatrixF& X, int K, int L)
{
  mcv::IsomapOptions o;
  o.numberOfNeighbors = K;
  o.numberOfLandmarks = L;
  o.seed = 5;
  FitPair f;
  o.device = mcv::Device::CPU;
  f.cpu = mcv::fitIsomap(X, o);
  o.device = mcv::Device::GPU;
  f.gpu = mcv::fitIsomap(X, o);
  return f;
}

// The GPU's graph and geodesics are the CPU's bits and the top eigenpairs come from Lanczos
// on the host either way, so the coordinates are the CPU's bits; the rest of the spectrum
// (cuSOLVER against Eigen) agrees to rounding.
void expectSameFit(const FitPair& f)
{
  ASSERT_TRUE(f.cpu.error.empty()) << f.cpu.error;
  ASSERT_TRUE(f.gpu.error.empty()) << f.gpu.error;
  EXPECT_EQ(f.gpu.warnings, f.cpu.warnings); // no "on the GPU failed" warning
  ASSERT_EQ(f.gpu.eigenvalues.size(), f.cpu.eigenvalues.size());
  double worstValue = 0;
  for (std::size_t k = 0; k < f.cpu.eigenvalues.size(); ++k)
    worstValue = std::max(worstValue, std::abs(f.gpu.eigenvalues[k] - f.cpu.eigenvalues[k]));
  EXPECT_LE(worstValue, 1e-10 * std::abs(f.cpu.eigenvalues[0]));
  EXPECT_NEAR(f.gpu.varianceRetained, f.cpu.varianceRetained, 1e-12);
  ASSERT_EQ(f.gpu.coordinates.rows(), f.cpu.coordinates.rows());
  ASSERT_EQ(f.gpu.coordinates.cols(), f.cpu.coordinates.cols());
  EXPECT_EQ(std::memcmp(f.gpu.coordinates.data(), f.cpu.coordinates.data(),
              static_cast<std::size_t>(f.cpu.coordinates.size()) * sizeof(float)),
    0)
    << "coordinates differ; worst " << (f.gpu.coordinates - f.cpu.coordinates).cwiseAbs().maxCoeff();
  EXPECT_EQ(f.gpu.referenceRadius, f.cpu.referenceRadius);
}

TEST(IsomapGPU, FitIsTheCpusOnRandomRows)
{
  MCV_REQUIRE_GPU();
  expectSameFit(fitBoth(normalRows(4000, 24, 11), 12, 300));
}

TEST(IsomapGPU, FitIsTheCpusOnTheBrain)
{
  MCV_REQUIRE_GPU();
  if (!mt::haveBrain())
    GTEST_SKIP() << "Colin27 volumes missing (scripts/fetch-data.sh)";
  const auto ch = mt::loadBrain();
  const auto f = mt::brainFeatures(ch, mcv::FeaturePreset::TwentyFourD, mcv::Device::CPU);
  ASSERT_TRUE(f.result.ok()) << f.result.error;
  mcv::ReferenceSampleOptions so;
  so.size = 10000;
  const auto rows = mcv::drawReferenceSample(f.values.data(), f.rows, f.cols, {}, {}, so);
  mcv::RowMatrixF X(static_cast<Eigen::Index>(rows.size()), f.cols);
  for (std::size_t r = 0; r < rows.size(); ++r)
    std::copy(f.values.begin() + rows[r] * f.cols, f.values.begin() + (rows[r] + 1) * f.cols, X.row(r).data());
  // The main job's settings: K = 50, L = 500.
  expectSameFit(fitBoth(X, 50, 500));
}

TEST(IsomapGPU, AFailureOnTheDeviceLeavesTheCpusFitWithAWarning)
{
  MCV_REQUIRE_GPU();
  const mcv::RowMatrixF X = normalRows(1500, 24, 12);
  mcv::IsomapOptions o;
  o.numberOfNeighbors = 10;
  o.numberOfLandmarks = 200;
  const mcv::Embedding cpu = mcv::fitIsomap(X, o);
  o.device = mcv::Device::GPU;
  // The neighbour search's first allocation, the shortest paths' launch (the second), and,
  // where cuSOLVER is linked, the eigenvalues' first allocation (after the search's three and
  // the shortest paths' five).
  const std::vector<std::pair<mcv::cuda::CudaCall, long>> points = { { mcv::cuda::CudaCall::Alloc, 1 },
    { mcv::cuda::CudaCall::Launch, 2 },
#ifdef MCV_HAS_CUSOLVER
    { mcv::cuda::CudaCall::Alloc, 9 },
#endif
  };
  for (const auto& [kind, nth] : points)
  {
    SCOPED_TRACE(std::string(mcv::cuda::cudaCallName(kind)) + " " + std::to_string(nth));
    mcv::cuda::injectFailure("isomapfit", kind, nth);
    const mcv::Embedding gpu = mcv::fitIsomap(X, o);
    EXPECT_FALSE(mcv::cuda::failurePending());
    mcv::cuda::clearInjectedFailure();
    ASSERT_TRUE(gpu.error.empty()) << gpu.error;
    ASSERT_EQ(gpu.warnings.size(), cpu.warnings.size() + 1);
    EXPECT_EQ(std::count_if(gpu.warnings.begin(), gpu.warnings.end(),
                [](const std::string& w) { return w.find("on the GPU failed") != std::string::npos; }),
      1);
    EXPECT_EQ((gpu.coordinates - cpu.coordinates).cwiseAbs().maxCoeff(), 0.f);
  }
}

} // namespace
