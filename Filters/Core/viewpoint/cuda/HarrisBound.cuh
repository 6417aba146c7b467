// Exact pruning of the Harris kernel for the top-N (HarrisPipeline::topN).
//
// The structure tensor M is positive semi-definite, so det M <= (tr M / 3)^3 and
//   R = det M - k tr M^3 <= tr M^3 (1/27 - k).
// tr M is the Gaussian-smoothed |g|^2: one smoothed channel instead of six. A block of the
// Harris kernel whose largest bound is below a lower bound of the N-th largest response
// holds none of the top N, and is not computed. The pipeline:
//   1. traceBound: per (xy tile, input slice) the largest x,y-smoothed |g|^2 (one channel;
//      a NaN counts as +Inf); the trace of an output slice z, the z pass's weighted mean
//      of slices z - R .. z + R, is at most their largest;
//   2. blockBounds: per block of the Harris launch (tile x z chunk), X, the largest of
//      those over its slices and R more on either side, and the bound X^3 (1/27 - k) with
//      a margin over float rounding;
//   3. phaseGate: theta, so that about `wanted` blocks have a bound >= theta (the ones
//      most likely to hold the top N); the Harris kernel computes those first (phase A,
//      gate {theta, NaN}), adding to the level-1 histogram;
//   4. tauGate: from that histogram, tau, the lower edge of the level-1 bin of phase A's
//      N-th largest candidate (<= the N-th largest response of the volume; 0 when phase A
//      has fewer than N candidates); the Harris kernel then computes the blocks with
//      tau <= bound < theta (phase B, gate {tau, theta}).
// Every voxel with R >= the N-th largest response lies in a computed block (its bound is
// >= R >= tau), so the selection over the computed blocks gives the top N of the whole
// volume, bit for bit. The blocks left out keep no responses (the selection's row maxima
// are cleared first; the slow selection path, which reads every score, is not taken).
#pragma once

#include "HarrisKernel.cuh"

#include <cuda_runtime.h>

namespace mcv
{
namespace cuda
{
namespace detail
{

// Step 1. sliceMax: tilesX * tilesY * nz unsigned (float bits of X >= 0, or of +Inf),
// cleared to 0 by the caller, at (z * tilesY + ty) * tilesX + tx. Radius 0..3; not for
// planar grids (the 2D response has another bound).
template <typename T>
cudaError_t launchTraceBound(
  const T* input, const HarrisKernelArgs& args, int radius, unsigned* sliceMax, cudaStream_t stream);

// Step 2. blockBound: one float per block of a Harris launch over all nz slices with
// z chunk zChunk, indexed as the kernel's (blockIdx.z * tilesY + blockIdx.y) * tilesX +
// blockIdx.x.
cudaError_t launchBlockBounds(const unsigned* sliceMax, int tilesX, int tilesY, int nz,
  int zChunk, int radius, float k, float* blockBound, cudaStream_t stream);

// Step 3. gateA = {theta, NaN}; gateB[1] = theta (the blocks phase A computed).
cudaError_t launchPhaseGate(
  const float* blockBound, int blocks, int wanted, float* gateA, float* gateB, cudaStream_t stream);

// Step 4. gateB[0] = tau from the level-1 histogram (kLevel1Bins counts) after phase A.
cudaError_t launchTauGate(const unsigned long long* hist, int N, float* gateB, cudaStream_t stream);

} // namespace detail
} // namespace cuda
} // namespace mcv
