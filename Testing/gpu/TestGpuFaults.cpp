// A GPU that fails or runs out of memory mid-run: the CPU takes over with a warning and the
// result is the same. For each GPU path (best viewpoint, features, Gaussian transfer
// function, out-of-sample placement, the fused reduction's slabs) a clean run counts its
// checked CUDA calls, then an out-of-memory is injected (common/cuda/FaultInjection.h) at the
// first and last allocation, the first and last copy, the first launch, the last
// synchronisation and the very last checked call. Each time: exactly one warning naming the GPU failure, deviceUsed CPU, the
// CPU path's result (bit-identical where the CPU path is deterministic) over an output
// prefilled with garbage, and the next call without injection runs on the GPU again with
// the clean GPU result. Device memory after all faults is what it was before (nothing
// leaked). The fused reduction also fails in the middle of its slabs (a launch half way):
// the slabs already down stay the GPU's, the CPU places the rest. The FaultInjection tests
// need no GPU; the others skip without one.
#include "cuda/CudaCheck.h"
#include "cuda/FaultInjection.h"
#include "cuda/HarrisCuda.h"
#include "cuda/HarrisSlabStream.h"

#include "BestViewpoint.h"
#include "FeatureVectors.h"
#include "GaussianTransferFunction.h"
#include "OutOfSample.h"

#include "FusedRuns.h"
#include "RequireGpu.h"
#include "TestVolumes.h"

#include <cuda_runtime.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <limits>
#include <random>
#include <string>
#include <vector>

namespace
{

namespace mt = mcv::testing;
using mcv::Device;
using mcv::ImageGrid;
using mcv::cuda::CudaCall;

// ---------------------------------------------------------------------------------------
// The injection mechanism itself (no GPU needed: the "calls" are host functions whose names
// classify like CUDA's)
// ---------------------------------------------------------------------------------------

cudaError_t cudaMallocFake(int* calls)
{
  ++*calls;
  return cudaSuccess;
}

cudaError_t cudaMemcpyFake(int* calls)
{
  ++*calls;
  return cudaSuccess;
}

// Two allocations and a copy inside `stage`, checked like the GPU paths check theirs.
bool fakeStep(const char* stage, int* calls, std::string* error)
{
  mcv::cuda::FaultStage inside(stage);
  MCV_CUDA_TRY(cudaMallocFake(calls));
  MCV_CUDA_TRY(cudaMallocFake(calls));
  MCV_CUDA_TRY(cudaMemcpyFake(calls));
  return true;
}

TEST(FaultInjection, TheNthCallOfItsKindInItsStageFailsOnce)
{
  int calls = 0;
  std::string error;
  mcv::cuda::injectFailure("features", CudaCall::Alloc, 2);
  EXPECT_TRUE(mcv::cuda::failurePending());
  const long before = mcv::cuda::injectedFailureCount();
  // Another stage is not counted.
  EXPECT_TRUE(fakeStep("harris", &calls, &error)) << error;
  EXPECT_EQ(calls, 3);
  // The second allocation fails without running; the copy after it is never reached.
  calls = 0;
  EXPECT_FALSE(fakeStep("features", &calls, &error));
  EXPECT_EQ(calls, 1);
  EXPECT_NE(error.find("cudaErrorMemoryAllocation"), std::string::npos) << error;
  EXPECT_NE(error.find("cudaMallocFake"), std::string::npos) << error;
  EXPECT_NE(error.find("[injected failure]"), std::string::npos) << error;
  EXPECT_EQ(mcv::cuda::injectedFailureCount(), before + 1);
  EXPECT_FALSE(mcv::cuda::failurePending());
  // Fired once: the next run succeeds.
  calls = 0;
  EXPECT_TRUE(fakeStep("features", &calls, &error)) << error;
  EXPECT_EQ(calls, 3);
}

TEST(FaultInjection, KindsCountSeparatelyAndAnyCountsAll)
{
  int calls = 0;
  std::string error;
  mcv::cuda::injectFailure("outofsample", CudaCall::Copy, 2);
  EXPECT_TRUE(fakeStep("outofsample", &calls, &error)) << error; // copy #1
  EXPECT_FALSE(fakeStep("outofsample", &calls, &error));         // copy #2
  EXPECT_EQ(calls, 5);
  mcv::cuda::injectFailure("outofsample", CudaCall::Any, 2);
  calls = 0;
  EXPECT_FALSE(fakeStep("outofsample", &calls, &error)); // the second call of any kind
  EXPECT_EQ(calls, 1);
  // Counting.
  mcv::cuda::countCudaCalls(true);
  EXPECT_TRUE(fakeStep("gaussiantf", &calls, &error)) << error;
  EXPECT_TRUE(fakeStep("gaussiantf", &calls, &error)) << error;
  mcv::cuda::countCudaCalls(false);
  EXPECT_EQ(mcv::cuda::countedCudaCalls("gaussiantf", CudaCall::Alloc), 4);
  EXPECT_EQ(mcv::cuda::countedCudaCalls("gaussiantf", CudaCall::Copy), 2);
  EXPECT_EQ(mcv::cuda::countedCudaCalls("gaussiantf", CudaCall::Any), 6);
  EXPECT_EQ(mcv::cuda::countedCudaCalls("harris", CudaCall::Any), 0);
}

TEST(FaultInjection, SpecsAreParsedLikeTheEnvironmentVariable)
{
  std::string error;
  EXPECT_TRUE(mcv::cuda::injectFailure("harris:3", &error)) << error;
  EXPECT_TRUE(mcv::cuda::failurePending());
  mcv::cuda::clearInjectedFailure();
  EXPECT_FALSE(mcv::cuda::failurePending());
  EXPECT_TRUE(mcv::cuda::injectFailure("features:copy:1", &error)) << error;
  mcv::cuda::clearInjectedFailure();
  for (const char* bad : { "harris", "harris:0", "harris:x", "harris:copy:", "nowhere:1",
         "features:memcpy:2", "features::2", ":1" })
  {
    error.clear();
    EXPECT_FALSE(mcv::cuda::injectFailure(bad, &error)) << bad;
    EXPECT_FALSE(error.empty()) << bad;
    EXPECT_FALSE(mcv::cuda::failurePending()) << bad;
  }
}

// ---------------------------------------------------------------------------------------
// Helpers of the GPU tests
// ---------------------------------------------------------------------------------------

struct Point
{
  CudaCall kind;
  long n;
};

std::string describe(const Point& p)
{
  return std::string(mcv::cuda::cudaCallName(p.kind)) + " #" + std::to_string(p.n);
}

// Counts the checked CUDA calls of `stage` during one clean `run` and picks the injection
// points: first and last allocation, first and last copy, first launch, last sync, last call.
// A first run is not counted: once-only setup (streams, events, loading kernels) is done.
template <class Run>
std::vector<Point> injectionPoints(const char* stage, Run&& run)
{
  run();
  mcv::cuda::countCudaCalls(true);
  run();
  auto count = [&](CudaCall k) { return mcv::cuda::countedCudaCalls(stage, k); };
  const long alloc = count(CudaCall::Alloc), copy = count(CudaCall::Copy);
  const long launch = count(CudaCall::Launch), sync = count(CudaCall::Sync);
  const long any = count(CudaCall::Any);
  mcv::cuda::countCudaCalls(false);
  std::printf("[ faults ] %s: %ld allocations, %ld copies, %ld launches, %ld syncs, %ld checked "
              "calls\n",
    stage, alloc, copy, launch, sync, any);
  EXPECT_GT(alloc, 0) << stage;
  EXPECT_GT(copy, 0) << stage;
  std::vector<Point> points;
  for (const Point& p : { Point{ CudaCall::Alloc, 1 }, Point{ CudaCall::Alloc, alloc },
         Point{ CudaCall::Copy, 1 }, Point{ CudaCall::Copy, copy }, Point{ CudaCall::Launch, 1 },
         Point{ CudaCall::Sync, sync }, Point{ CudaCall::Any, any } })
  {
    const bool seen = std::any_of(points.begin(), points.end(),
      [&](const Point& q) { return q.kind == p.kind && q.n == p.n; });
    if (p.n >= 1 && !seen)
    {
      points.push_back(p);
    }
  }
  return points;
}

// Runs `run` with one failure injected at `p` of `stage`; the injection must fire.
template <class Run>
auto runWithFault(const char* stage, const Point& p, Run&& run) -> decltype(run())
{
  const long before = mcv::cuda::injectedFailureCount();
  mcv::cuda::injectFailure(stage, p.kind, p.n);
  auto result = run();
  EXPECT_FALSE(mcv::cuda::failurePending()) << "injection point never reached";
  mcv::cuda::clearInjectedFailure();
  EXPECT_EQ(mcv::cuda::injectedFailureCount(), before + 1);
  return result;
}

bool isFaultWarning(const std::string& w)
{
  return w.find("[injected failure]") != std::string::npos;
}

// Exactly one warning tells of the failure: the GPU failed, why, and that the CPU ran.
// Returns the other warnings.
std::vector<std::string> expectOneFaultWarning(const std::vector<std::string>& warnings)
{
  std::vector<std::string> rest;
  std::string all, fault;
  int faults = 0;
  for (const std::string& w : warnings)
  {
    all += "\n  " + w;
    if (isFaultWarning(w))
    {
      ++faults;
      fault = w;
    }
    else
    {
      rest.push_back(w);
    }
  }
  EXPECT_EQ(faults, 1) << "warnings:" << all;
  EXPECT_NE(fault.find("GPU"), std::string::npos) << fault;
  EXPECT_NE(fault.find("failed"), std::string::npos) << fault;
  EXPECT_NE(fault.find("cudaErrorMemoryAllocation"), std::string::npos) << fault;
  EXPECT_NE(fault.find("CPU"), std::string::npos) << fault;
  return rest;
}

template <class T>
bool sameBits(const std::vector<T>& a, const std::vector<T>& b)
{
  return a.size() == b.size() && std::memcmp(a.data(), b.data(), a.size() * sizeof(T)) == 0;
}

void releaseDeviceCaches()
{
  mcv::cuda::releaseHarrisCache();
  mcv::releaseGaussianWidgetDeviceCache();
}

std::size_t freeDeviceMemory()
{
  std::size_t free = 0, total = 0;
  return cudaMemGetInfo(&free, &total) == cudaSuccess ? free : 0;
}

// Every test's data is sized so that one run's leaked buffers would exceed this.
constexpr std::size_t kLeakSlack = std::size_t(8) << 20;

// Records free device memory (caches released) and checks it again when it goes out of
// scope. Made after the clean GPU runs, so that what the driver keeps once a kernel has run
// (code, local memory) is in the baseline.
class LeakCheck
{
public:
  LeakCheck()
  {
    releaseDeviceCaches();
    before_ = freeDeviceMemory();
  }
  ~LeakCheck()
  {
    releaseDeviceCaches();
    const std::size_t after = freeDeviceMemory();
    EXPECT_GE(after + kLeakSlack, before_)
      << "device memory not given back after the faults: " << (before_ - after) << " bytes";
  }

private:
  std::size_t before_ = 0;
};

// ---------------------------------------------------------------------------------------
// Best viewpoint (Harris + top-N)
// ---------------------------------------------------------------------------------------

mcv::BestViewpointResult viewpoint(const std::vector<float>& opacity, const ImageGrid& grid,
  Device device, int N, const mcv::GridPiece& piece = {})
{
  mcv::BestViewpointOptions o;
  o.device = device;
  o.numberOfInterestPoints = N;
  o.piece = piece;
  mcv::BestViewpointResult r = mcv::computeBestViewpoint(opacity.data(), grid, o);
  EXPECT_TRUE(r.ok()) << r.error;
  return r;
}

void expectSameViewpoint(const mcv::BestViewpointResult& a, const mcv::BestViewpointResult& b)
{
  EXPECT_EQ(a.points.indices, b.points.indices);
  EXPECT_TRUE(sameBits(a.points.scores, b.points.scores));
  EXPECT_EQ(a.view.valid, b.view.valid);
  EXPECT_EQ(a.view.best, b.view.best);
  EXPECT_EQ(a.view.worst, b.view.worst);
  EXPECT_EQ(a.view.viewUp, b.view.viewUp);
  EXPECT_EQ(a.view.eigenvalues, b.view.eigenvalues);
}

void viewpointFaults(const std::vector<float>& opacity, const ImageGrid& grid, int N,
  const mcv::GridPiece& piece = {})
{
  const mcv::BestViewpointResult cpu = viewpoint(opacity, grid, Device::CPU, N, piece);
  ASSERT_GT(cpu.points.size(), 0u);
  mcv::BestViewpointResult gpu;
  const std::vector<Point> points = injectionPoints("harris", [&] {
    releaseDeviceCaches();
    gpu = viewpoint(opacity, grid, Device::GPU, N, piece);
  });
  ASSERT_EQ(gpu.deviceUsed, Device::GPU) << (gpu.warnings.empty() ? "" : gpu.warnings.back());
  LeakCheck leaks;
  for (const Point& p : points)
  {
    SCOPED_TRACE("harris, failure at " + describe(p));
    releaseDeviceCaches(); // the state of the counting run
    const mcv::BestViewpointResult fell =
      runWithFault("harris", p, [&] { return viewpoint(opacity, grid, Device::GPU, N, piece); });
    EXPECT_EQ(fell.deviceUsed, Device::CPU);
    EXPECT_EQ(expectOneFaultWarning(fell.warnings), cpu.warnings);
    expectSameViewpoint(fell, cpu);
    // The GPU works again (its buffers were given back and are allocated anew).
    const mcv::BestViewpointResult again = viewpoint(opacity, grid, Device::GPU, N, piece);
    EXPECT_EQ(again.deviceUsed, Device::GPU);
    EXPECT_EQ(again.warnings, gpu.warnings);
    expectSameViewpoint(again, gpu);
  }
}

TEST(GpuFaults, BestViewpointFallsBackAtEveryFailurePoint)
{
  MCV_REQUIRE_GPU();
  const mt::Volume v = mt::structuredVolume(144);
  // 2048: the fast selection; 4096: the slow one (CUB, more allocations after the kernel).
  for (int N : { 2048, 4096 })
  {
    SCOPED_TRACE("N = " + std::to_string(N));
    viewpointFaults(v.values, v.grid, N);
  }
}

// The same under a device budget that sends the volume through the GPU in 4 z-slabs
// (HarrisSlabStream): a failure in any slab falls back to the CPU, frees the slab buffers,
// and the next call streams again with the same result.
TEST(GpuFaults, BestViewpointInSlabsFallsBackAtEveryFailurePoint)
{
  MCV_REQUIRE_GPU();
  const mt::Volume v = mt::structuredVolume(144);
  const std::size_t planeBytes = 144 * 144 * sizeof(float);
  // float: 2 x (S + 6) input slices + S score slices + the selection reserve -> S = 40.
  mcv::cuda::setHarrisDeviceBudget(mcv::cuda::kSelectionReserveBytes + (12 + 3 * 40) * planeBytes);
  mcv::InterestPoints points;
  mcv::cuda::GpuStageTimings timings;
  std::string error;
  EXPECT_TRUE(mcv::cuda::harrisTopN(
    v.values.data(), v.grid, mcv::HarrisParameters(), 2048, points, &error, &timings)) << error;
  EXPECT_EQ(timings.slabs, 4);
  viewpointFaults(v.values, v.grid, 2048);
  mcv::cuda::setHarrisDeviceBudget(0);
  releaseDeviceCaches();
}

TEST(GpuFaults, BestViewpointOfABlockFallsBack)
{
  MCV_REQUIRE_GPU();
  // A block that owns an inner box (split over processes): the response comes back whole.
  const mt::Volume v = mt::structuredVolume(144);
  mcv::GridPiece piece = mcv::GridPiece::whole(v.grid);
  for (int a = 0; a < 3; ++a)
  {
    piece.ownedLo[a] = 4;
    piece.ownedHi[a] = v.grid.dims[a] - 5;
  }
  viewpointFaults(v.values, v.grid, 2048, piece);
}

// ---------------------------------------------------------------------------------------
// Feature vectors
// ---------------------------------------------------------------------------------------

struct FeatureRun
{
  std::vector<float> m;
  mcv::FeatureResult r;
};

FeatureRun features(const std::vector<std::vector<float>>& channels, const ImageGrid& grid,
  mcv::FeaturePreset preset, mcv::FeatureNormalization norm, Device device)
{
  std::vector<mcv::ChannelView> views;
  for (const std::vector<float>& c : channels)
  {
    mcv::ChannelView view;
    view.data = c.data();
    views.push_back(view);
  }
  mcv::FeatureOptions o;
  o.preset = preset;
  o.normalization = norm;
  o.device = device;
  const int F = mcv::featureCount(views.size(), o);
  FeatureRun run;
  run.m.assign(grid.voxelCount() * F, -12345.0f); // garbage a half-written output would show
  EXPECT_TRUE(mcv::computeFeatures(views, grid, o, { run.m.data(), grid.voxelCount(), F }, run.r))
    << run.r.error;
  return run;
}

// Bit-identical, or (ZScore: the statistics are sums in another order) within `tolerance`
// relative.
void expectSameFeatures(const FeatureRun& a, const FeatureRun& b, double tolerance)
{
  EXPECT_EQ(a.r.names, b.r.names);
  EXPECT_EQ(a.r.nonFiniteVoxels, b.r.nonFiniteVoxels);
  EXPECT_EQ(a.r.constantColumns, b.r.constantColumns);
  ASSERT_EQ(a.m.size(), b.m.size());
  if (tolerance == 0)
  {
    EXPECT_TRUE(sameBits(a.m, b.m));
    return;
  }
  double worst = 0;
  for (std::size_t i = 0; i < a.m.size(); ++i)
  {
    worst = std::max(worst,
      std::fabs(double(a.m[i]) - double(b.m[i])) / std::max(1.0, std::fabs(double(b.m[i]))));
  }
  EXPECT_LE(worst, tolerance);
}

void featureFaults(int n, mcv::FeaturePreset preset, mcv::FeatureNormalization norm, double tolerance)
{
  std::vector<std::vector<float>> channels{ mt::structuredVolume(n, 7).values,
    mt::structuredVolume(n, 11).values };
  // A few NaN/Inf voxels: the mask and the masked normalisation run too.
  channels[1][12345] = std::numeric_limits<float>::quiet_NaN();
  channels[1][67890] = std::numeric_limits<float>::infinity();
  const ImageGrid grid = mt::makeGrid(n, n, n);
  const FeatureRun cpu = features(channels, grid, preset, norm, Device::CPU);
  ASSERT_EQ(cpu.r.nonFiniteVoxels, 2u);
  FeatureRun gpu;
  const std::vector<Point> points = injectionPoints(
    "features", [&] { gpu = features(channels, grid, preset, norm, Device::GPU); });
  ASSERT_EQ(gpu.r.deviceUsed, Device::GPU);
  LeakCheck leaks;
  for (const Point& p : points)
  {
    SCOPED_TRACE("features, failure at " + describe(p));
    const FeatureRun fell = runWithFault(
      "features", p, [&] { return features(channels, grid, preset, norm, Device::GPU); });
    EXPECT_EQ(fell.r.deviceUsed, Device::CPU);
    EXPECT_EQ(expectOneFaultWarning(fell.r.warnings), cpu.r.warnings);
    expectSameFeatures(fell, cpu, tolerance);
    const FeatureRun again = features(channels, grid, preset, norm, Device::GPU);
    EXPECT_EQ(again.r.deviceUsed, Device::GPU);
    EXPECT_EQ(again.r.warnings, gpu.r.warnings);
    expectSameFeatures(again, gpu, tolerance);
  }
}

TEST(GpuFaults, FeaturesFallBackAtEveryFailurePoint)
{
  MCV_REQUIRE_GPU();
  // Raw features: the CPU path is deterministic, the fallback bit-identical to it.
  featureFaults(128, mcv::FeaturePreset::SixD, mcv::FeatureNormalization::None, 0.0);
}

TEST(GpuFaults, NormalizedFeaturesFallBackAtEveryFailurePoint)
{
  MCV_REQUIRE_GPU();
  // ZScore: more steps (two statistics passes, the mean upload, the normalisation); the
  // sums' order differs between runs, so 1e-5 relative.
  featureFaults(96, mcv::FeaturePreset::TwentyFourD, mcv::FeatureNormalization::ZScore, 1e-5);
}

// ---------------------------------------------------------------------------------------
// Gaussian transfer function
// ---------------------------------------------------------------------------------------

template <class T>
struct TFRun
{
  std::vector<T> out;
  mcv::TransferFunctionRun r;
};

template <class T>
TFRun<T> shade(const mcv::CoordinateView& view, const std::vector<mcv::GaussianWidget>& widgets,
  Device device)
{
  TFRun<T> run;
  run.out.assign(4 * view.count, T(77)); // garbage a half-written output would show
  run.r = mcv::applyGaussianWidgets(view, widgets, run.out.data(), device);
  EXPECT_TRUE(run.r.ok()) << run.r.error;
  return run;
}

template <class T>
void transferFunctionFaults(const mcv::CoordinateView& view,
  const std::vector<mcv::GaussianWidget>& widgets, const char* label)
{
  SCOPED_TRACE(label);
  const TFRun<T> cpu = shade<T>(view, widgets, Device::CPU);
  TFRun<T> gpu;
  const std::vector<Point> points = injectionPoints("gaussiantf", [&] {
    releaseDeviceCaches();
    gpu = shade<T>(view, widgets, Device::GPU);
  });
  ASSERT_EQ(gpu.r.deviceUsed, Device::GPU);
  LeakCheck leaks;
  for (const Point& p : points)
  {
    SCOPED_TRACE("gaussiantf, failure at " + describe(p));
    releaseDeviceCaches();
    const TFRun<T> fell =
      runWithFault("gaussiantf", p, [&] { return shade<T>(view, widgets, Device::GPU); });
    EXPECT_EQ(fell.r.deviceUsed, Device::CPU);
    EXPECT_EQ(expectOneFaultWarning(fell.r.warnings), cpu.r.warnings);
    EXPECT_TRUE(sameBits(fell.out, cpu.out));
    // Same coordinates and version: what the failed call left resident must not be reused.
    const TFRun<T> again = shade<T>(view, widgets, Device::GPU);
    EXPECT_EQ(again.r.deviceUsed, Device::GPU);
    EXPECT_TRUE(sameBits(again.out, gpu.out));
  }
}

TEST(GpuFaults, GaussianTransferFunctionFallsBackAtEveryFailurePoint)
{
  MCV_REQUIRE_GPU();
  std::mt19937 rng(5);
  std::uniform_real_distribution<float> box(-1.f, 2.f);
  std::vector<float> coords(3 * (std::size_t(1) << 20));
  for (float& x : coords)
    x = box(rng);
  coords[300] = std::numeric_limits<float>::quiet_NaN();
  std::uniform_real_distribution<double> unit(0, 1);
  std::vector<mcv::GaussianWidget> widgets(8);
  for (mcv::GaussianWidget& w : widgets)
  {
    for (int d = 0; d < 3; ++d)
    {
      w.center[d] = unit(rng);
      w.color[d] = unit(rng);
    }
    w.sigma = 0.05 + 0.3 * unit(rng);
    w.opacity = 0.2 + 0.8 * unit(rng);
  }
  // A non-zero version: the device keeps the coordinates between calls.
  const mcv::CoordinateView view{ coords.data(), coords.size() / 3, 3, 42 };
  transferFunctionFaults<float>(view, widgets, "float RGBA");
  transferFunctionFaults<unsigned char>(view, widgets, "byte RGBA");
}

// ---------------------------------------------------------------------------------------
// Out-of-sample placement
// ---------------------------------------------------------------------------------------

struct Placed
{
  std::vector<float> y;
  std::vector<std::uint32_t> nb;
  mcv::OutOfSampleReport report;
};

Placed place(const mcv::RowMatrixF& refX, const mcv::RowMatrixF& refY, const std::vector<float>& rows,
  int dim, const std::vector<int>& columns, Device device)
{
  const std::size_t n = rows.size() / dim;
  Placed p;
  p.y.assign(n * refY.cols(), -5.f); // garbage a half-written output would show
  p.nb.assign(n * 3, 0xdeadbeefu);
  mcv::OutOfSampleOptions o;
  o.device = device;
  p.report = mcv::placeOutOfSample(refX, refY, rows.data(), n, dim, columns, p.y.data(), o, p.nb.data());
  return p;
}

TEST(GpuFaults, OutOfSamplePlacementFallsBackAtEveryFailurePoint)
{
  MCV_REQUIRE_GPU();
  std::mt19937 rng(17);
  std::normal_distribution<float> g(0.f, 1.f);
  const int D = 8, dim = 10;
  mcv::RowMatrixF refX(2000, D), refY(2000, 2);
  for (Eigen::Index i = 0; i < refX.size(); ++i)
    refX.data()[i] = g(rng);
  for (Eigen::Index i = 0; i < refY.size(); ++i)
    refY.data()[i] = g(rng);
  std::vector<float> rows((std::size_t(1) << 18) * dim);
  for (float& x : rows)
    x = g(rng);
  const std::vector<int> columns{ 0, 1, 2, 4, 5, 6, 8, 9 }; // D of the dim columns

  const Placed cpu = place(refX, refY, rows, dim, columns, Device::CPU);
  Placed gpu;
  const std::vector<Point> points = injectionPoints(
    "outofsample", [&] { gpu = place(refX, refY, rows, dim, columns, Device::GPU); });
  ASSERT_EQ(gpu.report.deviceUsed, Device::GPU)
    << (gpu.report.warnings.empty() ? "" : gpu.report.warnings.back());
  LeakCheck leaks;
  for (const Point& p : points)
  {
    SCOPED_TRACE("outofsample, failure at " + describe(p));
    const Placed fell = runWithFault(
      "outofsample", p, [&] { return place(refX, refY, rows, dim, columns, Device::GPU); });
    EXPECT_EQ(fell.report.deviceUsed, Device::CPU);
    EXPECT_EQ(expectOneFaultWarning(fell.report.warnings), cpu.report.warnings);
    EXPECT_TRUE(sameBits(fell.y, cpu.y));
    EXPECT_EQ(fell.nb, cpu.nb);
    const Placed again = place(refX, refY, rows, dim, columns, Device::GPU);
    EXPECT_EQ(again.report.deviceUsed, Device::GPU);
    EXPECT_TRUE(again.report.warnings.empty());
    EXPECT_TRUE(sameBits(again.y, gpu.y));
    EXPECT_EQ(again.nb, gpu.nb);
  }
}

// ---------------------------------------------------------------------------------------
// The fused reduction's GPU slabs (features + placement on the device, FusedPlacementCuda.h)
// ---------------------------------------------------------------------------------------

// The voxels the GPU had placed when it failed, from the warning ("... after X of N voxels").
std::size_t voxelsPlacedBeforeTheFault(const std::vector<std::string>& warnings)
{
  for (const std::string& w : warnings)
  {
    const std::size_t at = w.find("failed after ");
    if (isFaultWarning(w) && at != std::string::npos)
    {
      return static_cast<std::size_t>(std::stoull(w.substr(at + 13)));
    }
  }
  return static_cast<std::size_t>(-1);
}

TEST(GpuFaults, FusedPlacementFallsBackAtEveryFailurePoint)
{
  MCV_REQUIRE_GPU();
  const mt::TypedChannels t = mt::randomChannels({ 31, 27, 24 }, 3);
  const std::size_t voxels = t.grid.voxelCount();
  const std::size_t budget = mt::budgetForSlices(t.grid, 3, 24, 500, 3, 3);
  const mt::FusedRun cpu = mt::runFused(t.views(), t.grid, mt::isomapOptions(500, Device::CPU), 0);
  const float range = mt::coordinateRange(cpu.result.coordinates);
  auto runGpu = [&] { return mt::runFused(t.views(), t.grid, mt::isomapOptions(500, Device::GPU), budget); };
  mt::FusedRun gpu;
  std::vector<Point> points = injectionPoints("fused", [&] { gpu = runGpu(); });
  ASSERT_EQ(gpu.result.deviceUsed, Device::GPU);
  ASSERT_GE(gpu.stats.slabs, 6u);
  // Also a launch in the middle of the run: a slab half way fails after earlier ones are done.
  mcv::cuda::countCudaCalls(true);
  runGpu();
  const long launches = mcv::cuda::countedCudaCalls("fused", CudaCall::Launch);
  mcv::cuda::countCudaCalls(false);
  points.push_back(Point{ CudaCall::Launch, launches / 2 });
  LeakCheck leaks;
  for (const Point& p : points)
  {
    SCOPED_TRACE("fused, failure at " + describe(p));
    const mt::FusedRun fell = runWithFault("fused", p, runGpu);
    ASSERT_TRUE(fell.result.ok()) << fell.result.error;
    EXPECT_EQ(expectOneFaultWarning(fell.result.warnings), gpu.result.warnings);
    const std::size_t placed = voxelsPlacedBeforeTheFault(fell.result.warnings);
    ASSERT_LE(placed, voxels);
    EXPECT_EQ(fell.result.deviceUsed, placed == voxels ? Device::GPU : Device::CPU);
    if (p.kind == CudaCall::Launch && p.n > 1)
    {
      EXPECT_GT(placed, 0u); // slabs before the fault stay the GPU's
      EXPECT_LT(placed, voxels);
    }
    EXPECT_LE(mt::maxDifference(fell.result.coordinates, cpu.result.coordinates), 1e-5f * range);
    // The rows the GPU placed are its own, the rest the CPU's.
    const std::size_t split = std::min(placed, voxels) * 3;
    EXPECT_TRUE(std::equal(fell.result.coordinates.begin(), fell.result.coordinates.begin() + split,
      gpu.result.coordinates.begin()));
    EXPECT_TRUE(std::equal(fell.result.coordinates.begin() + split, fell.result.coordinates.end(),
      cpu.result.coordinates.begin() + split));
    // The GPU works again.
    const mt::FusedRun again = runGpu();
    EXPECT_EQ(again.result.deviceUsed, Device::GPU);
    EXPECT_EQ(again.result.coordinates, gpu.result.coordinates);
  }
}

// The fused reduction's other GPU passes (statistics, column sums, strata:
// FusedPassesCuda.h): a failure at any point reruns that pass on the CPU with one warning.
// The column sums and strata are the CPU's bits, so only a failed statistics pass (the CPU's
// sums in another order) may move the coordinates, by rounding.
TEST(GpuFaults, FusedPassesFallBackAtEveryFailurePoint)
{
  MCV_REQUIRE_GPU();
  const mt::TypedChannels t = mt::randomChannels({ 31, 27, 24 }, 3);
  const std::size_t budget = mt::budgetForSlices(t.grid, 3, 24, 500, 3, 3);
  auto runGpu = [&] {
    return mt::runFused(t.views(), t.grid, mt::isomapOptions(500, Device::GPU), budget,
      mcv::FeatureBricks::kDefaultSlabBytes, Device::GPU);
  };
  auto warnings = [](const mt::FusedRun& r) {
    std::vector<std::string> all = r.prepared.warnings;
    all.insert(all.end(), r.result.warnings.begin(), r.result.warnings.end());
    return all;
  };
  mt::FusedRun gpu;
  const std::vector<Point> points = injectionPoints("fusedpasses", [&] { gpu = runGpu(); });
  ASSERT_EQ(gpu.passesOnDevice, 3);
  const float range = mt::coordinateRange(gpu.result.coordinates);
  LeakCheck leaks;
  for (const Point& p : points)
  {
    SCOPED_TRACE("fusedpasses, failure at " + describe(p));
    const mt::FusedRun fell = runWithFault("fusedpasses", p, runGpu);
    ASSERT_TRUE(fell.result.ok()) << fell.result.error;
    EXPECT_EQ(fell.passesOnDevice, 2);
    EXPECT_EQ(expectOneFaultWarning(warnings(fell)), warnings(gpu));
    EXPECT_EQ(fell.result.referenceIndices, gpu.result.referenceIndices);
    EXPECT_LE(mt::maxDifference(fell.result.coordinates, gpu.result.coordinates), 1e-5f * range);
  }
}

} // namespace
