#include "BestViewpoint.h"

#ifdef MCV_HAS_CUDA
#include "../../cuda/HarrisCuda.h"
#endif

#include <chrono>
#include <string>
#include <vector>

namespace mcv
{

namespace
{

using Clock = std::chrono::steady_clock;

double millisecondsSince(Clock::time_point start)
{
  return std::chrono::duration<double, std::milli>(Clock::now() - start).count();
}

void report(const BestViewpointOptions& options, double fraction)
{
  if (options.progress)
  {
    options.progress(fraction);
  }
}

// Harris response + top-N on the chosen device; the GPU path falls back to the CPU on
// any CUDA failure, so a result always comes back.
InterestPoints findInterestPoints(const float* opacity, const ImageGrid& grid,
  const BestViewpointOptions& options, BestViewpointResult& result)
{
  std::string warning;
  result.deviceUsed = resolveDevice(options.device, &warning);
  if (!warning.empty())
  {
    result.warnings.push_back(warning);
  }
  const int N = options.numberOfInterestPoints;
#ifdef MCV_HAS_CUDA
  // A single slice is tiny and takes the 2D form: the CPU handles it.
  if (result.deviceUsed == Device::GPU && grid.extendedAxes() == 2)
  {
    result.deviceUsed = Device::CPU;
  }
  if (result.deviceUsed == Device::GPU)
  {
    InterestPoints points;
    std::string error;
    cuda::GpuStageTimings gpu;
    if (cuda::harrisTopN(opacity, grid, options.harris, N, points, &error, &gpu))
    {
      result.timings.harrisMs = gpu.uploadMs + gpu.harrisMs;
      result.timings.selectMs = gpu.selectMs + gpu.downloadMs;
      return points;
    }
    result.warnings.push_back("GPU path failed (" + error + "); running on the CPU.");
    result.deviceUsed = Device::CPU;
  }
#endif
  auto start = Clock::now();
  std::vector<float> response(grid.voxelCount());
  computeHarrisResponseCPU(opacity, grid, options.harris, response.data());
  result.timings.harrisMs = millisecondsSince(start);
  report(options, 0.7);

  start = Clock::now();
  InterestPoints points = selectTopResponsesCPU(response.data(), response.size(), N);
  result.timings.selectMs = millisecondsSince(start);
  return points;
}

void harrisPCA(const float* opacity, const ImageGrid& grid, const BestViewpointOptions& options,
  BestViewpointResult& result)
{
  result.points = findInterestPoints(opacity, grid, options, result);
  report(options, 0.9);

  const auto start = Clock::now();
  result.pointPositions = worldPositions(result.points, grid);
  const std::size_t found = result.points.size();
  if (found == 0)
  {
    result.warnings.push_back("No interest points: the opacity volume has no corner or "
                              "blob (it is constant, empty or flat); no view direction.");
  }
  else if (found < static_cast<std::size_t>(options.numberOfInterestPoints))
  {
    result.warnings.push_back("Only " + std::to_string(found) +
      " voxels have a positive Harris response, fewer than the " +
      std::to_string(options.numberOfInterestPoints) + " asked for: using all of them.");
  }
  if (found > 0)
  {
    result.view = computeViewDirections(result.pointPositions);
    if (!result.view.valid)
    {
      result.warnings.push_back("No view direction: " + result.view.message + ".");
    }
  }
  result.timings.pcaMs = millisecondsSince(start);
}

} // namespace

BestViewpointResult computeBestViewpoint(
  const float* opacity, const ImageGrid& grid, const BestViewpointOptions& options)
{
  BestViewpointResult result;
  const auto start = Clock::now();
  if (opacity == nullptr || grid.voxelCount() == 0)
  {
    result.error = "the input volume is empty (no voxels)";
    return result;
  }
  for (int a = 0; a < 3; ++a)
  {
    if (!(grid.spacing[a] > 0.0))
    {
      result.error = "the voxel spacing must be positive along every axis";
      return result;
    }
  }
  if (grid.extendedAxes() < 2)
  {
    result.error = "the input has fewer than two axes with more than one voxel: a line or a "
                   "point has no view direction";
    return result;
  }
  if (options.numberOfInterestPoints <= 0)
  {
    result.error = "NumberOfInterestPoints must be positive";
    return result;
  }
  const std::string badParameters = checkHarrisParameters(options.harris);
  if (!badParameters.empty())
  {
    result.error = badParameters;
    return result;
  }
  if (grid.extendedAxes() == 2)
  {
    result.warnings.push_back("The input is a single slice: interest points use the 2D Harris "
                              "response and the view direction is the slice normal.");
  }
  report(options, 0.0);

  switch (options.method)
  {
    case ViewMethod::HarrisPCA:
      harrisPCA(opacity, grid, options, result);
      break;
    case ViewMethod::AreaMaximizing:
      result.view = areaMaximizingView(opacity, grid);
      break;
    case ViewMethod::ViewpointEntropy:
      result.view = viewpointEntropyView(opacity, grid, options.entropy, options.progress);
      break;
  }
  if (options.method != ViewMethod::HarrisPCA && !result.view.valid)
  {
    result.warnings.push_back("No view direction: " + result.view.message + ".");
  }
  result.timings.totalMs = millisecondsSince(start);
  report(options, 1.0);
  return result;
}

} // namespace mcv
