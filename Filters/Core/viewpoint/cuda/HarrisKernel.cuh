// The fused 3D Harris kernel (gradient, six products, separable Gaussian, response, and
// optionally the level-1 histogram of the top-N radix select and the row maxima that its
// compaction reads) and its launcher. The default kernel skips empty space exactly: slices
// whose input tile is all zero are not computed (see harrisKernel in HarrisKernel.cu).
//
// Each block owns a 32x16 xy tile of outputs and a run of z slices. It streams along z:
// the input slices sit in a ring of three shared-memory tiles (with a 1+radius halo),
// the six gradient products of one slice are formed in shared memory, smoothed along x
// (float4, 4 outputs per task) and y (2 rows per thread), and each thread keeps the last
// 2*radius+1 xy-smoothed slices of its two voxels in registers for the z pass. Borders are
// replicated exactly as on the CPU: gradients read clamped neighbours, and the Gaussian
// reads the product field at clamped positions (a product slice/column outside the grid
// is the one of the nearest border voxel).
#pragma once

#include <cuda_runtime.h>

#include <cstdint>

namespace mcv
{
namespace cuda
{
namespace detail
{

constexpr int kHarrisTileX = 32;
constexpr int kHarrisTileY = 16;
constexpr int kHarrisThreads = 256; // 32 x 8, each thread owns two rows of the tile
constexpr int kHarrisMaxRadius = 3; // kernel widths 1, 3, 5, 7 run on the GPU
constexpr int kLevel1Bins = 2048;   // top 11 bits of a positive float
// Kernel variants 0-7 (bit 0: z loop unrolled into a register ring; bit 1: 3 blocks per SM;
// bit 2: product positions from a per-block table) and 8 (variant 5's form with two input
// slices per round of barriers); all nine are built for width 5, the default variant for
// the other widths.
constexpr int kHarrisVariants = 9;
constexpr int kHarrisPairsVariant = 8;
constexpr int kHarrisDefaultVariant = 5; // the fastest measured (mcvBenchmarkGPU --variants)

struct HarrisKernelArgs
{
  int nx = 0, ny = 0, nz = 0; // the grid as the kernel sees it (a slice: nz == 1)
  int zChunk = 0;             // output slices per block
  // Output slices [zOutBegin, zOutEnd) (zOutEnd <= 0: all nz); response holds only those,
  // slice z at (z - zOutBegin) * nx * ny. A z-slab with halo slices computes its owned
  // slices this way: the halo is read (and clamped at the slab's ends) but not output.
  int zOutBegin = 0, zOutEnd = 0;
  float scaleX = 0, scaleY = 0, scaleZ = 0; // 0.5 / spacing
  float k = 0;
  int planar = 0; // 1: 2D form det2 - k tr2^2 on the x,y block
  float taps[2 * kHarrisMaxRadius + 1] = {};
  float* response = nullptr;
  unsigned long long* hist = nullptr; // level-1 histogram (kLevel1Bins) or null
  int histMode = 1; // 0: warp-aggregated shared atomics (__match_any_sync); 1: plain (faster)
  // Row maxima for the top-N compaction (or null): for output rows 2 p, 2 p + 1 of slice z
  // and their kHarrisTileX-wide segments t (x in [32 t, 32 t + 32)), the largest
  // candidate's bit pattern (R > 0 and finite; 0: none) at
  // ((z - zOutBegin) * ((ny + 1) / 2) + p) * tilesX + t.
  unsigned* rowMax = nullptr;
  // Pruning for the top N (HarrisBound.cuh), or null: a block computes (and writes) only
  // when gate[0] <= blockBound[its id] and not gate[1] <= it (a NaN gate[1]: no upper
  // limit); id = (blockIdx.z * tilesY + blockIdx.y) * tilesX + blockIdx.x. Variants 0-7.
  const float* blockBound = nullptr;
  const float* gate = nullptr;
};

// Launches the kernel for input type T (float or uint8) and radius `radius` (0..3);
// zChunk <= 0 picks one from the occupancy; variant < 0 the default. Returns the launch
// error; *usedZChunk gets the chunk (may be null).
template <typename T>
cudaError_t launchHarris(const T* input, HarrisKernelArgs args, int radius, int zChunk,
  cudaStream_t stream, int* usedZChunk, int variant = -1);

} // namespace detail
} // namespace cuda
} // namespace mcv
