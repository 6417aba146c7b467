// Device-resident best-viewpoint GPU pipeline: keeps the volume, the score volume and the
// selection buffers on the GPU between calls, so that repeated runs (a transfer function
// being edited; the benchmark) pay no allocation and, with the volume already uploaded,
// no host-to-device copy. Plain C++ (no CUDA types): the GPU tests and the benchmark use it
// directly; HarrisCuda.h's functions are built on one shared instance of it.
//
// Not thread-safe: one caller at a time per instance. Uses the current CUDA device.
#pragma once

#include "HarrisCuda.h"
#include "NonCopyable.h"

#include <cstddef>
#include <cstdint>
#include <memory>
#include <string>

namespace mcv
{
namespace cuda
{

class HarrisPipeline : NonCopyable
{
public:
  HarrisPipeline();
  ~HarrisPipeline();

  // Copies a volume (x fastest, grid.voxelCount() values) to the device; the copy time is
  // kept as lastUploadMs(). uint8 volumes (0..255) rank exactly like value/255 in float,
  // up to rounding: the response scales by 255^6.
  bool uploadVolume(const float* host, const ImageGrid& grid, std::string* error);
  bool uploadVolume(const std::uint8_t* host, const ImageGrid& grid, std::string* error);

  // Harris response + top-N on the uploaded volume. timings (optional): harrisMs, selectMs,
  // downloadMs measured with CUDA events on the GPU timeline, uploadMs = lastUploadMs().
  bool topN(const HarrisParameters& params, int N, InterestPoints& out, std::string* error,
    GpuStageTimings* timings = nullptr);

  // Harris response of the uploaded volume, copied to `hostResponse` (voxelCount floats).
  bool response(const HarrisParameters& params, float* hostResponse, std::string* error);

  // Selection alone, from a host score volume (tests of the radix select: ties, NaN, ...).
  bool selectFromScores(const float* hostScores, std::size_t count, int N, InterestPoints& out,
    std::string* error);

  // Output slices per block of the Harris kernel; 0 (default) picks it from the occupancy.
  void setZChunk(int zChunk);
  // Harris kernel variant for width 5 (benchmark/tests): -1 default (5), 0..7 (bit 0: z
  // loop unrolled into a register ring, bit 1: 3 blocks per SM, bit 2: product positions
  // from a per-block table and two barriers per slice); histogram mode 0: warp-aggregated
  // shared atomics, 1 (default): plain shared atomics.
  void setKernelVariant(int variant, int histogramMode);
  // Variants built for width 5 (0 .. count - 1).
  static int kernelVariantCount();
  int lastZChunk() const;
  double lastUploadMs() const;

  // The last selection's compacted list (candidates in or above the N-th score's level-1
  // bin) and whether it needed the slow path (list longer than the fast capacity).
  long long lastListSize() const;
  bool lastSelectUsedSlowPath() const;
  // Test hook: always take the slow selection path.
  void setForceSlowSelect(bool force);

  // Harris kernel alone on the uploaded volume (benchmark attribution), in ms (CUDA events).
  bool timeHarrisKernel(const HarrisParameters& params, bool withHistogram, double* ms,
    std::string* error);

  // Exact pruning of topN (HarrisBound.cuh): an upper bound of the response per block of
  // the Harris kernel (tile x zChunk slices); the blocks of the largest bounds (1 /
  // phaseShare of them) are computed first, then those whose bound reaches the N-th largest
  // response found there. The same points as without it, bit for bit. Automatic (the
  // default) prunes volumes of at least pruneMinVoxels voxels, where it was measured
  // faster than the whole volume (docs/benchmarks.md, section 2).
  enum class Pruning
  {
    Automatic,
    Always,
    Never
  };
  static constexpr std::size_t pruneMinVoxels = std::size_t(1) << 25;
  void setPruning(Pruning mode, int zChunk = 16, int phaseShare = 64);
  // The share of the Harris kernel's blocks the last topN computed (1 when not pruned;
  // reads the bounds back: for the benchmark, not for timing).
  double lastComputedBlockShare();

  // Bytes of the volume and score buffers it holds now (the selection's are small).
  std::size_t deviceBytesHeld() const;

  // Frees every device buffer (they are allocated again on the next call).
  void release();

private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

// Parameters the GPU path cannot run (the caller then uses the CPU), or "" when it can.
const char* gpuUnsupportedReason(const ImageGrid& grid, const HarrisParameters& params);

} // namespace cuda
} // namespace mcv
