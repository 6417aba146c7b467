// The CUDA layout of UMAP (reduction/cuda/UMAPLayoutCuda.h) against the CPU layout (UMAPLayout.h),
// both inside fitUMAP on the same graph and the same start. Not bit equality (the GPU's
// rounds, random streams and powf differ: UMAPLayoutCuda.h), so agreement is measured:
//  - trustworthiness (k = 10) of the GPU layout within 0.01 of the CPU's;
//  - the Procrustes disparity of the two layouts (both centred and scaled to unit norm, the
//    GPU's optimally rotated/reflected and scaled onto the CPU's; 1 - (sum of singular values
//    of A^T B)^2, scipy.spatial.procrustes) at most twice the largest disparity between the
//    CPU layout and two CPU layouts that differ only in their seed, plus 0.01. The seed is
//    the SGD's own noise: the GPU layout is another draw of the same process, so it may not
//    sit further from the CPU's than reseeded CPU runs do by more than a factor 2 (+0.01 so
//    that a near-zero seed spread does not demand more than float rounding). A host run of
//    the GPU's arithmetic gave 0.022, 0.076 and 0.044 against seed spreads 0.014, 0.14 and
//    0.033 (two blobs, brain 24D with 2000 and 5000 points); a layout that ignored the graph
//    (unrelated point sets) would sit near 1;
// on two well-separated Gaussian blobs in 10D (which also stay separated on the GPU) and on
// reference samples of the real brain's 24D and 6D features. Also: the same seed gives the
// same GPU layout bit for bit, and an injected CUDA failure falls back to the CPU layout with
// one warning.
#include "cuda/FaultInjection.h"

#include "BrainFeatures.h"
#include "OutOfSampleData.h"
#include "DimensionReduction.h"
#include "LayoutComparison.h"
#include "OutOfSample.h"
#include "ReferenceSample.h"
#include "Trustworthiness.h"
#include "UMAPEmbedding.h"

#include "RequireGpu.h"

#include <Eigen/Dense>
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <numeric>
#include <random>
#include <string>
#include <vector>

namespace
{

namespace mt = mcv::testing;
using mcv::Device;
using mcv::RowMatrixF;

mcv::Embedding fit(const RowMatrixF& X, Device device, std::uint64_t seed)
{
  mcv::UMAPOptions o;
  o.device = device;
  o.seed = seed;
  return mcv::fitUMAP(X, o);
}

bool mentionsGpuFailure(const std::string& w)
{
  return w.find("GPU UMAP layout failed") != std::string::npos;
}

// Fits X on the CPU (seeds 0 and 1) and the GPU (seed 0) and checks the agreement above.
// Returns the GPU embedding.
mcv::Embedding expectGpuAgreesWithCpu(const RowMatrixF& X, const char* what)
{
  const mcv::Embedding cpu = fit(X, Device::CPU, 0);
  const mcv::Embedding reseeded = fit(X, Device::CPU, 1), reseeded2 = fit(X, Device::CPU, 2);
  const mcv::Embedding gpu = fit(X, Device::GPU, 0);
  EXPECT_TRUE(cpu.error.empty() && reseeded.error.empty() && reseeded2.error.empty() && gpu.error.empty())
    << cpu.error << gpu.error;
  for (const std::string& w : gpu.warnings)
  {
    EXPECT_FALSE(mentionsGpuFailure(w)) << w;
  }
  EXPECT_TRUE(gpu.coordinates.allFinite());
  const std::size_t n = static_cast<std::size_t>(X.rows());
  const int D = static_cast<int>(X.cols()), d = static_cast<int>(cpu.coordinates.cols());
  const double tCpu = mcv::trustworthiness(X.data(), D, cpu.coordinates.data(), d, n, 10);
  const double tSeed = mcv::trustworthiness(X.data(), D, reseeded.coordinates.data(), d, n, 10);
  const double tGpu = mcv::trustworthiness(X.data(), D, gpu.coordinates.data(), d, n, 10);
  const double seedSpread = std::max(mt::procrustesDisparity(cpu.coordinates, reseeded.coordinates),
    mt::procrustesDisparity(cpu.coordinates, reseeded2.coordinates));
  const double disparity = mt::procrustesDisparity(cpu.coordinates, gpu.coordinates);
  std::printf("[ agreement ] UMAP %s, N = %zu: trustworthiness CPU %.4f (other seed %.4f), GPU %.4f; "
              "Procrustes disparity CPU-GPU %.4f, CPU-CPU other seeds (max of 2) %.4f\n",
    what, n, tCpu, tSeed, tGpu, disparity, seedSpread);
  EXPECT_NEAR(tGpu, tCpu, 0.01);
  EXPECT_LE(disparity, 2.0 * seedSpread + 0.01);
  return gpu;
}

// Two isotropic Gaussian blobs (sigma 1) in 10D whose centres are 20 apart (as TestUMAP).
RowMatrixF twoBlobs(int n, unsigned seed, RowMatrixF& centres)
{
  std::mt19937 rng(seed);
  std::normal_distribution<float> g(0.f, 1.f);
  centres = RowMatrixF::Zero(2, 10);
  centres(1, 0) = 20.f;
  RowMatrixF X(2 * n, 10);
  for (int i = 0; i < 2 * n; ++i)
  {
    for (int c = 0; c < 10; ++c)
    {
      X(i, c) = centres(i < n ? 0 : 1, c) + g(rng);
    }
  }
  return X;
}

std::vector<int> nearestRows(const RowMatrixF& Y, const float* y, int k)
{
  std::vector<float> d2(static_cast<std::size_t>(Y.rows()));
  for (Eigen::Index i = 0; i < Y.rows(); ++i)
  {
    d2[i] = (Y.row(i) - Eigen::Map<const Eigen::RowVectorXf>(y, Y.cols())).squaredNorm();
  }
  std::vector<int> idx(d2.size());
  std::iota(idx.begin(), idx.end(), 0);
  std::partial_sort(idx.begin(), idx.begin() + k, idx.end(), [&](int a, int b) { return d2[a] < d2[b]; });
  idx.resize(k);
  return idx;
}

// A reference sample of the real brain's features (a central box, as TestOutOfSample).
RowMatrixF brainSample(mcv::FeaturePreset preset, std::size_t size)
{
  static const auto ch = mt::cropBrain(mt::loadBrain(), { 40, 50, 60 }, { 140, 150, 110 });
  const auto f = mt::brainFeatures(ch, preset, Device::CPU);
  EXPECT_TRUE(f.result.ok()) << f.result.error;
  return mt::referenceSampleRows(f, size);
}

TEST(UMAPLayoutGPU, TwoBlobsAgreeWithCpuAndStaySeparated)
{
  MCV_REQUIRE_GPU();
  const int n = 300;
  RowMatrixF centres;
  const RowMatrixF X = twoBlobs(n, 7, centres);
  const mcv::Embedding gpu = expectGpuAgreesWithCpu(X, "two blobs 10D");
  ASSERT_EQ(gpu.coordinates.rows(), 2 * n);
  // The blobs' centres placed as every voxel is; none of a centre's 10 nearest points in
  // the GPU layout belongs to the other blob.
  std::vector<float> placed(6);
  mcv::placeOutOfSample(X, gpu.coordinates, centres.data(), 2, 10, {}, placed.data());
  for (int c = 0; c < 2; ++c)
  {
    for (const int i : nearestRows(gpu.coordinates, placed.data() + 3 * c, 10))
    {
      EXPECT_EQ(i < n ? 0 : 1, c) << "point " << i << " among the 10 nearest of centre " << c;
    }
  }
}

TEST(UMAPLayoutGPU, BrainFeaturesAgreeWithCpu)
{
  MCV_REQUIRE_GPU();
  if (!mt::haveBrain())
  {
    GTEST_SKIP() << "Colin27 volumes missing (scripts/fetch-data.sh)";
  }
  expectGpuAgreesWithCpu(brainSample(mcv::FeaturePreset::TwentyFourD, 5000), "brain 24D");
  expectGpuAgreesWithCpu(brainSample(mcv::FeaturePreset::SixD, 5000), "brain 6D");
}

TEST(UMAPLayoutGPU, SameSeedSameLayout)
{
  MCV_REQUIRE_GPU();
  RowMatrixF centres;
  const RowMatrixF X = twoBlobs(400, 3, centres);
  const mcv::Embedding a = fit(X, Device::GPU, 5), b = fit(X, Device::GPU, 5), c = fit(X, Device::GPU, 6);
  ASSERT_TRUE(a.error.empty() && b.error.empty() && c.error.empty());
  EXPECT_TRUE(a.coordinates == b.coordinates) << "two GPU runs with seed 5 differ";
  EXPECT_FALSE(a.coordinates == c.coordinates) << "seeds 5 and 6 gave the same GPU layout";
}

// Out of memory (or any failed CUDA call) at the first allocation, the first copy, the
// first launch and the last synchronisation: one warning, the CPU layout bit for bit, and
// the next call runs on the GPU again.
TEST(UMAPLayoutGPU, FailureFallsBackToTheCpuWithOneWarning)
{
  MCV_REQUIRE_GPU();
  RowMatrixF centres;
  const RowMatrixF X = twoBlobs(200, 5, centres);
  const mcv::Embedding cpu = fit(X, Device::CPU, 0);
  mcv::cuda::countCudaCalls(true);
  const mcv::Embedding gpu = fit(X, Device::GPU, 0);
  const long syncs = mcv::cuda::countedCudaCalls("umaplayout", mcv::cuda::CudaCall::Sync);
  mcv::cuda::countCudaCalls(false);
  ASSERT_TRUE(gpu.error.empty());
  ASSERT_GE(syncs, 1);
  const std::pair<mcv::cuda::CudaCall, long> faults[] = { { mcv::cuda::CudaCall::Alloc, 1 },
    { mcv::cuda::CudaCall::Copy, 1 }, { mcv::cuda::CudaCall::Launch, 1 }, { mcv::cuda::CudaCall::Sync, syncs } };
  for (const auto& [kind, nth] : faults)
  {
    SCOPED_TRACE(std::string(mcv::cuda::cudaCallName(kind)) + " #" + std::to_string(nth));
    mcv::cuda::injectFailure("umaplayout", kind, nth);
    const mcv::Embedding fallback = fit(X, Device::GPU, 0);
    EXPECT_FALSE(mcv::cuda::failurePending()) << "the injection did not fire";
    ASSERT_TRUE(fallback.error.empty()) << fallback.error;
    const auto failures = std::count_if(fallback.warnings.begin(), fallback.warnings.end(), mentionsGpuFailure);
    EXPECT_EQ(failures, 1);
    EXPECT_TRUE(fallback.coordinates == cpu.coordinates) << "the fallback is not the CPU layout";
    EXPECT_TRUE(fit(X, Device::GPU, 0).coordinates == gpu.coordinates) << "the GPU did not take over again";
  }
  mcv::cuda::clearInjectedFailure();

  // The same through reduceDimension (Method UMAP, Device GPU): one warning, a result.
  mcv::ReductionOptions ro;
  ro.method = mcv::ReductionMethod::UMAP;
  ro.numberOfNeighbors = 15;
  ro.device = Device::GPU;
  ro.trustworthinessSample = 0;
  mcv::cuda::injectFailure("umaplayout", mcv::cuda::CudaCall::Alloc, 1);
  const mcv::ReductionResult r =
    mcv::reduceDimension({ X.data(), static_cast<std::size_t>(X.rows()), static_cast<int>(X.cols()) }, ro);
  mcv::cuda::clearInjectedFailure();
  ASSERT_TRUE(r.ok()) << r.error;
  EXPECT_EQ(std::count_if(r.warnings.begin(), r.warnings.end(), mentionsGpuFailure), 1);
}

} // namespace
