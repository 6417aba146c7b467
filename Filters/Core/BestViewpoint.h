// The best-viewpoint capability's one entry point: opacity volume in, view directions out.
#pragma once

#include "Device.h"
#include "HarrisResponse.h"
#include "ImageGrid.h"
#include "TopResponses.h"
#include "ViewBaselines.h"
#include "ViewFromPoints.h"

#include <functional>
#include <string>
#include <vector>

namespace mcv
{

enum class ViewMethod
{
  HarrisPCA = 0,        // 3D Harris interest points + PCA (the method of this suite)
  AreaMaximizing = 1,   // baseline: tight bounding box, eq. 7.10-7.11
  ViewpointEntropy = 2  // baseline: opacity entropy over sphere samples
};

struct BestViewpointOptions
{
  ViewMethod method = ViewMethod::HarrisPCA;
  HarrisParameters harris;
  int numberOfInterestPoints = 2048;
  Device device = Device::Auto;
  EntropyOptions entropy;
  std::function<void(double)> progress; // optional, receives [0,1]
};

struct StageTimings
{
  double harrisMs = 0, selectMs = 0, pcaMs = 0, totalMs = 0;
};

struct BestViewpointResult
{
  std::string error;                 // non-empty: nothing else is meaningful
  std::vector<std::string> warnings; // one line each
  Device deviceUsed = Device::CPU;
  InterestPoints points;             // HarrisPCA only
  std::vector<Vec3> pointPositions;  // world positions of `points`
  ViewDirections view;               // view.valid false (with a warning) for flat volumes
  StageTimings timings;
  bool ok() const { return error.empty(); }
};

// `opacity` holds grid.voxelCount() values in [0,1] (x fastest).
BestViewpointResult computeBestViewpoint(
  const float* opacity, const ImageGrid& grid, const BestViewpointOptions& options);

} // namespace mcv
