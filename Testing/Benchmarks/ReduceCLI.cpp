// mcvReduceCLI: the dimension-reduction core on a raw float32 matrix, for the comparison
// with scikit-learn (compare_sklearn.py) and the whole-volume benchmark.
//
//   mcvReduceCLI --input features.f32 --rows N --cols D [--method pca|isomap|lle|umap]
//                [--dim 3] [--neighbors 50] [--landmarks 500] [--reference 10000]
//                [--min-dist 0.1] [--epochs 0]
//                [--seed 0] [--trust-sample 2000] [--output embedding.f32] [--json out.json]
//                [--repeat 1] [--repeat-below 2]
//
// The input is N x D float32, row-major (numpy's C order). The output (when asked for) is
// N x dim float32. A JSON object with times, trustworthiness, warnings and the time of
// every progress stage is printed on stdout (and written to --json).
// --repeat R runs the reduction up to R times in this process, while the runs so far took
// less than --repeat-below seconds in all, and reports the fastest (same seed, same answer):
// the rule compare_sklearn.py applies to scikit-learn's fits in its one Python process, whose
// heap and threads are warm after the first; a fresh process pays page faults for every
// large buffer.
#include "DimensionReduction.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <iostream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

namespace
{
std::string jsonString(const std::string& s)
{
  std::string out = "\"";
  for (char c : s)
  {
    if (c == '"' || c == '\\')
    {
      out += '\\';
    }
    if (c == '\n')
    {
      out += "\\n";
      continue;
    }
    out += c;
  }
  return out + "\"";
}

std::string jsonNumber(double v)
{
  if (!std::isfinite(v))
  {
    return "null";
  }
  std::ostringstream s;
  s.precision(10);
  s << v;
  return s.str();
}

int usage(const char* why)
{
  std::cerr << "mcvReduceCLI: " << why << "\n"
            << "usage: mcvReduceCLI --input F --rows N --cols D [--method pca|isomap|lle|umap] [--dim 3]\n"
               "       [--neighbors 50] [--landmarks 500] [--reference 10000] [--seed 0]\n"
               "       [--min-dist 0.1] [--epochs 0 (UMAP: automatic)]\n"
               "       [--trust-sample 2000] [--output F] [--json F] [--repeat 1] [--repeat-below 2]\n";
  return 2;
}
} // namespace

int main(int argc, char** argv)
{
  std::map<std::string, std::string> a;
  for (int i = 1; i + 1 < argc; i += 2)
  {
    if (std::string(argv[i]).rfind("--", 0) != 0)
    {
      return usage((std::string("unexpected argument ") + argv[i]).c_str());
    }
    a[argv[i] + 2] = argv[i + 1];
  }
  if (!a.count("input") || !a.count("rows") || !a.count("cols"))
  {
    return usage("--input, --rows and --cols are required");
  }
  const std::size_t rows = std::stoull(a["rows"]);
  const int cols = std::stoi(a["cols"]);
  std::vector<float> data(rows * static_cast<std::size_t>(cols));
  {
    std::ifstream in(a["input"], std::ios::binary);
    if (!in.read(reinterpret_cast<char*>(data.data()), static_cast<std::streamsize>(data.size() * sizeof(float))))
    {
      return usage(("cannot read " + std::to_string(data.size() * sizeof(float)) + " bytes from " + a["input"]).c_str());
    }
  }
  mcv::ReductionOptions o;
  const std::string method = a.count("method") ? a["method"] : "pca";
  o.method = method == "isomap" ? mcv::ReductionMethod::Isomap
    : method == "lle"           ? mcv::ReductionMethod::LLE
    : method == "umap"          ? mcv::ReductionMethod::UMAP
                                : mcv::ReductionMethod::PCA;
  o.outputDimension = a.count("dim") ? std::stoi(a["dim"]) : 3;
  o.numberOfNeighbors = a.count("neighbors") ? std::stoi(a["neighbors"]) : 50;
  o.numberOfLandmarks = a.count("landmarks") ? std::stoi(a["landmarks"]) : 500;
  o.minimumDistance = a.count("min-dist") ? std::stod(a["min-dist"]) : 0.1;
  o.numberOfEpochs = a.count("epochs") ? std::stoi(a["epochs"]) : 0;
  o.referenceSampleSize = a.count("reference") ? std::stoull(a["reference"]) : 10000;
  o.randomSeed = a.count("seed") ? std::stoull(a["seed"]) : 0;
  o.trustworthinessSample = a.count("trust-sample") ? std::stoull(a["trust-sample"]) : 2000;
  o.device = mcv::Device::CPU;

  // The OpenMP threads are started before the clock: a process pays that once (~5 ms here),
  // ParaView and a warm Python process (scikit-learn's side) have paid it already.
#pragma omp parallel
  {
  }
  const int repeat = a.count("repeat") ? std::max(1, std::stoi(a["repeat"])) : 1;
  const double repeatBelowMs = 1000.0 * (a.count("repeat-below") ? std::stod(a["repeat-below"]) : 2.0);
  // Time of every stage: from its first progress call to the next stage's.
  using Clock = std::chrono::steady_clock;
  mcv::ReductionResult r;
  std::vector<std::pair<std::string, double>> stages;
  double wallMs = 0.0, spentMs = 0.0;
  int runs = 0;
  while (runs < repeat && (runs == 0 || spentMs < repeatBelowMs))
  {
    const auto t0 = Clock::now();
    std::vector<std::pair<std::string, double>> runStages;
    o.progress = [&](const char* stage, double) {
      if (runStages.empty() || runStages.back().first != stage)
      {
        runStages.emplace_back(stage, std::chrono::duration<double, std::milli>(Clock::now() - t0).count());
      }
    };
    mcv::ReductionResult run = mcv::reduceDimension({ data.data(), rows, cols }, o);
    const double runWallMs = std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
    spentMs += runWallMs;
    if (runs++ == 0 || (run.ok() && run.totalMs < r.totalMs))
    {
      r = std::move(run);
      stages = std::move(runStages);
      wallMs = runWallMs;
    }
  }

  std::ostringstream j;
  j << "{\"method\": " << jsonString(method) << ", \"rows\": " << rows << ", \"cols\": " << cols
    << ", \"ok\": " << (r.ok() ? "true" : "false") << ", \"error\": " << jsonString(r.error)
    << ", \"fit_ms\": " << jsonNumber(r.fitMs) << ", \"place_ms\": " << jsonNumber(r.placeMs)
    << ", \"total_ms\": " << jsonNumber(r.totalMs) << ", \"wall_ms\": " << jsonNumber(wallMs)
    << ", \"trustworthiness\": " << jsonNumber(r.trustworthiness)
    << ", \"variance_retained\": " << jsonNumber(r.varianceRetained)
    << ", \"reference_points\": " << r.referenceIndices.size() << ", \"runs\": " << runs << ", \"eigenvalues\": [";
  for (std::size_t i = 0; i < r.eigenvalues.size() && i < 10; ++i)
  {
    j << (i ? ", " : "") << jsonNumber(r.eigenvalues[i]);
  }
  j << "], \"warnings\": [";
  for (std::size_t i = 0; i < r.warnings.size(); ++i)
  {
    j << (i ? ", " : "") << jsonString(r.warnings[i]);
  }
  j << "], \"stages_ms\": [";
  for (std::size_t i = 0; i < stages.size(); ++i)
  {
    const double end = i + 1 < stages.size() ? stages[i + 1].second : wallMs;
    j << (i ? ", " : "") << "[" << jsonString(stages[i].first) << ", " << jsonNumber(end - stages[i].second) << "]";
  }
  j << "]}";
  std::cout << j.str() << std::endl;
  if (a.count("json"))
  {
    std::ofstream(a["json"]) << j.str() << "\n";
  }
  if (r.ok() && a.count("output"))
  {
    std::ofstream out(a["output"], std::ios::binary);
    out.write(reinterpret_cast<const char*>(r.coordinates.data()),
      static_cast<std::streamsize>(r.coordinates.size() * sizeof(float)));
  }
  return r.ok() ? 0 : 1;
}
