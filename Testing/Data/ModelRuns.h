// Fitting a reduction model on a volume's channels and applying it, on the fused path
// (FeatureBricks -> reduceDimension) as DimensionReduction does: the fit keeps its model
// (ReductionOptions::fittedModel) and the normalisation's offsets and scales; applying
// gives those to FeatureBricks (FeatureOptions::givenOffset/givenScale) and the model to
// reduceDimension, with a ModelDistance output. Shared by the core and GPU tests and the
// model benchmark. Header-only.
#pragma once

#include "DimensionReduction.h"
#include "FeatureBricks.h"

#include <chrono>
#include <string>
#include <vector>

namespace mcv
{
namespace testing
{

struct ModelRun
{
  std::string error; // non-empty: what failed
  ReductionResult result;
  ReductionModel model;               // the fit's (fitModel only)
  std::vector<double> offset, scale;  // the normalisation used
  std::vector<float> distance;        // ModelDistance (applyModel only)
  double ms = 0;                      // features' preparation and reduction
};

// The 24D features of the fused path, their statistics pass on `device`.
inline FeatureOptions fused24DOn(Device device)
{
  FeatureOptions o;
  o.preset = FeaturePreset::TwentyFourD;
  o.device = device;
  return o;
}

inline double msSince(std::chrono::steady_clock::time_point t)
{
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t).count();
}

// Runs `ro` on the fused features `fo` of `channels` (prepared first), timed.
inline ModelRun runOnBricks(const std::vector<ChannelView>& channels, const ImageGrid& grid, const FeatureOptions& fo,
  ReductionOptions ro, ModelRun run)
{
  const auto start = std::chrono::steady_clock::now();
  FeatureBricks bricks(channels, grid, fo);
  FeatureResult prepared;
  if (!bricks.prepare(prepared))
  {
    run.error = prepared.error;
    return run;
  }
  run.offset = prepared.columnOffset;
  run.scale = prepared.columnScale;
  if (!run.distance.empty())
  {
    ro.modelDistanceOutput = run.distance.data();
  }
  if (!ro.model)
  {
    ro.fittedModel = &run.model;
  }
  run.result = reduceDimension(bricks, ro);
  run.error = run.result.error;
  run.ms = msSince(start);
  return run;
}

// Fits `ro` on the fused features `fo` of `channels`, keeping the model.
inline ModelRun fitModel(const std::vector<ChannelView>& channels, const ImageGrid& grid, const FeatureOptions& fo,
  const ReductionOptions& ro)
{
  return runOnBricks(channels, grid, fo, ro, ModelRun());
}

// Places `channels` with `fitted`'s model and normalisation on `device` (no fit).
inline ModelRun applyModel(const std::vector<ChannelView>& channels, const ImageGrid& grid, FeatureOptions fo,
  const ModelRun& fitted, Device device)
{
  fo.givenOffset = fitted.offset;
  fo.givenScale = fitted.scale;
  fo.device = device;
  ReductionOptions ro;
  ro.model = &fitted.model;
  ro.device = device;
  ModelRun run;
  run.distance.resize(grid.voxelCount());
  return runOnBricks(channels, grid, fo, ro, std::move(run));
}

} // namespace testing
} // namespace mcv
