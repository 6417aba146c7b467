// The memory check of the filters (Filters/Core/common/MemoryBudget.h): the estimates follow their
// formulas and saturate instead of wrapping, the check passes up to the limit and fails
// one byte above it, the message says how much is needed and how much there is, and the
// limit comes from MCV_MEMORY_LIMIT_MB when set, else from the system.
#include "MemoryBudget.h"

#include <gtest/gtest.h>

#include <cstdlib>
#include <fstream>
#include <limits>
#include <string>

#include <sys/resource.h>

namespace
{

constexpr std::size_t kMiB = std::size_t(1) << 20;
constexpr std::size_t kGiB = std::size_t(1) << 30;
constexpr std::size_t kMax = std::numeric_limits<std::size_t>::max();

// Sets MCV_MEMORY_LIMIT_MB (or unsets it) for one test; restores the old value.
class MemoryLimit
{
public:
  explicit MemoryLimit(const char* value)
  {
    const char* old = std::getenv("MCV_MEMORY_LIMIT_MB");
    had_ = old != nullptr;
    old_ = old ? old : "";
    if (value)
    {
      setenv("MCV_MEMORY_LIMIT_MB", value, 1);
    }
    else
    {
      unsetenv("MCV_MEMORY_LIMIT_MB");
    }
  }
  ~MemoryLimit()
  {
    if (had_)
    {
      setenv("MCV_MEMORY_LIMIT_MB", old_.c_str(), 1);
    }
    else
    {
      unsetenv("MCV_MEMORY_LIMIT_MB");
    }
  }

private:
  bool had_ = false;
  std::string old_;
};

bool contains(const std::string& text, const std::string& part)
{
  return text.find(part) != std::string::npos;
}

} // namespace

TEST(MemoryBudget, EstimatesFollowTheirFormulas)
{
  // Features: output n x F floats + one float channel + one mask byte per voxel.
  EXPECT_EQ(mcv::featureBytes(1000, 24), 1000u * 24 * 4 + 1000 * 4 + 1000);
  EXPECT_EQ(mcv::featureBytes(1000, 6), 1000u * 6 * 4 + 1000 * 4 + 1000);
  // Reduction: n x d float coordinates, plus a float copy of non-float input.
  EXPECT_EQ(mcv::reductionBytes(1000, 24, 3, true), 1000u * 3 * 4);
  EXPECT_EQ(mcv::reductionBytes(1000, 24, 3, false), 1000u * 3 * 4 + 1000 * 24 * 4);
  // Best viewpoint: opacity + response.
  EXPECT_EQ(mcv::viewpointBytes(1000), 8000u);
  EXPECT_EQ(mcv::featureBytes(0, 24), 0u);
  EXPECT_EQ(mcv::featureBytes(10, -3), 10u * 4 + 10); // no negative column count
}

TEST(MemoryBudget, EstimatesSaturateInsteadOfWrapping)
{
  EXPECT_EQ(mcv::featureBytes(kMax / 8, 24), kMax);
  EXPECT_EQ(mcv::reductionBytes(kMax / 2, 24, 3, false), kMax);
  EXPECT_EQ(mcv::viewpointBytes(kMax / 4), kMax);
  MemoryLimit limit("1024");
  EXPECT_FALSE(mcv::checkFeatureMemory(kMax / 8, 24).empty());
}

TEST(MemoryBudget, FitsUpToTheLimitAndNotOneByteMore)
{
  MemoryLimit limit("100");
  EXPECT_EQ(mcv::availableMemoryBytes(), 100 * kMiB);
  EXPECT_EQ(mcv::checkMemory(0, "X"), "");
  EXPECT_EQ(mcv::checkMemory(50 * kMiB, "X"), "");
  EXPECT_EQ(mcv::checkMemory(100 * kMiB, "X"), "");
  const std::string message = mcv::checkMemory(100 * kMiB + 1, "X");
  EXPECT_EQ(message,
    "X needs 100.1 MiB but only 100.0 MiB is available on this process; crop or subsample the "
    "volume, or run on more MPI ranks (mpiexec -np R pvbatch --mpi) so that each holds a "
    "smaller piece.");
}

TEST(MemoryBudget, FeatureMessageSaysWhatIsNeededAndWhatThereIs)
{
  MemoryLimit limit("1229"); // 1.2 GiB
  // 30 M voxels x 24 features: 30e6 x (96 + 4 + 1) bytes = 2.82 GiB, rounded up.
  EXPECT_EQ(mcv::checkFeatureMemory(30000000, 24),
    "MultichannelFeatures needs 2.9 GiB for 30.0 M voxels x 24 features but only 1.2 GiB is "
    "available on this process; use fewer features, crop or subsample the volume, or run on "
    "more MPI ranks (mpiexec -np R pvbatch --mpi) so that each holds a smaller piece.");
  // 7.1 M voxels x 6 features fit (0.2 GiB).
  EXPECT_EQ(mcv::checkFeatureMemory(7100000, 6), "");
}

TEST(MemoryBudget, ReductionAndViewpointMessages)
{
  MemoryLimit limit("64");
  const std::string reduction = mcv::checkReductionMemory(20000000, 24, 3, false);
  EXPECT_TRUE(contains(reduction, "DimensionReduction needs 2.1 GiB for 20.0 M points x 3 "
                                  "coordinates (and a float copy of the 24 input features)"))
    << reduction;
  EXPECT_TRUE(contains(reduction, "but only 64.0 MiB is available on this process")) << reduction;
  EXPECT_TRUE(contains(reduction, "mpiexec -np R pvbatch --mpi")) << reduction;
  const std::string view = mcv::checkViewpointMemory(512u * 512 * 512);
  EXPECT_TRUE(contains(view, "BestViewpoint needs 1.0 GiB for 134.2 M voxels")) << view;
  EXPECT_EQ(mcv::checkViewpointMemory(1000000), ""); // 7.6 MiB
}

TEST(MemoryBudget, ZeroLimitRefusesEverythingButNothing)
{
  MemoryLimit limit("0");
  EXPECT_EQ(mcv::availableMemoryBytes(), 0u);
  EXPECT_EQ(mcv::checkMemory(0, "X"), "");
  EXPECT_TRUE(contains(mcv::checkMemory(1, "X"), "X needs 1 B but only 0 B is available"));
}

TEST(MemoryBudget, SystemMemoryWhenNoLimitIsSet)
{
  std::size_t system = 0;
  {
    MemoryLimit limit(nullptr);
    system = mcv::availableMemoryBytes();
  }
  EXPECT_GT(system, 0u);
  std::ifstream meminfo("/proc/meminfo");
  if (meminfo)
  {
    // Never more than the machine has.
    std::string key;
    unsigned long long kib = 0;
    ASSERT_TRUE(meminfo >> key >> kib);
    EXPECT_EQ(key, "MemTotal:");
    EXPECT_LE(system, kib * 1024);
  }
  // A value that is not a number >= 0 is ignored.
  for (const char* bad : { "", "abc", "-5", "12MB" })
  {
    MemoryLimit limit(bad);
    EXPECT_NE(mcv::availableMemoryBytes(), 0u) << bad;
    EXPECT_LE(mcv::availableMemoryBytes(), system + kGiB) << bad; // memory may change a little
  }
}

TEST(MemoryBudget, AddressSpaceLimitCounts)
{
  // ulimit -v: the memory left is what the limit leaves above the current virtual size,
  // however much the machine has free.
  MemoryLimit noEnvironmentLimit(nullptr);
  rlimit saved{};
  ASSERT_EQ(getrlimit(RLIMIT_AS, &saved), 0);
  std::ifstream status("/proc/self/status");
  std::string line;
  unsigned long long vmKiB = 0;
  while (std::getline(status, line))
  {
    if (line.rfind("VmSize:", 0) == 0)
    {
      vmKiB = std::stoull(line.substr(7));
    }
  }
  ASSERT_GT(vmKiB, 0u);
  const unsigned long long room = 256ull << 20;
  rlimit lowered = saved;
  lowered.rlim_cur = vmKiB * 1024 + room;
  if (saved.rlim_max != RLIM_INFINITY && lowered.rlim_cur > saved.rlim_max)
  {
    GTEST_SKIP() << "the hard address-space limit is already below the test's";
  }
  ASSERT_EQ(setrlimit(RLIMIT_AS, &lowered), 0);
  const std::size_t available = mcv::availableMemoryBytes();
  ASSERT_EQ(setrlimit(RLIMIT_AS, &saved), 0);
  EXPECT_LE(available, room);
  EXPECT_GT(available, room / 2); // the virtual size grew a little at most
}

TEST(MemoryBudget, Formatting)
{
  EXPECT_EQ(mcv::formatBytes(0), "0 B");
  EXPECT_EQ(mcv::formatBytes(1023), "1023 B");
  EXPECT_EQ(mcv::formatBytes(1536), "1.5 KiB");
  EXPECT_EQ(mcv::formatBytes(kGiB), "1.0 GiB");
  EXPECT_EQ(mcv::formatBytes(kGiB, true), "1.0 GiB");
  EXPECT_EQ(mcv::formatBytes(kGiB + 1), "1.0 GiB");
  EXPECT_EQ(mcv::formatBytes(kGiB + 1, true), "1.1 GiB");
  EXPECT_EQ(mcv::formatBytes(3 * kGiB / 2), "1.5 GiB");
  EXPECT_EQ(mcv::formatBytes(kMax), "16.0 EiB");
  EXPECT_EQ(mcv::formatCount(950), "950");
  EXPECT_EQ(mcv::formatCount(12345), "12.3 k");
  EXPECT_EQ(mcv::formatCount(7100000), "7.1 M");
  EXPECT_EQ(mcv::formatCount(999960), "1.0 M");
  EXPECT_EQ(mcv::formatCount(2500000000u), "2.5 G");
}
