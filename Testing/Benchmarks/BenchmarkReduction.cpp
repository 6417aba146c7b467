// mcvBenchmarkReduction: the whole dimension-reduction chain on the real 3-channel brain
// (Colin27 T1 + AAL + Brodmann, 181 x 217 x 181 = 7.1 M voxels): features (24D and 6D),
// Isomap fitted on a reference sample of 10000, out-of-sample placement of every voxel.
// Per-stage times for the CPU and (when a GPU is usable) the GPU path, and the kd-tree
// placement as the in-run baseline, timed on a subset of rows and extrapolated (said so in
// the output). Latest results: docs/benchmarks.md.
//
//   mcvBenchmarkReduction [--presets 24,6] [--devices cpu,gpu] [--reference 10000]
//                         [--baseline-rows 100000] [--sweep] [--sweep-rows 20000] [--no-fused]
//
// Each device runs the chain twice: with the Features array stored (features, then the
// reduction over it) and on the fused path DimensionReduction takes (FeatureBricks: a
// statistics pass, then the features of a slab at a time, never stored), with the fused
// coordinates compared with the stored ones.
// --sweep: kd-tree vs brute-force placement time against the dimension (the first D of
// the 24 brain features), the measurement behind chooseKnnMethod's crossover.
#include "BrainFeatures.h"
#include "CommandLine.h"
#include "DimensionReduction.h"
#include "ExactKnn.h"
#include "FeatureBricks.h"
#include "ForwardingRows.h"
#include "OutOfSample.h"
#include "ReferenceSample.h"

#include <omp.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <functional>
#include <cstdio>
#include <cstdlib>
#include <map>
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

// Rows i = 0, step, 2 step, ... of a matrix: a subset spread over the whole volume.
std::vector<float> everyNth(const mt::BrainFeatureMatrix& f, std::size_t step, const std::vector<int>& columns)
{
  std::vector<float> rows;
  for (std::size_t i = 0; i < f.rows; i += step)
    for (int c : columns)
      rows.push_back(f.values[i * f.cols + c]);
  return rows;
}

double timePlacement(const mcv::RowMatrixF& refX, const mcv::RowMatrixF& refY, const std::vector<float>& rows,
  mcv::KnnMethod method, std::vector<float>& out, std::size_t* scans = nullptr, bool mergeEqualRows = true)
{
  const int D = static_cast<int>(refX.cols());
  const std::size_t n = rows.size() / D;
  out.assign(n * refY.cols(), 0.f);
  mcv::OutOfSampleOptions o;
  o.knn = method;
  o.mergeEqualRows = mergeEqualRows;
  const auto t = Clock::now();
  const auto r = mcv::placeOutOfSample(refX, refY, rows.data(), n, D, {}, out.data(), o);
  if (scans)
    *scans = r.radiusScans;
  return msSince(t);
}

struct ChainResult
{
  bool ok = false;
  mcv::ReductionResult r;
  double featuresMs = 0, chainMs = 0;
  std::vector<std::pair<std::string, double>> stages;
};

ChainResult runChain(const mt::BrainFeatureMatrix& f, mcv::Device device, std::size_t reference)
{
  ChainResult c;
  mcv::ReductionOptions o;
  o.method = mcv::ReductionMethod::Isomap;
  o.outputDimension = 3;
  o.referenceSampleSize = reference;
  o.device = device;
  const auto t0 = Clock::now();
  o.progress = [&](const char* stage, double) {
    if (c.stages.empty() || c.stages.back().first != stage)
      c.stages.emplace_back(stage, msSince(t0));
  };
  c.r = mcv::reduceDimension({ f.values.data(), f.rows, f.cols }, o);
  const double total = msSince(t0);
  for (std::size_t i = 0; i < c.stages.size(); ++i)
    c.stages[i].second = (i + 1 < c.stages.size() ? c.stages[i + 1].second : total) - c.stages[i].second;
  c.ok = c.r.ok();
  return c;
}

// The fused path's rows with the time of their single-voxel gathers (the reference
// sample's features) counted: what of the sample's stage is feature work on the host.
class TimedRows final : public mt::ForwardingRows
{
public:
  using ForwardingRows::ForwardingRows;
  void gather(const std::size_t* index, std::size_t n, float* out) override
  {
    const auto t = Clock::now();
    ForwardingRows::gather(index, n, out);
    gatherMs += msSince(t);
    ++gathers;
    gatheredRows += n;
  }
  double gatherMs = 0;
  std::size_t gathers = 0, gatheredRows = 0;
};

// The fused path: FeatureBricks' statistics pass (prepare) is the "features" stage, the
// features of each slab are computed again where the reduction reads them.
ChainResult runFusedChain(const std::vector<mt::Volume>& ch, mcv::FeaturePreset preset, mcv::Device device,
  std::size_t reference, std::string& passes)
{
  ChainResult c;
  mcv::FeatureOptions fo;
  fo.preset = preset;
  fo.device = device;
  mcv::ReductionOptions o;
  o.method = mcv::ReductionMethod::Isomap;
  o.outputDimension = 3;
  o.referenceSampleSize = reference;
  o.device = device;
  const std::vector<mcv::ChannelView> views = mt::floatViews(ch);
  const auto t0 = Clock::now();
  mcv::FeatureBricks bricks(views, ch[0].grid, fo);
  mcv::FeatureResult prepared;
  if (!bricks.prepare(prepared))
  {
    c.r.error = prepared.error;
    return c;
  }
  c.featuresMs = msSince(t0);
  const auto t1 = Clock::now();
  o.progress = [&](const char* stage, double) {
    if (c.stages.empty() || c.stages.back().first != stage)
      c.stages.emplace_back(stage, msSince(t1));
  };
  TimedRows timed(bricks);
  c.r = mcv::reduceDimension(timed, o);
  const double total = msSince(t1);
  for (std::size_t i = 0; i < c.stages.size(); ++i)
    c.stages[i].second = (i + 1 < c.stages.size() ? c.stages[i + 1].second : total) - c.stages[i].second;
  // Each GPU pass's time, and of it: opening the stream (buffers, pinned staging), the
  // host's conversion of the channels, the waits for the device.
  for (const auto& pass : bricks.devicePasses())
  {
    char line[160];
    std::snprintf(line, sizeof line, " [%s%s%.0f ms: setup %.0f, fill %.0f, wait %.0f]", pass.name.c_str(),
      pass.ok ? " " : " FAILED ", pass.stats.totalMs, pass.stats.setupMs, pass.stats.fillMs, pass.stats.waitMs);
    passes += line;
  }
  char line[160];
  std::snprintf(line, sizeof line, "; sample's gathers: %zu calls, %zu voxels, %.0f ms", timed.gathers,
    timed.gatheredRows, timed.gatherMs);
  passes += line;
  c.ok = c.r.ok();
  return c;
}

// Rows of two runs' coordinates within 1e-4 of the range of `a`'s, among the rows
// `compared` accepts (all when empty); counts and the worst difference.
struct Agreement
{
  std::size_t compared = 0, within = 0;
  float worst = 0, scale = 0;
};
Agreement rowsWithin(const mcv::ReductionResult& a, const mcv::ReductionResult& b,
  const std::function<bool(std::size_t)>& compared = {})
{
  Agreement g;
  for (float v : a.coordinates)
    g.scale = std::max(g.scale, std::abs(v));
  if (a.coordinates.size() != b.coordinates.size())
    return g;
  for (std::size_t row = 0; row < a.coordinates.size() / 3; ++row)
  {
    if (compared && !compared(row))
      continue;
    ++g.compared;
    bool eq = true;
    for (std::size_t k = row * 3; k < row * 3 + 3; ++k)
    {
      const float d = std::abs(a.coordinates[k] - b.coordinates[k]);
      g.worst = std::max(g.worst, d);
      eq = eq && d <= 1e-4f * g.scale;
    }
    g.within += eq;
  }
  return g;
}

void printChain(const char* label, const ChainResult& c)
{
  std::printf("%s: features %.0f ms | fit %.0f ms | placement %.0f ms | reduction total %.0f ms | "
              "WHOLE CHAIN %.0f ms (placement on %s)\n",
    label, c.featuresMs, c.r.fitMs, c.r.placeMs, c.r.totalMs, c.featuresMs + c.r.totalMs,
    mcv::deviceName(c.r.deviceUsed));
  std::printf("    stages:");
  std::map<std::string, double> merged;
  for (const auto& s : c.stages)
    std::printf(" [%s %.0f ms]", s.first.c_str(), s.second);
  std::printf("\n");
  for (const auto& w : c.r.warnings)
    std::printf("    warning: %s\n", w.c_str());
}
} // namespace

int main(int argc, char** argv)
{
  std::setvbuf(stdout, nullptr, _IOLBF, 0); // progress visible in a log file
  std::map<std::string, std::string> a;
  bool sweep = false, fused = true;
  for (int i = 1; i < argc; ++i)
  {
    const std::string k = argv[i];
    if (k == "--sweep")
      sweep = true;
    else if (k == "--no-fused")
      fused = false;
    else if (k.rfind("--", 0) == 0 && i + 1 < argc)
      a[k.substr(2)] = argv[++i];
    else
    {
      std::fprintf(stderr, "unexpected argument %s\n", argv[i]);
      return 2;
    }
  }
  const auto presets = mt::stringList(a.count("presets") ? a["presets"] : "24,6");
  std::string why;
  const bool gpu = mcv::gpuUsable(&why);
  auto devices = mt::stringList(a.count("devices") ? a["devices"] : (gpu ? "cpu,gpu" : "cpu"));
  const std::size_t reference = a.count("reference") ? std::stoull(a["reference"]) : 10000;
  const std::size_t baselineRows = a.count("baseline-rows") ? std::stoull(a["baseline-rows"]) : 100000;
  const std::size_t sweepRows = a.count("sweep-rows") ? std::stoull(a["sweep-rows"]) : 20000;

  if (!mt::haveBrain())
  {
    std::printf("Colin27 volumes missing (scripts/fetch-data.sh): nothing to measure\n");
    return 1;
  }
  std::printf("== Dimension-reduction chain on the real brain (%d OpenMP threads, GPU: %s, CPU kNN kernel: %s)\n",
    omp_get_max_threads(), gpu ? "usable" : why.c_str(), mcv::TiledKnn::vectorKernel() ? "AVX2+FMA" : "portable");
  auto t = Clock::now();
  const auto ch = mt::loadBrain();
  std::printf("loaded %zu voxels x 3 channels in %.0f ms (not part of the chain)\n", ch[0].grid.voxelCount(), msSince(t));

  for (const auto& p : presets)
  {
    const auto preset = p == "6" ? mcv::FeaturePreset::SixD : mcv::FeaturePreset::TwentyFourD;
    ChainResult cpuChain;
    mt::BrainFeatureMatrix cpuFeatures;
    for (const auto& dev : devices)
    {
      const mcv::Device device = dev == "gpu" ? mcv::Device::GPU : mcv::Device::CPU;
      t = Clock::now();
      mt::BrainFeatureMatrix f = mt::brainFeatures(ch, preset, device);
      const double featuresMs = msSince(t);
      if (!f.result.ok())
      {
        std::printf("%sD %s: features failed: %s\n", p.c_str(), dev.c_str(), f.result.error.c_str());
        continue;
      }
      ChainResult c = runChain(f, device, reference);
      c.featuresMs = featuresMs;
      if (!c.ok)
      {
        std::printf("%sD %s: reduction failed: %s\n", p.c_str(), dev.c_str(), c.r.error.c_str());
        continue;
      }
      const std::string label = p + "D " + dev + " (features on " + mcv::deviceName(f.result.deviceUsed) + ")";
      printChain(label.c_str(), c);
      if (fused)
      {
        std::string passes;
        const ChainResult fc = runFusedChain(ch, preset, device, reference, passes);
        if (!fc.ok)
          std::printf("%sD %s fused: reduction failed: %s\n", p.c_str(), dev.c_str(), fc.r.error.c_str());
        else
        {
          const std::string fusedLabel = p + "D " + dev + " FUSED (statistics pass as 'features')";
          printChain(fusedLabel.c_str(), fc);
          const Agreement g = rowsWithin(c.r, fc.r);
          std::printf("    fused vs stored: %s reference rows; %zu of %zu rows within 1e-4 of the range (worst %.3g); "
                      "GPU passes:%s; fused / stored whole chain %.2f\n",
            c.r.referenceIndices == fc.r.referenceIndices ? "same" : "DIFFERENT", g.within, g.compared,
            g.worst, passes.empty() ? " none" : passes.c_str(),
            (fc.featuresMs + fc.r.totalMs) / (c.featuresMs + c.r.totalMs));
        }
      }
      if (device == mcv::Device::CPU)
      {
        cpuChain = std::move(c);
        cpuFeatures = std::move(f);
      }
      else if (cpuChain.ok && cpuChain.r.coordinates.size() == c.r.coordinates.size())
      {
        // Same features? (GPU and CPU features agree to float rounding, so compare placements
        // only where the features are bit-identical and the references are the same rows.)
        const bool sameRefs = cpuChain.r.referenceIndices == c.r.referenceIndices;
        const Agreement g = sameRefs ? rowsWithin(cpuChain.r, c.r, [&](std::size_t i) {
          return std::equal(f.values.begin() + i * f.cols, f.values.begin() + (i + 1) * f.cols,
            cpuFeatures.values.begin() + i * f.cols);
        })
                                     : Agreement();
        std::printf("    GPU vs CPU: %s reference rows; on %zu rows with bit-identical features, %zu within 1e-4 of "
                    "the coordinate range (worst %.3g of %.3g)\n",
          sameRefs ? "same" : "DIFFERENT", g.compared, g.within, g.worst, g.scale);
      }
    }
    if (!cpuChain.ok)
      continue;

    // Baseline: the kd-tree placement on every step-th row, against
    // the tiled brute force on the same rows and the same fitted model.
    const auto& r = cpuChain.r;
    const int D = static_cast<int>(r.usedColumns.size());
    mcv::RowMatrixF refX(static_cast<Eigen::Index>(r.referenceIndices.size()), D);
    mcv::RowMatrixF refY(static_cast<Eigen::Index>(r.referenceIndices.size()), 3);
    for (std::size_t i = 0; i < r.referenceIndices.size(); ++i)
    {
      const std::size_t row = static_cast<std::size_t>(r.referenceIndices[i]);
      for (int c = 0; c < D; ++c)
        refX(i, c) = cpuFeatures.values[row * cpuFeatures.cols + r.usedColumns[c]];
      for (int c = 0; c < 3; ++c)
        refY(i, c) = r.coordinates[row * 3 + c];
    }
    const std::size_t step = std::max<std::size_t>(1, cpuFeatures.rows / baselineRows);
    const auto rows = everyNth(cpuFeatures, step, r.usedColumns);
    const std::size_t n = rows.size() / D;
    std::vector<float> kdOut, bfOut;
    std::size_t kdScans = 0, bfScans = 0;
    const double kdMs = timePlacement(refX, refY, rows, mcv::KnnMethod::KdTree, kdOut, &kdScans);
    const double bfMs = timePlacement(refX, refY, rows, mcv::KnnMethod::BruteForce, bfOut, &bfScans);
    std::size_t agree = 0;
    for (std::size_t i = 0; i < n; ++i)
      agree += std::equal(kdOut.begin() + i * 3, kdOut.begin() + (i + 1) * 3, bfOut.begin() + i * 3);
    const double scaleUp = static_cast<double>(cpuFeatures.rows) / static_cast<double>(n);
    std::printf("%sD baseline on %zu rows (every %zu-th voxel), EXTRAPOLATED x%.1f to all %zu rows:\n"
                "    kd-tree placement %.0f ms -> ~%.1f s; tiled brute force %.0f ms -> ~%.1f s; ratio kd/brute %.2f; "
                "radius scans %zu / %zu; identical coordinates on %zu / %zu rows\n",
      p.c_str(), n, step, scaleUp, cpuFeatures.rows, kdMs, kdMs * scaleUp / 1000, bfMs, bfMs * scaleUp / 1000,
      kdMs / bfMs, kdScans, bfScans, agree, n);
    std::printf("    in-run: full CPU placement (%s) %.1f s vs extrapolated kd-tree %.1f s: x%.1f\n",
      mcv::knnMethodName(mcv::chooseKnnMethod(D)), r.placeMs / 1000, kdMs * scaleUp / 1000,
      kdMs * scaleUp / r.placeMs);
    {
      // Runs of equal rows (the background) searched once, against every row searched.
      const auto all = everyNth(cpuFeatures, 1, r.usedColumns);
      std::vector<float> merged, unmerged;
      const auto method = mcv::chooseKnnMethod(D);
      const double mergedMs = timePlacement(refX, refY, all, method, merged);
      const double unmergedMs = timePlacement(refX, refY, all, method, unmerged, nullptr, false);
      std::printf("    in-run: CPU placement of all %zu rows (%s), equal neighbouring rows searched once %.1f s vs "
                  "every row searched %.1f s: x%.2f; identical coordinates: %s\n",
        cpuFeatures.rows, mcv::knnMethodName(method), mergedMs / 1000, unmergedMs / 1000, unmergedMs / mergedMs,
        merged == unmerged ? "yes" : "NO");
    }

    if (sweep && preset == mcv::FeaturePreset::TwentyFourD)
    {
      std::printf("== crossover sweep: placement of %zu rows, %zu references, first D of the 24 features\n", sweepRows,
        reference);
      for (int d : { 4, 6, 8, 10, 12, 16, 24 })
      {
        std::vector<int> cols;
        for (int c = 0; c < d; ++c)
          cols.push_back(c);
        mcv::ReferenceSampleOptions so;
        so.size = reference;
        const auto refRows = mcv::drawReferenceSample(cpuFeatures.values.data(), cpuFeatures.rows, 24, cols, {}, so);
        mcv::RowMatrixF sx(static_cast<Eigen::Index>(refRows.size()), d);
        mcv::RowMatrixF sy = mcv::RowMatrixF::Random(static_cast<Eigen::Index>(refRows.size()), 3);
        for (std::size_t i = 0; i < refRows.size(); ++i)
          for (int c = 0; c < d; ++c)
            sx(i, c) = cpuFeatures.values[static_cast<std::size_t>(refRows[i]) * 24 + c];
        const auto srows = everyNth(cpuFeatures, std::max<std::size_t>(1, cpuFeatures.rows / sweepRows), cols);
        std::vector<float> o1, o2;
        const double kd = timePlacement(sx, sy, srows, mcv::KnnMethod::KdTree, o1);
        const double bf = timePlacement(sx, sy, srows, mcv::KnnMethod::BruteForce, o2);
        std::printf("    D=%2d: kd-tree %7.0f ms, brute force %7.0f ms, kd/brute %.2f (Auto picks %s)\n", d, kd, bf,
          kd / bf, mcv::knnMethodName(mcv::chooseKnnMethod(d)));
      }
    }
  }
  return 0;
}
