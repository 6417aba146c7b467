// mcvBenchmarkUMAPGPU: UMAP's CUDA layout (reduction/cuda/UMAPLayoutCuda.h) against the CPU layout in
// the same run, on reference samples of the real brain's 24D features, and the whole 7.1 M-voxel brain with UMAP beside Isomap.
//  1. For each N (--sizes, default 10000,100000): the reference sample of N distinct
//     vectors that reduceDimension would draw; fitUMAP (kNN graph, fuzzy set, spectral
//     start, layout, principal axes) on the CPU and with the layout on the GPU, timed whole
//     and the layout alone (from fitUMAP's own progress reports: "UMAP: layout" to
//     "UMAP: done"); trustworthiness (k = 10) of both on the same 5000 points of the sample.
//     Each fit is run --runs times (default 3; fastest reported, all listed). --rounds R1,R2,..
//     adds GPU fits with those rounds per epoch (UMAPLayoutCuda.h), the quality/speed sweep
//     behind its default.
//  2. The whole brain (--skip-brain to leave it out): features once, then reduceDimension with
//     Isomap and with UMAP (reference 10000, Device GPU: UMAP's layout and the placement of
//     every voxel on the GPU). Target: UMAP's whole chain within Isomap's plus the
//     difference of their fits (UMAP's fit is the only step that differs). The features are
//     computed once and counted in both chains; each reduction is the fastest of --runs.
// Ratios are printed against the CPU (1) and against the target (2), all measured in this run.
#include "BrainFeatures.h"
#include "DimensionReduction.h"
#include "LayoutComparison.h"
#include "ReferenceSample.h"
#include "Trustworthiness.h"
#include "UMAPEmbedding.h"

#include <Eigen/Dense>
#include <omp.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <map>
#include <numeric>
#include <random>
#include <sstream>
#include <string>
#include <vector>

namespace mt = mcv::testing;
using Clock = std::chrono::steady_clock;

namespace
{
double msSince(Clock::time_point t)
{
  return std::chrono::duration<double, std::milli>(Clock::now() - t).count();
}

struct TimedFit
{
  mcv::Embedding e;
  double totalMs = 0, layoutMs = 0;
};

TimedFit timeFit(const mcv::RowMatrixF& X, mcv::Device device, int rounds = 0)
{
  TimedFit f;
  mcv::UMAPOptions o;
  o.device = device;
  o.gpuLayoutRounds = rounds;
  Clock::time_point layoutStart{}, done{};
  o.progress = [&](const char* stage, double) {
    const std::string s = stage;
    if (s == "UMAP: layout" && layoutStart == Clock::time_point{})
      layoutStart = Clock::now();
    else if (s == "UMAP: done")
      done = Clock::now();
  };
  const auto t = Clock::now();
  f.e = mcv::fitUMAP(X, o);
  f.totalMs = msSince(t);
  f.layoutMs = std::chrono::duration<double, std::milli>(done - layoutStart).count();
  return f;
}

// The fastest of `runs` fits (the layouts are the same for a seed: deterministic on both
// devices); `all` lists every run's fit and layout times.
TimedFit bestOf(int runs, const mcv::RowMatrixF& X, mcv::Device device, std::string& all, int rounds = 0)
{
  TimedFit best;
  char buf[64];
  for (int r = 0; r < runs; ++r)
  {
    TimedFit f = timeFit(X, device, rounds);
    std::snprintf(buf, sizeof buf, "%s%.0f/%.0f", r ? ", " : "", f.totalMs, f.layoutMs);
    all += buf;
    if (r == 0 || f.totalMs < best.totalMs)
      best = std::move(f);
  }
  return best;
}

// Trustworthiness of Y on the given rows (X and Y restricted to them).
double trustworthinessOn(const mcv::RowMatrixF& X, const mcv::RowMatrixF& Y, const std::vector<int>& rows)
{
  mcv::RowMatrixF x(static_cast<Eigen::Index>(rows.size()), X.cols()), y(static_cast<Eigen::Index>(rows.size()), Y.cols());
  for (std::size_t i = 0; i < rows.size(); ++i)
  {
    x.row(i) = X.row(rows[i]);
    y.row(i) = Y.row(rows[i]);
  }
  return mcv::trustworthiness(x.data(), static_cast<int>(x.cols()), y.data(), static_cast<int>(y.cols()), rows.size(), 10);
}

void printWarnings(const std::vector<std::string>& warnings)
{
  for (const auto& w : warnings)
    std::printf("    warning: %s\n", w.c_str());
}
} // namespace

int main(int argc, char** argv)
{
  std::setvbuf(stdout, nullptr, _IOLBF, 0);
  std::vector<std::size_t> sizes = { 10000, 100000 };
  std::vector<int> rounds;
  int runs = 3;
  bool brain = true;
  for (int i = 1; i < argc; ++i)
  {
    const std::string k = argv[i];
    if (k == "--sizes" && i + 1 < argc)
    {
      sizes.clear();
      std::stringstream in(argv[++i]);
      for (std::string s; std::getline(in, s, ',');)
        sizes.push_back(std::stoull(s));
    }
    else if (k == "--rounds" && i + 1 < argc)
    {
      std::stringstream in(argv[++i]);
      for (std::string s; std::getline(in, s, ',');)
        rounds.push_back(std::stoi(s));
    }
    else if (k == "--runs" && i + 1 < argc)
      runs = std::max(1, std::stoi(argv[++i]));
    else if (k == "--skip-brain")
      brain = false;
    else
    {
      std::fprintf(stderr, "usage: mcvBenchmarkUMAPGPU [--sizes 10000,100000] [--runs 3] [--rounds 1,4,8] [--skip-brain]\n");
      return 2;
    }
  }
  std::string why;
  if (!mcv::gpuUsable(&why))
  {
    std::printf("no usable GPU (%s): nothing to compare\n", why.c_str());
    return 1;
  }
  if (!mt::haveBrain())
  {
    std::printf("Colin27 volumes missing (scripts/fetch-data.sh): nothing to measure\n");
    return 1;
  }
  std::printf("== UMAP on the GPU vs the CPU (%d OpenMP threads), real brain, 24D features\n", omp_get_max_threads());
  const auto ch = mt::loadBrain();
  auto t = Clock::now();
  const mt::BrainFeatureMatrix f = mt::brainFeatures(ch, mcv::FeaturePreset::TwentyFourD, mcv::Device::GPU);
  const double featuresMs = msSince(t);
  if (!f.result.ok())
  {
    std::printf("features failed: %s\n", f.result.error.c_str());
    return 1;
  }
  std::printf("features: %zu voxels x %d in %.0f ms (on %s)\n", f.rows, f.cols, featuresMs,
    mcv::deviceName(f.result.deviceUsed));

  int failures = 0;
  for (const std::size_t N : sizes)
  {
    mcv::ReferenceSampleOptions so;
    so.size = N;
    const auto rows = mcv::drawReferenceSample(f.values.data(), f.rows, f.cols, {}, {}, so);
    mcv::RowMatrixF X(static_cast<Eigen::Index>(rows.size()), f.cols);
    for (std::size_t r = 0; r < rows.size(); ++r)
      std::copy(f.values.begin() + rows[r] * f.cols, f.values.begin() + (rows[r] + 1) * f.cols, X.row(r).data());
    std::vector<int> tRows(rows.size());
    std::iota(tRows.begin(), tRows.end(), 0);
    std::shuffle(tRows.begin(), tRows.end(), std::mt19937(1));
    tRows.resize(std::min<std::size_t>(5000, tRows.size()));

    std::string cpuRuns, gpuRuns;
    const TimedFit cpu = bestOf(runs, X, mcv::Device::CPU, cpuRuns);
    const TimedFit gpu = bestOf(runs, X, mcv::Device::GPU, gpuRuns);
    if (!cpu.e.error.empty() || !gpu.e.error.empty())
    {
      std::printf("N = %zu: fit failed: %s %s\n", rows.size(), cpu.e.error.c_str(), gpu.e.error.c_str());
      ++failures;
      continue;
    }
    const double tCpu = trustworthinessOn(X, cpu.e.coordinates, tRows);
    const double tGpu = trustworthinessOn(X, gpu.e.coordinates, tRows);
    std::printf("N = %6zu CPU: fit %8.0f ms (layout %8.0f ms) T %.4f   [runs fit/layout ms: %s]\n", rows.size(),
      cpu.totalMs, cpu.layoutMs, tCpu, cpuRuns.c_str());
    std::printf("N = %6zu GPU: fit %8.0f ms (layout %8.0f ms) T %.4f   [runs fit/layout ms: %s]\n", rows.size(),
      gpu.totalMs, gpu.layoutMs, tGpu, gpuRuns.c_str());
    std::printf("N = %6zu GPU vs CPU: fit %.1fx faster, layout %.1fx faster, dT %+.4f (T on %zu points)\n",
      rows.size(), cpu.totalMs / gpu.totalMs, cpu.layoutMs / gpu.layoutMs, tGpu - tCpu, tRows.size());
    printWarnings(gpu.e.warnings);
    for (const int R : rounds)
    {
      std::string all;
      const TimedFit g = bestOf(runs, X, mcv::Device::GPU, all, R);
      std::printf("N = %6zu GPU, %2d rounds/epoch: layout %6.0f ms, T %.4f (dT vs CPU %+.4f), Procrustes to the CPU "
                  "layout %.4f\n",
        rows.size(), R, g.layoutMs, trustworthinessOn(X, g.e.coordinates, tRows),
        trustworthinessOn(X, g.e.coordinates, tRows) - tCpu, mcv::testing::procrustesDisparity(cpu.e.coordinates, g.e.coordinates));
    }
  }

  if (brain)
  {
    std::printf("== whole brain (%zu voxels, 24D, reference 10000, Device GPU): Isomap vs UMAP\n", f.rows);
    std::map<std::string, mcv::ReductionResult> r;
    for (const auto method : { mcv::ReductionMethod::Isomap, mcv::ReductionMethod::UMAP })
    {
      mcv::ReductionOptions o;
      o.method = method;
      o.numberOfNeighbors = method == mcv::ReductionMethod::UMAP ? 15 : 50;
      o.outputDimension = 3;
      o.device = mcv::Device::GPU;
      const std::string name = method == mcv::ReductionMethod::UMAP ? "UMAP" : "Isomap";
      std::string all;
      for (int run = 0; run < runs; ++run) // the fastest of `runs`
      {
        mcv::ReductionResult x = mcv::reduceDimension({ f.values.data(), f.rows, f.cols }, o);
        all += (run ? ", " : "") + std::to_string(static_cast<long>(x.totalMs + 0.5));
        if (run == 0 || (x.ok() && x.totalMs < r[name].totalMs))
          r[name] = std::move(x);
      }
      const auto& x = r[name];
      if (!x.ok())
      {
        std::printf("%s failed: %s\n", name.c_str(), x.error.c_str());
        ++failures;
        continue;
      }
      std::printf("%-6s: features %.0f ms | fit %.0f ms | placement %.0f ms (on %s) | reduction total %.0f ms | "
                  "WHOLE CHAIN %.0f ms | T %.4f   [reduction total of each run, ms: %s]\n",
        name.c_str(), featuresMs, x.fitMs, x.placeMs, mcv::deviceName(x.deviceUsed), x.totalMs, featuresMs + x.totalMs,
        x.trustworthiness, all.c_str());
      printWarnings(x.warnings);
    }
    if (r["Isomap"].ok() && r["UMAP"].ok())
    {
      const double isomapChain = featuresMs + r["Isomap"].totalMs, umapChain = featuresMs + r["UMAP"].totalMs;
      const double target = isomapChain + (r["UMAP"].fitMs - r["Isomap"].fitMs);
      std::printf("UMAP whole chain %.0f ms vs target (Isomap chain %.0f ms + fit difference %+.0f ms) %.0f ms: "
                  "ratio %.3f (<= 1 meets it)\n",
        umapChain, isomapChain, r["UMAP"].fitMs - r["Isomap"].fitMs, target, umapChain / target);
    }
  }
  return failures == 0 ? 0 : 1;
}
