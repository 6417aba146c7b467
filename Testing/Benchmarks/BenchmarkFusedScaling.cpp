// mcvBenchmarkFusedScaling: does the fused reduction's time grow
// linearly with the voxel count, and what does its memory peak at? The main job's chain on
// the CPU (all cores): 24D features computed a slab at a time (FeatureBricks), Isomap
// (K = 10, L = 500) fitted on a reference sample of 10000, every voxel placed by its 3
// nearest references.
//
// The volume: the real brain (Colin27 T1 + AAL + Brodmann, 181 x 217 x 181, float32)
// resampled trilinearly by F along each axis, as ParaView's ResampleToImage does in
// benchmark_fused.py (F = 0.53, 1, 2, 3: 1.06, 7.1, 56.9, 192 M voxels), or with --tile the
// brain tiled periodically to the same dimensions (Testing/Data/ScaledBrain.h).
//
// Each size runs in its own child process (this program run again with --one F), so the
// child's peak resident memory (ru_maxrss from wait4, and its own VmHWM) belongs to that
// size alone. Per size: the stages' seconds, the whole chain's, the peak memory, the
// nanoseconds per voxel and their ratio to the baseline size's (F = 1, 7.1 M voxels) in the
// same run: ~1 when the time is linear in the voxel count.
//
//   mcvBenchmarkFusedScaling [--factors 0.53,1,2,3] [--tile] [--reference 10000]
#include "BrainFeatures.h"
#include "CommandLine.h"
#include "DimensionReduction.h"
#include "FeatureBricks.h"
#include "ScaledBrain.h"

#include <omp.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <string>
#include <vector>

namespace mt = mcv::testing;
using Clock = std::chrono::steady_clock;

namespace
{
double secondsSince(Clock::time_point t)
{
  return std::chrono::duration<double>(Clock::now() - t).count();
}

// A "VmRSS:" / "VmHWM:" line of /proc/self/status, in KiB.
double statusKiB(const char* key)
{
  std::ifstream f("/proc/self/status");
  std::string line;
  while (std::getline(f, line))
    if (line.rfind(key, 0) == 0)
      return std::atof(line.c_str() + std::strlen(key));
  return 0;
}

// What one child reports (one "RESULT" line).
struct SizeRun
{
  double factor = 0;
  int dims[3] = { 0, 0, 0 };
  double voxels = 0, makeS = 0, inputKiB = 0, statisticsS = 0, columnsS = 0, sampleS = 0, fitS = 0, placeS = 0, wholeS = 0,
         hwmKiB = 0, maxrssKiB = 0;
  bool ok = false;
};

// The child: one size, stages timed, one RESULT line on stdout.
int runOne(double factor, bool tile, std::size_t reference)
{
  const auto t0 = Clock::now();
  mt::ScaledChannels volume;
  {
    const std::vector<mt::Volume> brain = mt::loadBrain();
    volume = tile ? mt::tileBrain(brain, mt::scaledDims(brain[0].grid, factor)) : mt::upsampleBrain(brain, factor);
  }
  SizeRun r;
  r.makeS = secondsSince(t0);
  r.inputKiB = statusKiB("VmRSS:");
  const mcv::ImageGrid& g = volume.grid;
  r.voxels = static_cast<double>(g.voxelCount());
  std::printf("%d x %d x %d = %.2f M voxels (brain %s in %.1f s), %d threads\n", g.dims[0], g.dims[1], g.dims[2],
    r.voxels / 1e6, tile ? "tiled" : "resampled", r.makeS, omp_get_max_threads());
  std::fflush(stdout);

  mcv::FeatureOptions fo;
  fo.preset = mcv::FeaturePreset::TwentyFourD;
  fo.device = mcv::Device::CPU;
  mcv::FeatureBricks bricks(volume.views(), g, fo);
  const auto start = Clock::now();
  mcv::FeatureResult prepared;
  if (!bricks.prepare(prepared))
  {
    std::printf("statistics pass failed: %s\n", prepared.error.c_str());
    return 1;
  }
  r.statisticsS = secondsSince(start);
  mcv::ReductionOptions ro = mcv::testing::mainJobReduction(reference, mcv::Device::CPU);
  // The column check ends where the reference sample's drawing starts (its first report).
  Clock::time_point sampleStart{};
  ro.progress = [&](const char* stage, double) {
    if (sampleStart == Clock::time_point{} && std::strcmp(stage, "Drawing the reference sample") == 0)
      sampleStart = Clock::now();
  };
  const auto reduceStart = Clock::now();
  const mcv::ReductionResult result = mcv::reduceDimension(bricks, ro);
  const double reduceS = secondsSince(reduceStart);
  r.wholeS = secondsSince(start);
  if (!result.ok())
  {
    std::printf("reduction failed: %s\n", result.error.c_str());
    return 1;
  }
  for (const std::string& w : result.warnings)
    std::printf("warning: %s\n", w.c_str());
  r.fitS = result.fitMs / 1e3;
  r.placeS = result.placeMs / 1e3;
  // What reduceDimension does besides fit and placement: the column check (a pass over the
  // slabs) and the reference sample (a pass for the strata, the gather of the sample's rows).
  r.columnsS = std::chrono::duration<double>(sampleStart - reduceStart).count();
  r.sampleS = reduceS - r.fitS - r.placeS - r.columnsS;
  r.hwmKiB = statusKiB("VmHWM:");
  std::printf("%zu slabs of %d slices; %zu coordinates\n", bricks.blockCount(), bricks.slabSlices(),
    result.coordinates.size());
  std::printf("RESULT %d %d %d %.0f %.4f %.0f %.4f %.4f %.4f %.4f %.4f %.4f %.0f\n", g.dims[0], g.dims[1], g.dims[2],
    r.voxels, r.makeS, r.inputKiB, r.statisticsS, r.columnsS, r.sampleS, r.fitS, r.placeS, r.wholeS, r.hwmKiB);
  return 0;
}

// The parent: this program run again for one size, its output echoed, its RESULT parsed, its
// peak resident memory taken from wait4.
SizeRun runChild(const char* self, double factor, bool tile, const char* reference)
{
  SizeRun r;
  r.factor = factor;
  int fds[2];
  if (pipe(fds) != 0)
    return r;
  const std::string f = std::to_string(factor);
  std::fflush(stdout);
  const pid_t pid = fork();
  if (pid == 0)
  {
    dup2(fds[1], STDOUT_FILENO);
    close(fds[0]);
    close(fds[1]);
    if (tile)
      execl(self, self, "--one", f.c_str(), "--reference", reference, "--tile", static_cast<char*>(nullptr));
    else
      execl(self, self, "--one", f.c_str(), "--reference", reference, static_cast<char*>(nullptr));
    std::perror("exec");
    _exit(127);
  }
  close(fds[1]);
  FILE* in = fdopen(fds[0], "r");
  char line[4096];
  while (in && std::fgets(line, sizeof line, in))
  {
    std::printf("  %s", line);
    std::fflush(stdout);
    if (std::strncmp(line, "RESULT ", 7) == 0)
      r.ok = std::sscanf(line + 7, "%d %d %d %lf %lf %lf %lf %lf %lf %lf %lf %lf %lf", &r.dims[0], &r.dims[1],
               &r.dims[2], &r.voxels, &r.makeS, &r.inputKiB, &r.statisticsS, &r.columnsS, &r.sampleS, &r.fitS,
               &r.placeS, &r.wholeS, &r.hwmKiB) == 13;
  }
  if (in)
    std::fclose(in);
  int status = 0;
  struct rusage usage{};
  if (wait4(pid, &status, 0, &usage) != pid || !WIFEXITED(status) || WEXITSTATUS(status) != 0)
    r.ok = false;
  r.maxrssKiB = static_cast<double>(usage.ru_maxrss); // KiB on Linux
  return r;
}

std::string cpuModel()
{
  std::ifstream f("/proc/cpuinfo");
  std::string line;
  while (std::getline(f, line))
    if (line.rfind("model name", 0) == 0)
      return line.substr(line.find(':') + 2);
  return "unknown CPU";
}
} // namespace

int main(int argc, char** argv)
{
  const bool tile = mcv::testing::hasFlag(argc, argv, "--tile");
  const char* reference = mcv::testing::optionText(argc, argv, "--reference", "10000");
  if (mcv::testing::hasFlag(argc, argv, "--one"))
    return runOne(std::atof(mcv::testing::optionText(argc, argv, "--one", "1")), tile, std::strtoull(reference, nullptr, 10));

  if (!mt::haveBrain())
  {
    std::printf("brain volumes not in %s (scripts/fetch-data.sh)\n", mt::dataDir().c_str());
    return 1;
  }
  std::vector<double> factors;
  const std::string list = mcv::testing::optionText(argc, argv, "--factors", "0.53,1,2,3");
  for (std::size_t p = 0; p < list.size();)
  {
    const std::size_t q = std::min(list.find(',', p), list.size());
    factors.push_back(std::atof(list.substr(p, q - p).c_str()));
    p = q + 1;
  }
  std::printf("fused reduction (24D, Isomap K = 10, L = 500, reference sample %s, CPU) on the brain %s by F; %s, "
              "%d threads; one child process per size\n",
    reference, tile ? "tiled" : "resampled trilinearly", cpuModel().c_str(), omp_get_max_threads());
  std::vector<SizeRun> runs;
  bool allOk = true;
  for (double f : factors)
  {
    std::printf("\n== F = %g\n", f);
    runs.push_back(runChild("/proc/self/exe", f, tile, reference));
    if (!runs.back().ok)
    {
      std::printf("  F = %g FAILED\n", f);
      allOk = false;
    }
  }

  // The baseline of the ratios: the F = 1 run (the brain itself, 7.1 M voxels).
  const SizeRun* base = nullptr;
  for (const SizeRun& r : runs)
    if (r.ok && std::abs(r.factor - 1.0) < 1e-9)
      base = &r;
  const auto perVoxel = [](const SizeRun& r, double s) { return s * 1e9 / r.voxels; };
  std::printf("\n| F | dims | M voxels | volume made s | statistics s | column check s | sample s | fit s | placement s | "
              "whole s | peak GiB (ru_maxrss) | VmHWM GiB | input GiB | ns/voxel | / F=1 | ns/voxel less fit | / F=1 "
              "| placement ns/voxel | / F=1 |\n");
  std::printf("| --- | --- | --- | --- | --- | --- | --- | --- | --- | --- | --- | --- | --- | --- | --- | --- | --- | --- | --- |\n");
  const double gib = 1024.0 * 1024.0;
  for (const SizeRun& r : runs)
  {
    if (!r.ok)
    {
      std::printf("| %g | failed |\n", r.factor);
      continue;
    }
    const double whole = perVoxel(r, r.wholeS), lessFit = perVoxel(r, r.wholeS - r.fitS), place = perVoxel(r, r.placeS);
    char ratios[3][32] = { "-", "-", "-" };
    if (base)
    {
      std::snprintf(ratios[0], 32, "%.2f", whole / perVoxel(*base, base->wholeS));
      std::snprintf(ratios[1], 32, "%.2f", lessFit / perVoxel(*base, base->wholeS - base->fitS));
      std::snprintf(ratios[2], 32, "%.2f", place / perVoxel(*base, base->placeS));
    }
    std::printf("| %g | %d x %d x %d | %.2f | %.1f | %.2f | %.2f | %.2f | %.2f | %.2f | %.2f | %.2f | %.2f | %.2f | %.0f "
                "| %s | %.0f | %s | %.0f | %s |\n",
      r.factor, r.dims[0], r.dims[1], r.dims[2], r.voxels / 1e6, r.makeS, r.statisticsS, r.columnsS, r.sampleS, r.fitS,
      r.placeS, r.wholeS, r.maxrssKiB / gib, r.hwmKiB / gib, r.inputKiB / gib, whole, ratios[0], lessFit, ratios[1],
      place, ratios[2]);
  }
  return allOk ? 0 : 1;
}
