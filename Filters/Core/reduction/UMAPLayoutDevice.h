// Where UMAP's layout runs: the CPU layout (UMAPLayout.h) or its CUDA path
// (cuda/UMAPLayoutCuda.h, which says how its result differs), chosen by a resolved Device
// (resolveDevice in Device.h). A GPU that fails (out of memory, lost context, ...) leaves
// the start untouched and the CPU layout runs instead, with one warning.
#pragma once

#include "Device.h"
#include "UMAPLayout.h"

#include <string>
#include <vector>

namespace mcv
{

// Y: the start, replaced by the layout. Returns where the layout ran; warnings receives
// one line when the GPU was asked for and the CPU ran. gpuRounds: parallel rounds per epoch
// of the GPU layout (cuda::LayoutProblem::rounds), 0 for its default.
Device optimizeLayoutOn(Device device, const FuzzyGraph& graph, const LayoutOptions& options, RowMatrixF& Y,
  std::vector<std::string>& warnings, int gpuRounds = 0);

// The GPU layout alone (no fallback): false with `error` set when it did not run (no CUDA in
// this build, or a CUDA failure). For the tests and benchmarks that compare it with the CPU.
bool optimizeLayoutOnGpu(const FuzzyGraph& graph, const LayoutOptions& options, RowMatrixF& Y, std::string* error,
  int gpuRounds = 0);

} // namespace mcv
