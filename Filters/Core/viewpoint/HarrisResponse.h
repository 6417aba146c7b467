// 3D Harris interest-point response (Laptev-Lindeberg form) on an opacity volume.
//
//   g = grad I            central differences in world units, border voxels replicated
//   M = G_sigma * (g g^T)  separable Gaussian of width KernelWidth (voxels), border replicated
//   R = det(M) - k tr(M)^3
//
// For a single slice (one axis of size 1) the 2D form R = det(M2) - k tr(M2)^2 on the two
// in-plane axes is used, since the 3D determinant of a slice is always zero.
//
// The CPU path rounds as the CUDA kernel does (cuda/HarrisKernel.cu): each Gaussian pass
// is a chain of fused multiply-adds from 0 in tap order (x, then y, then z), the gradient
// products and the response are formed from the same expressions.
#pragma once

#include "ImageGrid.h"
#include "TopResponses.h"

#include <array>

namespace mcv
{

struct HarrisParameters
{
  double sigma = 1.5;  // Gaussian standard deviation, in voxels
  int kernelWidth = 5; // taps per axis (odd, >= 1)
  double k = 0.004;    // sensitivity constant
};

// Normalised 1D Gaussian taps (size kernelWidth, sums to 1). Shared by the CPU and GPU paths.
void gaussianTaps(const HarrisParameters& params, float* taps);

// Returns an empty string when the parameters are usable, else what is wrong.
const char* checkHarrisParameters(const HarrisParameters& params);

// The CPU path's instructions: AVX2 with FMA where the CPU has them, else plain floats
// (std::fma); Portable forces the latter. Both give the same bits (a test compares them).
enum class HarrisCpuKernel
{
  Auto,
  Portable
};

// CPU (OpenMP) response for every voxel. `opacity` and `response` hold grid.voxelCount()
// floats, x fastest. Requires grid.extendedAxes() >= 2 and valid parameters.
void computeHarrisResponseCPU(const float* opacity, const ImageGrid& grid,
  const HarrisParameters& params, float* response, HarrisCpuKernel kernel = HarrisCpuKernel::Auto);

// Voxels that may become interest points: the box [lo, hi] of block indices (inclusive).
struct VoxelBox
{
  std::array<int, 3> lo{ 0, 0, 0 };
  std::array<int, 3> hi{ -1, -1, -1 };
};

// CPU (OpenMP) top-N of the response, without storing it: the same points, in the same
// order, as computeHarrisResponseCPU followed by selectTopResponsesCPU (the response of
// each tile is offered to a per-thread TopResponseCollector while it is in cache).
// `candidates` (optional) limits the points to a box, e.g. the voxels a process owns; its
// responses are still computed from the whole block. Same requirements as above.
InterestPoints computeHarrisTopNCPU(const float* opacity, const ImageGrid& grid,
  const HarrisParameters& params, int N, const VoxelBox* candidates = nullptr);

} // namespace mcv
