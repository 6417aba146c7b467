#include "MemoryBudget.h"

#include "HalfCoordinates.h"

#include <sys/resource.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <limits>
#include <sstream>

namespace mcv
{

namespace
{

constexpr std::size_t kMax = std::numeric_limits<std::size_t>::max();

std::size_t mulSat(std::size_t a, std::size_t b)
{
  return (a != 0 && b > kMax / a) ? kMax : a * b;
}

std::size_t addSat(std::size_t a, std::size_t b)
{
  return b > kMax - a ? kMax : a + b;
}

std::size_t columns(int n)
{
  return n > 0 ? static_cast<std::size_t>(n) : 0;
}

// MCV_MEMORY_LIMIT_MB as bytes; false when unset or not a number >= 0.
bool limitFromEnvironment(std::size_t& bytes)
{
  const char* text = std::getenv("MCV_MEMORY_LIMIT_MB");
  if (!text || !*text)
  {
    return false;
  }
  char* end = nullptr;
  const double mb = std::strtod(text, &end);
  if (*end != '\0' || !std::isfinite(mb) || mb < 0)
  {
    return false;
  }
  const double b = mb * 1024.0 * 1024.0;
  bytes = b >= static_cast<double>(kMax) ? kMax : static_cast<std::size_t>(b);
  return true;
}

// MemAvailable (the kernel's estimate of what can be allocated without swapping).
bool memAvailable(std::size_t& bytes)
{
  std::ifstream in("/proc/meminfo");
  std::string key, unit;
  unsigned long long kib = 0;
  while (in >> key >> kib)
  {
    std::getline(in, unit);
    if (key == "MemAvailable:")
    {
      bytes = mulSat(static_cast<std::size_t>(kib), 1024);
      return true;
    }
  }
  return false;
}

bool readNumber(const std::string& path, unsigned long long& value)
{
  std::ifstream in(path);
  return static_cast<bool>(in >> value); // "max" (no limit) reads as no number
}

// Sum of the file-cache lines of a memory.stat (reclaimable: not counted as used).
unsigned long long fileCache(const std::string& path, const char* a, const char* b)
{
  std::ifstream in(path);
  std::string key;
  unsigned long long value = 0, sum = 0;
  while (in >> key >> value)
  {
    if (key == a || key == b)
    {
      sum += value;
    }
  }
  return sum;
}

// What the cgroup's memory limit leaves (v2 memory.max, else v1 limit_in_bytes); false
// without a limit.
bool cgroupAvailable(std::size_t& bytes)
{
  std::string v2Path, v1Path;
  std::ifstream self("/proc/self/cgroup");
  std::string line;
  while (std::getline(self, line))
  {
    if (line.rfind("0::", 0) == 0)
    {
      v2Path = line.substr(3);
    }
    else if (line.find(":memory:") != std::string::npos)
    {
      v1Path = line.substr(line.find(":memory:") + 8);
    }
  }
  struct Layout
  {
    std::string dir, limit, usage, stat, fileA, fileB;
  };
  const Layout layouts[] = {
    { "/sys/fs/cgroup" + v2Path, "memory.max", "memory.current", "memory.stat", "file", "" },
    { "/sys/fs/cgroup", "memory.max", "memory.current", "memory.stat", "file", "" },
    { "/sys/fs/cgroup/memory" + v1Path, "memory.limit_in_bytes", "memory.usage_in_bytes",
      "memory.stat", "total_inactive_file", "total_active_file" },
    { "/sys/fs/cgroup/memory", "memory.limit_in_bytes", "memory.usage_in_bytes", "memory.stat",
      "total_inactive_file", "total_active_file" },
  };
  for (const Layout& l : layouts)
  {
    unsigned long long limit = 0, usage = 0;
    if (!readNumber(l.dir + "/" + l.limit, limit))
    {
      continue;
    }
    if (limit >= (1ull << 60) || !readNumber(l.dir + "/" + l.usage, usage))
    {
      return false; // no limit (v1 writes a huge number)
    }
    const unsigned long long cache =
      fileCache(l.dir + "/" + l.stat, l.fileA.c_str(), l.fileB.c_str());
    const unsigned long long used = usage > cache ? usage - cache : 0;
    bytes = static_cast<std::size_t>(limit > used ? limit - used : 0);
    return true;
  }
  return false;
}

// What the address-space limit (ulimit -v, RLIMIT_AS; usual on clusters) leaves above the
// process's current virtual size; false without a limit. Allocations past it fail even
// when the machine has free memory.
bool addressSpaceAvailable(std::size_t& bytes)
{
  rlimit limit{};
  if (getrlimit(RLIMIT_AS, &limit) != 0 || limit.rlim_cur == RLIM_INFINITY)
  {
    return false;
  }
  std::ifstream status("/proc/self/status");
  std::string key;
  unsigned long long kib = 0;
  std::size_t used = 0;
  while (status >> key)
  {
    if (key == "VmSize:" && status >> kib)
    {
      used = mulSat(static_cast<std::size_t>(kib), 1024);
      break;
    }
    std::getline(status, key);
  }
  const std::size_t cap = static_cast<std::size_t>(limit.rlim_cur);
  bytes = cap > used ? cap - used : 0;
  return true;
}

const char* const kGeneralAdvice = "crop or subsample the volume, or run on more MPI ranks "
                                   "(mpiexec -np R pvbatch --mpi) so that each holds a smaller piece.";

} // namespace

std::size_t availableMemoryBytes()
{
  std::size_t bytes = kMax;
  if (limitFromEnvironment(bytes))
  {
    return bytes;
  }
  if (!memAvailable(bytes))
  {
    const long pages = sysconf(_SC_AVPHYS_PAGES), page = sysconf(_SC_PAGESIZE);
    bytes = pages > 0 && page > 0
      ? mulSat(static_cast<std::size_t>(pages), static_cast<std::size_t>(page))
      : kMax;
  }
  std::size_t cgroup = kMax;
  if (cgroupAvailable(cgroup) && cgroup < bytes)
  {
    bytes = cgroup;
  }
  std::size_t addressSpace = kMax;
  if (addressSpaceAvailable(addressSpace) && addressSpace < bytes)
  {
    bytes = addressSpace;
  }
  return bytes;
}

std::string formatBytes(std::size_t bytes, bool roundUp)
{
  const char* units[] = { "B", "KiB", "MiB", "GiB", "TiB", "PiB", "EiB" };
  if (bytes < 1024)
  {
    return std::to_string(bytes) + " B";
  }
  double value = static_cast<double>(bytes);
  int u = 0;
  while (value >= 1024.0 && u < 6)
  {
    value /= 1024.0;
    ++u;
  }
  // One decimal; a need rounds up and an availability down, so "needs 1.3 but only 1.2".
  const double tenths = roundUp ? std::ceil(value * 10.0 - 1e-9) : std::floor(value * 10.0 + 1e-9);
  char text[32];
  std::snprintf(text, sizeof text, "%.1f %s", tenths / 10.0, units[u]);
  return text;
}

std::string formatCount(std::size_t count)
{
  const char* units[] = { "", " k", " M", " G", " T" };
  if (count < 1000)
  {
    return std::to_string(count);
  }
  double value = static_cast<double>(count);
  int u = 0;
  while (value >= 999.95 && u < 4) // 999,960 prints as "1.0 M", not "1000.0 k"
  {
    value /= 1000.0;
    ++u;
  }
  char text[32];
  std::snprintf(text, sizeof text, "%.1f%s", value, units[u]);
  return text;
}

std::size_t featureBytes(std::size_t voxels, int features)
{
  const std::size_t output = mulSat(mulSat(voxels, columns(features)), sizeof(float));
  const std::size_t workingCopy = mulSat(voxels, sizeof(float));
  const std::size_t mask = voxels;
  return addSat(addSat(output, workingCopy), mask);
}

std::size_t coordinateBytes(std::size_t rows, int dimensions, bool halfCoordinates)
{
  if (!halfCoordinates)
  {
    return mulSat(mulSat(rows, columns(dimensions)), sizeof(float));
  }
  const std::size_t halves = mulSat(mulSat(rows, columns(dimensions)), sizeof(std::uint16_t));
  const std::size_t scratch = mulSat(mulSat(std::min(rows, kHalfPlacementRows), columns(dimensions)), sizeof(float));
  return addSat(halves, scratch);
}

std::size_t reductionBytes(std::size_t rows, int features, int dimensions, bool inputIsFloat, bool halfCoordinates)
{
  const std::size_t coordinates = coordinateBytes(rows, dimensions, halfCoordinates);
  const std::size_t converted =
    inputIsFloat ? 0 : mulSat(mulSat(rows, columns(features)), sizeof(float));
  return addSat(coordinates, converted);
}

std::size_t fusedReductionBytes(std::size_t rows, int dimensions, std::size_t slabBytes, bool halfCoordinates)
{
  // Coordinates, the Foreground mask and the sample's stratum per row (one byte each).
  const std::size_t coordinates = coordinateBytes(rows, dimensions, halfCoordinates);
  return addSat(addSat(coordinates, mulSat(rows, 2)), slabBytes);
}

std::size_t viewpointBytes(std::size_t voxels)
{
  return mulSat(voxels, 2 * sizeof(float));
}

std::string checkMemory(std::size_t bytesNeeded, const char* what)
{
  return checkMemory(bytesNeeded, what, std::string(), std::string());
}

std::string checkMemory(std::size_t bytesNeeded, const char* what, const std::string& forWhat,
  const std::string& advice)
{
  const std::size_t available = availableMemoryBytes();
  if (bytesNeeded <= available)
  {
    return std::string();
  }
  std::ostringstream os;
  os << (what && *what ? what : "This step") << " needs " << formatBytes(bytesNeeded, true);
  if (!forWhat.empty())
  {
    os << " for " << forWhat;
  }
  os << " but only " << formatBytes(available) << " is available on this process; " << advice
     << kGeneralAdvice;
  return os.str();
}

std::string checkFeatureMemory(std::size_t voxels, int features)
{
  return checkMemory(featureBytes(voxels, features), "MultichannelFeatures",
    formatCount(voxels) + " voxels x " + std::to_string(features) + " features",
    "use fewer features, ");
}

std::string checkReductionMemory(std::size_t rows, int features, int dimensions, bool inputIsFloat,
  bool halfCoordinates)
{
  std::string forWhat = formatCount(rows) + " points x " + std::to_string(dimensions) +
    (halfCoordinates ? " float16 coordinates" : " coordinates");
  if (!inputIsFloat)
  {
    forWhat += " (and a float copy of the " + std::to_string(features) + " input features)";
  }
  return checkMemory(reductionBytes(rows, features, dimensions, inputIsFloat, halfCoordinates),
    "DimensionReduction", forWhat, "");
}

std::string checkFusedReductionMemory(std::size_t rows, int features, int dimensions, std::size_t slabBytes,
  bool halfCoordinates)
{
  return checkMemory(fusedReductionBytes(rows, dimensions, slabBytes, halfCoordinates), "DimensionReduction",
    formatCount(rows) + " points x " + std::to_string(dimensions) +
      (halfCoordinates ? " float16 coordinates (the " : " coordinates (the ") +
      std::to_string(features) + " features computed a slab of " + formatBytes(slabBytes, true) + " at a time)",
    "");
}

std::string checkViewpointMemory(std::size_t voxels)
{
  return checkMemory(viewpointBytes(voxels), "BestViewpoint",
    formatCount(voxels) + " voxels (opacity and Harris response, 8 bytes each)", "");
}

} // namespace mcv
