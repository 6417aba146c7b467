// The best-viewpoint capability's one entry point: opacity volume in, view directions out.
#pragma once

#include "Communicator.h"
#include "Device.h"
#include "GridPiece.h"
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
  // Split over processes (MPI ranks; HarrisPCA only): the grid passed in is this process's
  // block with ghost layers enough for the gradient and the Gaussian (1 + KernelWidth/2
  // voxels), `piece` says where it lies and which voxels it owns. Each process selects the
  // top-N of its owned voxels, the lists are merged into the global top-N, and every
  // process gets the same points (whole-volume indices) and view. Default: serial.
  const Communicator* communicator = nullptr;
  GridPiece piece;
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
  InterestPoints points;             // HarrisPCA only; indices of the whole volume
  std::vector<Vec3> pointPositions;  // world positions of `points`
  ViewDirections view;               // view.valid false (with a warning) for flat volumes
  StageTimings timings;
  bool ok() const { return error.empty(); }
};

// `opacity` holds grid.voxelCount() values in [0,1] (x fastest).
BestViewpointResult computeBestViewpoint(
  const float* opacity, const ImageGrid& grid, const BestViewpointOptions& options);

} // namespace mcv
