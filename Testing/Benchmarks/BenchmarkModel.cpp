// mcvBenchmarkModel: applying a reduction model against fitting, on the real 3-channel brain
// (Colin27 T1 + AAL + Brodmann, 7.1 M voxels, 24D features computed a slab at a time as
// DimensionReduction's fused path does, Isomap on 10000 references), and a collection of
// volumes reduced with one model against one fit each. Both sides of each ratio are
// measured in the same run, on the same device. Latest results: docs/benchmarks.md.
//
//   mcvBenchmarkModel [--devices cpu,gpu] [--reference 10000] [--volumes 20] [--step 2]
//
// The collection: `volumes` copies of the brain resampled every `step` voxels, copy i with
// the T1 scaled by 1 + 0.01 i (a series whose intensity drifts).
#include "BrainFeatures.h"
#include "CommandLine.h"
#include "ModelRuns.h"

#include <omp.h>

#include <cstdio>
#include <map>
#include <string>
#include <vector>

namespace mt = mcv::testing;

namespace
{
std::vector<mt::Volume> resampled(const std::vector<mt::Volume>& ch, int step, float t1Scale)
{
  std::vector<mt::Volume> out;
  for (std::size_t c = 0; c < ch.size(); ++c)
  {
    const mt::Volume& v = ch[c];
    mt::Volume r;
    r.name = v.name;
    r.grid = v.grid;
    for (int a = 0; a < 3; ++a)
    {
      r.grid.dims[a] = (v.grid.dims[a] + step - 1) / step;
      r.grid.spacing[a] = v.grid.spacing[a] * step;
    }
    for (int k = 0; k < v.grid.dims[2]; k += step)
      for (int j = 0; j < v.grid.dims[1]; j += step)
        for (int i = 0; i < v.grid.dims[0]; i += step)
          r.values.push_back(v.values[(static_cast<std::size_t>(k) * v.grid.dims[1] + j) * v.grid.dims[0] + i] *
            (c == 0 ? t1Scale : 1.0f));
    out.push_back(std::move(r));
  }
  return out;
}

mcv::ReductionOptions isomap(std::size_t reference, mcv::Device device)
{
  mcv::ReductionOptions ro;
  ro.method = mcv::ReductionMethod::Isomap;
  ro.referenceSampleSize = reference;
  ro.device = device;
  return ro;
}
} // namespace

int main(int argc, char** argv)
{
  std::setvbuf(stdout, nullptr, _IOLBF, 0);
  std::map<std::string, std::string> a;
  for (int i = 1; i + 1 < argc; i += 2)
    a[std::string(argv[i]).substr(2)] = argv[i + 1];
  std::string why;
  const bool gpu = mcv::gpuUsable(&why);
  const auto devices = mt::stringList(a.count("devices") ? a["devices"] : (gpu ? "cpu,gpu" : "cpu"));
  const std::size_t reference = a.count("reference") ? std::stoull(a["reference"]) : 10000;
  const int volumes = a.count("volumes") ? std::stoi(a["volumes"]) : 20;
  const int step = a.count("step") ? std::stoi(a["step"]) : 2;
  if (!mt::haveBrain())
  {
    std::printf("Colin27 volumes missing (scripts/fetch-data.sh): nothing to measure\n");
    return 1;
  }
  std::printf("== Reduction models on the real brain (%d OpenMP threads, GPU: %s)\n", omp_get_max_threads(),
    gpu ? "usable" : why.c_str());
  const std::vector<mt::Volume> brain = mt::loadBrain();
  const mcv::ImageGrid grid = brain[0].grid;
  for (const std::string& dev : devices)
  {
    const mcv::Device device = dev == "gpu" ? mcv::Device::GPU : mcv::Device::CPU;
    const mcv::FeatureOptions fo = mt::fused24DOn(device);
    // The whole brain: one fit (statistics, sample, fit, placement) against applying its model.
    const mt::ModelRun fitted = mt::fitModel(mt::floatViews(brain), grid, fo, isomap(reference, device));
    if (!fitted.error.empty())
    {
      std::printf("%s: the fit failed: %s\n", dev.c_str(), fitted.error.c_str());
      continue;
    }
    const mt::ModelRun applied = mt::applyModel(mt::floatViews(brain), grid, fo, fitted, device);
    std::printf("%s  brain %zu voxels, 24D, Isomap M=%zu: fit %.0f ms (fit stage %.0f ms), apply the model %.0f ms "
                "(placement ran on %s): apply / fit = %.2f\n",
      dev.c_str(), grid.voxelCount(), fitted.model.references, fitted.ms, fitted.result.fitMs, applied.ms,
      applied.result.deviceUsed == mcv::Device::GPU ? "GPU" : "CPU", applied.ms / fitted.ms);

    // A collection: one fit each against one model for all.
    double fitsMs = 0, appliesMs = 0;
    mt::ModelRun first;
    for (int v = 0; v < volumes; ++v)
    {
      const std::vector<mt::Volume> volume = resampled(brain, step, 1.0f + 0.01f * static_cast<float>(v));
      const mt::ModelRun own = mt::fitModel(mt::floatViews(volume), volume[0].grid, fo, isomap(reference, device));
      fitsMs += own.ms;
      if (v == 0)
      {
        first = own;
        appliesMs += own.ms; // the one fit of the collection
        continue;
      }
      appliesMs += mt::applyModel(mt::floatViews(volume), volume[0].grid, fo, first, device).ms;
    }
    std::printf("%s  collection of %d volumes of %zu voxels: %d fits %.0f ms, 1 fit + %d applications %.0f ms: "
                "ratio %.2f\n",
      dev.c_str(), volumes, resampled(brain, step, 1.0f)[0].grid.voxelCount(), volumes, fitsMs, volumes - 1,
      appliesMs, appliesMs / fitsMs);
  }
  return 0;
}
