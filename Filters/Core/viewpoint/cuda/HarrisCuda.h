// GPU path of the best-viewpoint pipeline: Harris response and top-N selection on the
// device. Plain C++ interface (no CUDA types), so the core can call it; built only when
// MCV_ENABLE_CUDA is on (the core then defines MCV_HAS_CUDA).
#pragma once

#include "HarrisResponse.h"
#include "ImageGrid.h"
#include "TopResponses.h"

#include <cstddef>
#include <string>

namespace mcv
{
namespace cuda
{

struct GpuStageTimings
{
  double uploadMs = 0, harrisMs = 0, selectMs = 0, downloadMs = 0;
  int slabs = 0; // z-slabs streamed through the device (0: the whole volume was resident)
};

// Host volume in, top-N interest points out (same contract as computeHarrisResponseCPU +
// selectTopResponsesCPU). Returns false with `error` set on any CUDA failure, so the
// caller can fall back to the CPU; `out` is then empty. A 3D volume whose whole-volume
// buffers (volume + scores) exceed the device budget goes through the GPU in z-slabs with
// halo slices and a running top-N (HarrisSlabStream.h): the same points.
bool harrisTopN(const float* hostOpacity, const ImageGrid& grid, const HarrisParameters& params,
  int N, InterestPoints& out, std::string* error, GpuStageTimings* timings = nullptr);

// The whole response volume back to the host (tests compare it with the CPU path).
bool harrisResponse(const float* hostOpacity, const ImageGrid& grid,
  const HarrisParameters& params, float* hostResponse, std::string* error);

// Device memory harrisTopN may use, in bytes; 0 (the default): the free device memory
// minus a margin, at each call. Tests set a small one to force the slab path.
void setHarrisDeviceBudget(std::size_t bytes);

// Frees the device buffers that harrisTopN/harrisResponse keep between calls (they are
// allocated again by the next call). A failed call does this itself.
void releaseHarrisCache();

} // namespace cuda
} // namespace mcv
