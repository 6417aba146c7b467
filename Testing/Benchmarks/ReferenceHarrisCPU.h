// The CPU Harris response as the suite computed it before the tiled, vectorised path of
// Filters/Core/viewpoint/HarrisResponse.cpp: whole z-slices smoothed along x and y into a
// ring of KernelWidth slices (24 bytes per voxel of the slice per slot), the z pass and the
// response per row, plain float loops (no FMA), OpenMP over runs of z; the response volume
// then searched for the top-N by a priority queue per thread. Kept only as the benchmark's
// in-run baseline (mcvBenchmarkCPU prints the ratio to it).
#pragma once

#include "HarrisResponse.h"

namespace mcv
{
namespace benchmark
{

void referenceHarrisResponseCPU(
  const float* opacity, const ImageGrid& grid, const HarrisParameters& params, float* response);

// The former selectTopResponsesCPU (a std::priority_queue per thread): the same answer.
InterestPoints referenceSelectTopResponsesCPU(const float* response, std::size_t count, int N);

} // namespace benchmark
} // namespace mcv
