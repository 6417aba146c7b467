// The reference sample's key scan on the GPU (reduction/cuda/SampleKeysCuda.h) against sampleKey on
// the CPU: the same rows at every limit (none, a few, a fraction, all) and first index; and a
// GPU failure in it leaves the fused reduction's sample as it was, with one warning. Skips
// without a GPU.
#include "FusedRuns.h"
#include "RequireGpu.h"

#include "ReferenceSample.h"
#include "cuda/FaultInjection.h"
#include "cuda/SampleKeysCuda.h"

#include <gtest/gtest.h>

#include <cstdint>
#include <limits>
#include <string>
#include <vector>

namespace
{

namespace mt = mcv::testing;
using mcv::Device;

std::vector<std::size_t> cpuRows(std::uint64_t seed, std::int64_t first, std::size_t n, std::uint64_t limit)
{
  std::vector<std::size_t> rows;
  for (std::size_t r = 0; r < n; ++r)
    if (mcv::sampleKey(seed, first + static_cast<std::int64_t>(r)) <= limit)
      rows.push_back(r);
  return rows;
}

TEST(SampleKeysGPU, RowsBelowALimitAreTheCpus)
{
  MCV_REQUIRE_GPU();
  const std::size_t n = 3000017;
  const std::uint64_t all = std::numeric_limits<std::uint64_t>::max();
  for (const std::uint64_t seed : { std::uint64_t(0), std::uint64_t(12345) })
    for (const std::int64_t first : { std::int64_t(0), std::int64_t(987654321) })
      for (const std::uint64_t limit : { std::uint64_t(0), all >> 20, all >> 6, all >> 1, all })
      {
        SCOPED_TRACE("seed " + std::to_string(seed) + ", first " + std::to_string(first) + ", limit " + std::to_string(limit));
        std::vector<std::size_t> gpu;
        std::string error;
        ASSERT_TRUE(mcv::cuda::rowsWithKeyAtMost(seed, first, n, limit, &gpu, &error)) << error;
        const std::vector<std::size_t> cpu = cpuRows(seed, first, n, limit);
        EXPECT_EQ(gpu, cpu);
        if (limit == all)
          EXPECT_EQ(gpu.size(), n);
      }
}

TEST(SampleKeysGPU, AFailedScanLeavesTheSampleWithOneWarning)
{
  MCV_REQUIRE_GPU();
  const mt::TypedChannels t = mt::randomChannels({ 37, 29, 26 }, 11);
  const mcv::ReductionOptions o = mt::isomapOptions(600, Device::GPU);
  const mt::FusedRun clean = mt::runFused(t.views(), t.grid, o, 0, mcv::FeatureBricks::kDefaultSlabBytes, Device::GPU);
  mcv::cuda::injectFailure("samplekeys", mcv::cuda::CudaCall::Alloc, 1);
  const mt::FusedRun fell = mt::runFused(t.views(), t.grid, o, 0, mcv::FeatureBricks::kDefaultSlabBytes, Device::GPU);
  EXPECT_FALSE(mcv::cuda::failurePending());
  mcv::cuda::clearInjectedFailure();
  int said = 0;
  for (const std::string& w : fell.result.warnings)
    said += w.find("GPU key scan of the reference sample failed") != std::string::npos &&
      w.find("[injected failure]") != std::string::npos;
  EXPECT_EQ(said, 1);
  EXPECT_EQ(fell.result.warnings.size(), clean.result.warnings.size() + 1);
  EXPECT_EQ(fell.result.referenceIndices, clean.result.referenceIndices);
  EXPECT_EQ(fell.result.coordinates, clean.result.coordinates);
}

} // namespace
