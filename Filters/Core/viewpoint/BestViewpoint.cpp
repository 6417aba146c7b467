#include "BestViewpoint.h"

#ifdef MCV_HAS_CUDA
#include "cuda/HarrisCuda.h"
#endif

#include <algorithm>
#include <chrono>
#include <cmath>
#include <sstream>
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

bool isPartialBlock(const GridPiece& piece, const ImageGrid& grid)
{
  return piece.wholeDims[0] > 0 && !piece.isWhole(grid);
}

// Responses of the voxels this process does not own set to 0, which is never a candidate.
void keepOwnedResponses(const GridPiece& piece, const ImageGrid& grid, float* response)
{
  const int nx = grid.dims[0], ny = grid.dims[1], nz = grid.dims[2];
#pragma omp parallel for schedule(static)
  for (int k = 0; k < nz; ++k)
  {
    float* slice = response + static_cast<std::size_t>(k) * nx * ny;
    for (int j = 0; j < ny; ++j)
    {
      for (int i = 0; i < nx; ++i)
      {
        if (!piece.owns(i, j, k))
        {
          slice[static_cast<std::size_t>(j) * nx + i] = 0.f;
        }
      }
    }
  }
}

// Harris response + top-N on the chosen device; the GPU path falls back to the CPU on
// any CUDA failure, so a result always comes back. A partial block (split over processes)
// selects among its owned voxels only and returns whole-volume indices.
// The grid the Harris response is computed on: the same voxels with the spacing divided by
// its geometric mean. R = det(M) - k tr(M)^3 scales as spacing^-6 in world units, which
// overflows or underflows float for 10 nm voxels written in metres (1e-8) or for spacings
// of 1e9; a uniform scale multiplies every response by the same positive factor, so the
// ranking of the voxels, and the view, are those of the world units.
ImageGrid unitFreeGrid(const ImageGrid& grid)
{
  ImageGrid scaled = grid;
  const double mean = std::cbrt(grid.spacing[0] * grid.spacing[1] * grid.spacing[2]);
  if (std::isfinite(mean) && mean > 0)
  {
    for (int a = 0; a < 3; ++a)
    {
      scaled.spacing[a] = grid.spacing[a] / mean;
    }
  }
  else // the product under- or overflows double: scale axis by axis through logs
  {
    const double logMean =
      (std::log(grid.spacing[0]) + std::log(grid.spacing[1]) + std::log(grid.spacing[2])) / 3;
    for (int a = 0; a < 3; ++a)
    {
      scaled.spacing[a] = std::exp(std::log(grid.spacing[a]) - logMean);
    }
  }
  return scaled;
}

InterestPoints findInterestPoints(const float* opacity, const ImageGrid& worldGrid,
  const BestViewpointOptions& options, BestViewpointResult& result)
{
  const ImageGrid grid = unitFreeGrid(worldGrid); // positions come from the caller's grid
  std::string warning;
  result.deviceUsed = resolveDevice(options.device, &warning);
  if (!warning.empty())
  {
    result.warnings.push_back(warning);
  }
  const int N = options.numberOfInterestPoints;
  const bool partial = isPartialBlock(options.piece, grid);
  std::vector<float> response;
#ifdef MCV_HAS_CUDA
  // A single slice is tiny and takes the 2D form: the CPU handles it.
  if (result.deviceUsed == Device::GPU && grid.extendedAxes() == 2)
  {
    result.deviceUsed = Device::CPU;
  }
  if (result.deviceUsed == Device::GPU)
  {
    std::string error;
    const auto start = Clock::now();
    if (!partial)
    {
      InterestPoints points;
      cuda::GpuStageTimings gpu;
      if (cuda::harrisTopN(opacity, grid, options.harris, N, points, &error, &gpu))
      {
        result.timings.harrisMs = gpu.uploadMs + gpu.harrisMs;
        result.timings.selectMs = gpu.selectMs + gpu.downloadMs;
        return points;
      }
    }
    else
    {
      // The owned voxels are a sub-box: the response comes back and is selected here.
      response.resize(grid.voxelCount());
      if (cuda::harrisResponse(opacity, grid, options.harris, response.data(), &error))
      {
        result.timings.harrisMs = millisecondsSince(start);
      }
      else
      {
        response.clear();
      }
    }
    if (!error.empty())
    {
      result.warnings.push_back("GPU path failed (" + error + "); running on the CPU.");
      result.deviceUsed = Device::CPU;
    }
  }
#endif
  InterestPoints points;
  if (response.empty())
  {
    // The CPU selects while it computes, tile by tile (no response volume is stored): the
    // selection's time is inside harrisMs, and selectMs stays 0.
    const auto start = Clock::now();
    VoxelBox owned;
    owned.lo = options.piece.ownedLo;
    owned.hi = options.piece.ownedHi;
    points = computeHarrisTopNCPU(opacity, grid, options.harris, N, partial ? &owned : nullptr);
    result.timings.harrisMs = millisecondsSince(start);
    report(options, 0.7);
  }
  else
  {
    report(options, 0.7);
    const auto start = Clock::now();
    keepOwnedResponses(options.piece, grid, response.data());
    points = selectTopResponsesCPU(response.data(), response.size(), N);
    result.timings.selectMs = millisecondsSince(start);
  }
  if (partial)
  {
    for (std::int64_t& index : points.indices)
    {
      index = options.piece.globalIndex(index, grid);
    }
  }
  return points;
}

// The whole volume's grid, from a block's grid and where the block lies in it.
ImageGrid wholeGrid(const ImageGrid& block, const GridPiece& piece)
{
  ImageGrid whole = block;
  if (piece.wholeDims[0] > 0)
  {
    whole.dims = piece.wholeDims;
    for (int a = 0; a < 3; ++a)
    {
      whole.origin[a] = block.origin[a] - piece.offset[a] * block.spacing[a];
    }
  }
  return whole;
}

// Every process's top-N -> the global top-N, the same on every process.
InterestPoints mergeAcrossProcesses(
  const InterestPoints& local, const Communicator& comm, int N)
{
  InterestPoints all;
  all.indices = allGatherValues(comm, local.indices);
  all.scores = allGatherValues(comm, local.scores);
  return mergeTopResponses(all, N);
}

void harrisPCA(const float* opacity, const ImageGrid& grid, const BestViewpointOptions& options,
  BestViewpointResult& result)
{
  result.points = findInterestPoints(opacity, grid, options, result);
  if (isDistributed(options.communicator))
  {
    const auto start = Clock::now();
    result.points =
      mergeAcrossProcesses(result.points, *options.communicator, options.numberOfInterestPoints);
    result.timings.selectMs += millisecondsSince(start);
  }
  report(options, 0.9);

  const auto start = Clock::now();
  result.pointPositions = worldPositions(result.points, wholeGrid(grid, options.piece));
  const std::size_t found = result.points.size();
  // Whether the opacity varies at all tells the two reasons for no interest point apart.
  const std::size_t voxels = grid.voxelCount();
  const bool constant = voxels == 0 ||
    std::all_of(opacity, opacity + voxels, [first = opacity[0]](float v) { return v == first; });
  const bool allConstant = allTrue(options.communicator, constant);
  if (found == 0 && allConstant)
  {
    result.warnings.push_back("No interest points: the opacity volume is constant (empty or "
                              "flat everywhere); no view direction.");
  }
  else if (found == 0)
  {
    std::ostringstream msg;
    msg << "No interest points: no voxel has a positive Harris response with KernelWidth "
        << options.harris.kernelWidth << ", GaussianSigma " << options.harris.sigma
        << " and HarrisK " << options.harris.k
        << " (the opacity does vary); try the defaults (5, 1.5, 0.004): a wider kernel or "
           "sigma, or a smaller HarrisK. No view direction.";
    result.warnings.push_back(msg.str());
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

// The argument checks of computeBestViewpoint; "" when the arguments are usable.
std::string checkArguments(
  const float* opacity, const ImageGrid& grid, const BestViewpointOptions& options)
{
  if (opacity == nullptr || grid.voxelCount() == 0)
  {
    return "the input volume is empty (no voxels)";
  }
  if (!grid.spacingProblem().empty())
  {
    return grid.spacingProblem();
  }
  if (wholeGrid(grid, options.piece).extendedAxes() < 2)
  {
    return "the input has fewer than two axes with more than one voxel: a line or a "
           "point has no view direction";
  }
  if (options.numberOfInterestPoints <= 0)
  {
    return "NumberOfInterestPoints must be positive";
  }
  if (isPartialBlock(options.piece, grid) && options.method != ViewMethod::HarrisPCA)
  {
    return "only the HarrisPCA method runs on a volume split over processes (the baselines "
           "need the whole volume on each)";
  }
  return checkHarrisParameters(options.harris);
}

} // namespace

BestViewpointResult computeBestViewpoint(
  const float* opacity, const ImageGrid& grid, const BestViewpointOptions& options)
{
  BestViewpointResult result;
  const auto start = Clock::now();
  // Split over processes, every process takes the same branch: one with bad arguments
  // stops all of them (the others would wait in the top-N exchange).
  result.error = checkArguments(opacity, grid, options);
  if (!allTrue(options.communicator, result.error.empty()))
  {
    if (result.error.empty())
    {
      result.error = "another process of the parallel run reported an error";
    }
    return result;
  }
  if (wholeGrid(grid, options.piece).extendedAxes() == 2)
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
