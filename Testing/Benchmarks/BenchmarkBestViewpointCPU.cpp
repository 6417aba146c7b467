// CPU benchmark of the best-viewpoint pipeline (Harris + top-N + PCA) against the two
// baselines (viewpoint entropy, area maximising), all measured in the same run on the same
// opacity volumes: synthetic structured volumes 64^3..256^3 (uint8-like, deterministic) and
// the real volumes fetched by scripts/fetch-data.sh (Colin27 ch2 with a linear ramp
// opacity, VolPack brainsmall.den with a linear ramp opacity).
//
//   mcvBenchmarkCPU [--quick] [--runs N] [--entropy-runs N] [--sizes 64,128,...]
//                   [--entropy-samples S] [--large-entropy-samples S] [--large-from N]
//                   [--image-size P] [--threads T] [--no-real] [--no-synthetic]
//
// Times are medians over --runs runs (Harris pipeline, area maximising) and --entropy-runs
// runs (viewpoint entropy). The entropy baseline uses S sphere samples (default 400) at
// PxP pixels (default 128); volumes with at least --large-from voxels per side (default
// 192) may use --large-entropy-samples instead (default: the same S); the table prints the
// samples actually used, and the ratio column is always measured, never extrapolated.
//
// The former CPU path (ReferenceHarrisCPU.h: whole-slice smoothing without FMA, the response
// volume stored, then a priority-queue selection) runs interleaved with the current one, run
// for run, on the same volume: the `former` and `speed-up` columns; `agree` is the largest
// difference of the two response volumes over the largest |response|, `overlap` the share
// of the top-N both select, and `ang.old` the angle between their best views. The `peak`
// column is the current Harris + top-N time against the floor of the method's floating-
// point operations at the CPU's FMA peak (--fma-peak-gflops, else cores x MHz x 32: two
// 256-bit FMA units per core).
#include "BestViewpoint.h"
#include "OpacityFunction.h"
#include "ReferenceHarrisCPU.h"

#include "CommandLine.h"
#include "RunStatistics.h"
#include "TestVolumes.h"

#include <omp.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <iterator>
#include <sstream>
#include <string>
#include <unordered_set>
#include <utility>
#include <vector>

namespace
{
namespace mt = mcv::testing;
using mt::loadAverage;
using mt::median;
using Clock = std::chrono::steady_clock;

struct Config
{
  bool quick = false;
  int runs = 5;
  int entropyRuns = 1;
  std::vector<int> sizes{ 64, 128, 192, 256 };
  int entropySamples = 400;
  int largeEntropySamples = -1; // -1: same as entropySamples
  int largeFrom = 192;
  int imageSize = 128;
  bool real = true;
  bool synthetic = true;
  int threads = 0; // 0: OpenMP's default
  double peakGflops = 0; // 0: from /proc/cpuinfo
  bool former = true;
};

struct Row
{
  std::string name;
  std::string dims;
  double harrisMs = 0, selectMs = 0, pcaMs = 0, totalMs = 0;
  std::size_t points = 0;
  bool harrisValid = false;
  int entropySamples = 0;
  double entropyMs = 0, areaMs = 0;
  double angleEntropy = NAN, angleArea = NAN;
  double formerMs = NAN, formerHarrisMs = NAN, formerSelectMs = NAN; // the former CPU path
  double agreement = NAN, overlap = NAN, angleFormer = NAN;
  double floorMs = NAN; // the method's flops at the FMA peak
  std::string note;
};

std::string fmtVec(const mcv::Vec3& v)
{
  char buf[96];
  std::snprintf(buf, sizeof(buf), "(%+.3f, %+.3f, %+.3f)", v[0], v[1], v[2]);
  return buf;
}

// Floating-point operations per voxel of the Harris response (an FMA counts 2): gradient
// (3 differences, 3 scalings), 6 products, three Gaussian passes of `width` FMAs on 6
// channels, and the response (20 for the 3D form).
double harrisFlopsPerVoxel(int width)
{
  return 6 + 6 + 3 * 6 * 2.0 * width + 20;
}

// Cores x clock x 32 single-precision flops per cycle (two 256-bit FMA units), from
// /proc/cpuinfo's first "cpu MHz"; 0 if unknown.
double fmaPeakGflops()
{
  double mhz = 0;
  if (FILE* f = std::fopen("/proc/cpuinfo", "r"))
  {
    char line[512];
    while (std::fgets(line, sizeof(line), f))
    {
      if (std::strncmp(line, "cpu MHz", 7) == 0)
      {
        const char* colon = std::strchr(line, ':');
        if (colon)
          mhz = std::atof(colon + 1);
        break;
      }
    }
    std::fclose(f);
  }
  return mhz * 1e-3 * omp_get_max_threads() * 32.0;
}

// Share of a's indices that b holds too (1 for two empty lists).
double indexOverlap(const mcv::InterestPoints& a, const mcv::InterestPoints& b)
{
  if (a.size() == 0 && b.size() == 0)
    return 1.0;
  const std::unordered_set<std::int64_t> in(b.indices.begin(), b.indices.end());
  std::size_t shared = 0;
  for (std::int64_t i : a.indices)
    shared += in.count(i);
  return static_cast<double>(shared) / static_cast<double>(std::max(a.size(), b.size()));
}

void usage()
{
  std::printf("usage: mcvBenchmarkCPU [--quick] [--runs N] [--entropy-runs N] [--sizes a,b,..]\n"
              "         [--entropy-samples S] [--large-entropy-samples S] [--large-from N]\n"
              "         [--image-size P] [--threads T] [--no-real] [--no-synthetic]\n"
              "         [--fma-peak-gflops G] [--no-former]\n");
}

bool parseArgs(int argc, char** argv, Config& c)
{
  // The options that take a count, at least 1.
  static const std::pair<const char*, int Config::*> kCounts[] = { { "--runs", &Config::runs },
    { "--entropy-runs", &Config::entropyRuns }, { "--entropy-samples", &Config::entropySamples },
    { "--large-entropy-samples", &Config::largeEntropySamples }, { "--image-size", &Config::imageSize },
    { "--threads", &Config::threads } };
  for (int i = 1; i < argc; ++i)
  {
    const std::string a = argv[i];
    auto next = [&](const char* what) -> const char* {
      if (i + 1 >= argc)
      {
        std::fprintf(stderr, "mcvBenchmarkCPU: %s needs a value\n", what);
        std::exit(2);
      }
      return argv[++i];
    };
    const auto count =
      std::find_if(std::begin(kCounts), std::end(kCounts), [&](const auto& option) { return a == option.first; });
    if (a == "--quick")
    {
      c.quick = true;
      c.runs = 1;
      c.entropyRuns = 1;
      c.sizes = { 64 };
      c.entropySamples = 24;
      c.imageSize = 64;
    }
    else if (count != std::end(kCounts))
      c.*(count->second) = std::max(1, std::atoi(next(count->first)));
    else if (a == "--sizes")
      c.sizes = mt::integerList(next("--sizes"));
    else if (a == "--large-from")
      c.largeFrom = std::atoi(next("--large-from"));
    else if (a == "--no-real")
      c.real = false;
    else if (a == "--no-synthetic")
      c.synthetic = false;
    else if (a == "--fma-peak-gflops")
      c.peakGflops = std::atof(next("--fma-peak-gflops"));
    else if (a == "--no-former")
      c.former = false;
    else if (a == "--help" || a == "-h")
    {
      usage();
      std::exit(0);
    }
    else
    {
      std::fprintf(stderr, "mcvBenchmarkCPU: unknown argument %s\n", a.c_str());
      usage();
      return false;
    }
  }
  return true;
}

// Opacity through the core's own mapping: the channel's finite range, linearly 0..1.
std::vector<float> rampOpacity(const mt::Volume& v)
{
  mcv::ChannelView ch;
  ch.data = v.values.data();
  ch.type = mcv::ScalarType::Float32;
  const auto range = mcv::finiteRange(ch, v.values.size());
  std::vector<float> opacity(v.values.size(), 0.0f);
  mcv::accumulateOpacity(
    ch, v.values.size(), mcv::OpacityFunction::ramp(range.first, range.second), opacity.data());
  return opacity;
}

Row benchmarkVolume(const std::string& name, const mcv::ImageGrid& grid,
  const std::vector<float>& opacity, const Config& cfg)
{
  Row row;
  row.name = name;
  row.dims = std::to_string(grid.dims[0]) + "x" + std::to_string(grid.dims[1]) + "x" +
    std::to_string(grid.dims[2]);
  std::printf("\n== %s  %s  spacing (%.3g, %.3g, %.3g)\n", name.c_str(), row.dims.c_str(),
    grid.spacing[0], grid.spacing[1], grid.spacing[2]);
  std::fflush(stdout);

  // --- Harris + top-N + PCA (the suite's method), CPU.
  mcv::BestViewpointOptions opt;
  opt.device = mcv::Device::CPU;
  opt.method = mcv::ViewMethod::HarrisPCA;
  std::vector<double> h, s, p, t;
  mcv::BestViewpointResult harris;
  // One warm-up run (page faults of the first allocation, thread start-up).
  harris = mcv::computeBestViewpoint(opacity.data(), grid, opt);
  if (!harris.ok())
  {
    std::printf("   Harris: error: %s\n", harris.error.c_str());
    row.note = "harris error";
    return row;
  }
  // The former CPU path on the grid computeBestViewpoint uses (spacing over its geometric
  // mean), timed as it ran: the response volume allocated, computed, then searched.
  mcv::ImageGrid unitFree = grid;
  const double mean = std::cbrt(grid.spacing[0] * grid.spacing[1] * grid.spacing[2]);
  for (int a = 0; a < 3; ++a)
    unitFree.spacing[a] = grid.spacing[a] / mean;
  mcv::InterestPoints formerPoints;
  std::vector<double> fh, fs, ft;
  auto runFormer = [&]() {
    const auto start = Clock::now();
    std::vector<float> response(grid.voxelCount());
    mcv::benchmark::referenceHarrisResponseCPU(opacity.data(), unitFree, opt.harris, response.data());
    const double h = std::chrono::duration<double, std::milli>(Clock::now() - start).count();
    formerPoints = mcv::benchmark::referenceSelectTopResponsesCPU(
      response.data(), response.size(), opt.numberOfInterestPoints);
    const double t = std::chrono::duration<double, std::milli>(Clock::now() - start).count();
    fh.push_back(h);
    fs.push_back(t - h);
    ft.push_back(t);
  };
  if (cfg.former)
  {
    runFormer(); // its warm-up
    fh.clear();
    fs.clear();
    ft.clear();
  }
  for (int r = 0; r < cfg.runs; ++r)
  {
    harris = mcv::computeBestViewpoint(opacity.data(), grid, opt);
    h.push_back(harris.timings.harrisMs);
    s.push_back(harris.timings.selectMs);
    p.push_back(harris.timings.pcaMs);
    t.push_back(harris.timings.totalMs);
    if (cfg.former)
      runFormer();
  }
  row.harrisMs = median(h);
  row.selectMs = median(s);
  row.pcaMs = median(p);
  row.totalMs = median(t);
  row.points = harris.points.size();
  row.harrisValid = harris.view.valid;
  std::printf("   Harris/PCA  (median of %d): harris + top-N %.2f ms, merge %.2f ms, pca %.3f ms, "
              "total %.2f ms; %zu points\n",
    cfg.runs, row.harrisMs, row.selectMs, row.pcaMs, row.totalMs, row.points);
  const double peak = cfg.peakGflops > 0 ? cfg.peakGflops : fmaPeakGflops();
  if (peak > 0)
  {
    const double flops = harrisFlopsPerVoxel(opt.harris.kernelWidth);
    row.floorMs = flops * static_cast<double>(grid.voxelCount()) / (peak * 1e6);
    std::printf("   limit: %.0f flops per voxel at the FMA peak %.1f GFLOP/s = %.2f ms; "
                "harris + top-N at %.1fx that (%.0f%% of the peak)\n",
      flops, peak, row.floorMs, (row.harrisMs + row.selectMs) / row.floorMs,
      100.0 * row.floorMs / (row.harrisMs + row.selectMs));
  }
  if (cfg.former)
  {
    row.formerHarrisMs = median(fh);
    row.formerSelectMs = median(fs);
    row.formerMs = median(ft);
    // Agreement of the response volumes (the current path computed once more, whole).
    std::vector<float> now(grid.voxelCount()), before(grid.voxelCount());
    mcv::computeHarrisResponseCPU(opacity.data(), unitFree, opt.harris, now.data());
    mcv::benchmark::referenceHarrisResponseCPU(opacity.data(), unitFree, opt.harris, before.data());
    double maxAbs = 0, maxDiff = 0;
    for (std::size_t v = 0; v < now.size(); ++v)
    {
      maxAbs = std::max(maxAbs, static_cast<double>(std::fabs(before[v])));
      maxDiff = std::max(maxDiff, static_cast<double>(std::fabs(now[v] - before[v])));
    }
    row.agreement = maxAbs > 0 ? maxDiff / maxAbs : maxDiff;
    row.overlap = indexOverlap(harris.points, formerPoints);
    if (harris.view.valid && formerPoints.size() >= 3)
    {
      const mcv::ViewDirections fv = mcv::computeViewDirections(mcv::worldPositions(formerPoints, grid));
      if (fv.valid)
        row.angleFormer = mcv::axisAngleDegrees(harris.view.best, fv.best);
    }
    std::printf("   former CPU path (interleaved, median of %d): harris %.2f ms + select %.2f ms = "
                "%.2f ms; speed-up %.2fx; responses differ by %.2e of max|R|; top-N overlap "
                "%.4f; best views %.3f deg apart\n",
      cfg.runs, row.formerHarrisMs, row.formerSelectMs, row.formerMs,
      row.formerMs / (row.harrisMs + row.selectMs), row.agreement, row.overlap, row.angleFormer);
  }
  for (const auto& w : harris.warnings)
    std::printf("   warning: %s\n", w.c_str());
  if (harris.view.valid)
    std::printf("     best %s worst %s eigenvalues (%.3f, %.3f, %.3f)\n",
      fmtVec(harris.view.best).c_str(), fmtVec(harris.view.worst).c_str(),
      harris.view.eigenvalues[0], harris.view.eigenvalues[1], harris.view.eigenvalues[2]);
  // --- Area maximising baseline.
  opt.method = mcv::ViewMethod::AreaMaximizing;
  std::vector<double> a;
  mcv::BestViewpointResult area;
  for (int r = 0; r < cfg.runs; ++r)
  {
    area = mcv::computeBestViewpoint(opacity.data(), grid, opt);
    a.push_back(area.timings.totalMs);
  }
  row.areaMs = median(a);
  if (area.ok() && area.view.valid)
  {
    std::printf("   area max    (median of %d): %.2f ms; best %s\n", cfg.runs, row.areaMs,
      fmtVec(area.view.best).c_str());
    if (harris.view.valid)
      row.angleArea = mcv::axisAngleDegrees(harris.view.best, area.view.best);
  }
  else
    std::printf("   area max: no direction (%s)\n", area.ok() ? area.view.message.c_str()
                                                             : area.error.c_str());

  // --- Viewpoint entropy baseline.
  const int maxDim = std::max(grid.dims[0], std::max(grid.dims[1], grid.dims[2]));
  row.entropySamples = (cfg.largeEntropySamples > 0 && maxDim >= cfg.largeFrom)
    ? cfg.largeEntropySamples
    : cfg.entropySamples;
  opt.method = mcv::ViewMethod::ViewpointEntropy;
  opt.entropy.samples = row.entropySamples;
  opt.entropy.imageSize = cfg.imageSize;
  std::vector<double> e;
  mcv::BestViewpointResult entropy;
  for (int r = 0; r < cfg.entropyRuns; ++r)
  {
    const auto start = Clock::now();
    entropy = mcv::computeBestViewpoint(opacity.data(), grid, opt);
    e.push_back(std::chrono::duration<double, std::milli>(Clock::now() - start).count());
  }
  row.entropyMs = median(e);
  if (entropy.ok() && entropy.view.valid)
  {
    std::printf("   entropy     (median of %d, %d samples at %dx%d): %.1f ms "
                "(%.2f ms per view); best %s\n",
      cfg.entropyRuns, row.entropySamples, cfg.imageSize, cfg.imageSize, row.entropyMs,
      row.entropyMs / row.entropySamples, fmtVec(entropy.view.best).c_str());
    if (harris.view.valid)
      row.angleEntropy = mcv::axisAngleDegrees(harris.view.best, entropy.view.best);
  }
  else
    std::printf("   entropy: no direction (%s)\n", entropy.ok() ? entropy.view.message.c_str()
                                                              : entropy.error.c_str());
  if (row.totalMs > 0)
    std::printf("   ratio entropy / Harris total = %.1f\n", row.entropyMs / row.totalMs);
  std::fflush(stdout);
  return row;
}

} // namespace

int main(int argc, char** argv)
{
  Config cfg;
  if (!parseArgs(argc, argv, cfg))
    return 2;
  if (cfg.threads > 0)
    omp_set_num_threads(cfg.threads);

  std::printf("mcvBenchmarkCPU: best viewpoint on the CPU (%d OpenMP threads, %d processors, "
              "load average %.2f)%s\n",
    omp_get_max_threads(), omp_get_num_procs(), loadAverage(),
    cfg.quick ? " [--quick: smoke run, not a measurement]" : "");
  std::printf("Harris/PCA: N = 2048, sigma 1.5, 5 taps, k = 0.004; %d timed run(s) after one "
              "warm-up, median.\n",
    cfg.runs);
  std::printf("Entropy baseline: %d sphere samples at %dx%d", cfg.entropySamples, cfg.imageSize,
    cfg.imageSize);
  if (cfg.largeEntropySamples > 0 && cfg.largeEntropySamples != cfg.entropySamples)
    std::printf(" (%d samples for volumes >= %d per side)", cfg.largeEntropySamples,
      cfg.largeFrom);
  std::printf(", %d run(s), median.\n", cfg.entropyRuns);

  std::vector<Row> rows;
  if (cfg.synthetic)
    for (int n : cfg.sizes)
    {
      if (n < 2)
        continue;
      const auto start = Clock::now();
      const mt::Volume v = mt::structuredVolume(n);
      std::printf("\n(built %s in %.0f ms)", v.name.c_str(),
        std::chrono::duration<double, std::milli>(Clock::now() - start).count());
      rows.push_back(benchmarkVolume(v.name, v.grid, v.values, cfg));
    }

  if (cfg.real)
  {
    struct Real
    {
      const char* file;
      const char* label;
    };
    const Real reals[] = { { "ch2.nii.gz", "ch2 (Colin27)" }, { "brainsmall.den", "brainsmall" } };
    for (const Real& r : reals)
    {
      if (!mt::haveDataFile(r.file))
      {
        std::printf("\n== %s: %s not found (run scripts/fetch-data.sh): skipped\n", r.label,
          mt::dataFile(r.file).c_str());
        continue;
      }
      try
      {
        const mt::Volume v = std::string(r.file).find(".den") != std::string::npos
          ? mt::loadVolPackDen(mt::dataFile(r.file))
          : mt::loadNifti(mt::dataFile(r.file));
        const std::vector<float> opacity = rampOpacity(v);
        rows.push_back(benchmarkVolume(r.label, v.grid, opacity, cfg));
      }
      catch (const std::exception& e)
      {
        std::printf("\n== %s: cannot load: %s\n", r.label, e.what());
      }
    }
  }

  // Final table.
  std::printf("\n%-16s %-12s %9s %7s %8s %9s | %9s %8s %8s %8s %7s | %6s | %7s %11s %9s | "
              "%8s | %7s %7s\n",
    "volume", "dims", "harris", "merge", "pca", "total", "former", "speed-up", "agree", "overlap",
    "ang.old", "peak", "samples", "entropy", "ent/tot", "areamax", "ang.ent", "ang.area");
  std::printf("%-16s %-12s %9s %7s %8s %9s | %9s %8s %8s %8s %7s | %6s | %7s %11s %9s | %8s | "
              "%7s %7s\n",
    "", "", "+top-N ms", "ms", "ms", "ms", "ms", "x", "", "", "deg", "x", "", "ms", "ratio", "ms",
    "deg", "deg");
  std::printf("%s\n", std::string(184, '-').c_str());
  for (const Row& r : rows)
  {
    const double now = r.harrisMs + r.selectMs;
    std::printf("%-16s %-12s %9.2f %7.2f %8.3f %9.2f | %9.2f %8.2f %8.1e %8.4f %7.3f | %6.2f | "
                "%7d %11.1f %9.1f | %8.2f | %7.1f %7.1f%s\n",
      r.name.c_str(), r.dims.c_str(), r.harrisMs, r.selectMs, r.pcaMs, r.totalMs, r.formerMs,
      r.formerMs / now, r.agreement, r.overlap, r.angleFormer, now / r.floorMs, r.entropySamples,
      r.entropyMs, r.totalMs > 0 ? r.entropyMs / r.totalMs : NAN, r.areaMs, r.angleEntropy,
      r.angleArea, r.note.empty() ? "" : ("  " + r.note).c_str());
  }
  std::printf("load average at the end: %.2f (times are only comparable on a quiet machine)\n",
    loadAverage());
  std::printf("harris+top-N/merge/pca/total: Harris pipeline stages (Device CPU; the top-N is "
              "selected while the response is computed, merge is what remains); former: the former "
              "CPU path's harris + select, interleaved with the current one; speed-up = former / "
              "(harris + merge); agree: max |R_now - R_former| / max |R_former|; overlap: share of "
              "the top-N both select; ang.old: angle between their best views; peak: (harris + "
              "merge) / the method's flops at the FMA peak; entropy: viewpoint entropy baseline "
              "with `samples` views; ent/tot = entropy / Harris total (same run); ang.*: angle "
              "between the Harris best axis and the baseline's best axis.\n");
  return 0;
}
