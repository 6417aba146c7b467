// The Harris kernel's arguments for a grid and parameters: shared by the whole-volume
// pipeline (HarrisPipeline) and the z-slab stream (HarrisSlabStream), so both run the
// kernel on exactly the same terms.
#pragma once

#include "HarrisCuda.h"
#include "HarrisKernel.cuh"

namespace mcv
{
namespace cuda
{
namespace detail
{

// Grid shape (a single slice becomes an x,y image with nz = 1), 0.5 / spacing, k, taps.
// The caller sets response, hist and histMode. Parameters must pass gpuUnsupportedReason.
HarrisKernelArgs harrisKernelArgs(const ImageGrid& grid, const HarrisParameters& params);

} // namespace detail
} // namespace cuda
} // namespace mcv
