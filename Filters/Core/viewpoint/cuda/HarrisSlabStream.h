// Best-viewpoint Harris + top-N for volumes larger than the device memory the pipeline may
// use: the volume stays on the host and goes through the GPU in z-slabs. Each slab carries
// halo slices (1 for the central-difference gradient + KernelWidth/2 for the Gaussian), so
// the response of its owned slices is bit-for-bit the whole-volume kernel's; the slab's
// top-N (same selector, same order: score descending, then linear index ascending) is
// merged into a running top-N with mergeTopResponses. That order is total, and every point
// of the global top-N is in its own slab's top-N, so the result is exactly the whole-volume
// GPU result.
//
// Transfers overlap compute: slabs alternate between two device slab buffers; while the
// kernel runs on slab i, the host copies slab i+1 piece by piece into a small ring of
// pinned staging buffers (256 MiB) and a second stream uploads each piece as soon as it is
// there. Slabs hold at most 512 MiB of input, so the first, unoverlapped upload is short.
//
// Plain C++ (no CUDA types). Not thread-safe: one caller at a time per instance.
#pragma once

#include "HarrisCuda.h"

#include <cstddef>
#include <cstdint>
#include <memory>
#include <string>

namespace mcv
{
namespace cuda
{

// How a volume is cut into z-slabs under a device-memory budget.
struct SlabPlan
{
  int halo = 0;         // slices read on each side of a slab's owned slices
  int ownedSlices = 0;  // owned slices per slab (the last one may have fewer)
  int slabs = 0;        // number of slabs
  std::size_t deviceBytes = 0; // two input slab buffers + the owned scores + selection
};

// Device bytes the selection needs besides the score buffer (CUB temporaries, the compacted
// list of the fast path, the N results), kept free by the plans.
constexpr std::size_t kSelectionReserveBytes = std::size_t(64) << 20;

// Device bytes the whole-volume pipeline needs for this grid: volume + scores + selection.
std::size_t wholeVolumeDeviceBytes(const ImageGrid& grid, int bytesPerValue);

// The largest owned slab height whose buffers fit `budgetBytes` (capped at the grid's
// slices; `maxOwnedSlices` > 0 caps it further). ownedSlices == 0 when not even one owned
// slice fits. Needs a 3D grid (all three axes with more than one voxel).
SlabPlan planSlabs(const ImageGrid& grid, int bytesPerValue, int kernelWidth,
  std::size_t budgetBytes, int maxOwnedSlices = 0);

// The device memory the best-viewpoint path may use: `limitBytes` when non-zero, else the
// free device memory plus `alreadyHeldBytes` (buffers this process would give back first)
// minus a margin (the larger of 512 MiB and 5% of the device). 0 on a CUDA error.
std::size_t deviceBudgetBytes(std::size_t limitBytes, std::size_t alreadyHeldBytes = 0);

struct SlabTimings
{
  int slabs = 0, ownedSlices = 0, halo = 0;
  double stagingMs = 0;  // host: copies into the pinned staging ring (sum)
  double uploadMs = 0;   // per slab, first piece queued to last piece landed on the copy
                         // stream (sum, CUDA events; includes waits for the host copies)
  double harrisMs = 0;   // Harris kernels (sum, CUDA events)
  double selectMs = 0;   // per-slab selections incl. the N points' download (sum)
  double mergeMs = 0;    // host: running top-N merges (sum)
  double totalMs = 0;    // host clock around the whole call
  std::size_t deviceBytes = 0, pinnedBytes = 0;
};

class HarrisSlabStream
{
public:
  HarrisSlabStream();
  ~HarrisSlabStream();
  HarrisSlabStream(const HarrisSlabStream&) = delete;
  HarrisSlabStream& operator=(const HarrisSlabStream&) = delete;

  // Top-N of a host volume (x fastest, grid.voxelCount() values; a 3D grid), slab by slab
  // under the budget (0: deviceBudgetBytes(0)). The points carry whole-volume indices.
  bool topN(const float* host, const ImageGrid& grid, const HarrisParameters& params, int N,
    InterestPoints& out, std::string* error, SlabTimings* timings = nullptr);
  bool topN(const std::uint8_t* host, const ImageGrid& grid, const HarrisParameters& params,
    int N, InterestPoints& out, std::string* error, SlabTimings* timings = nullptr);

  // Device budget in bytes (0: the free memory minus a margin, at each call).
  void setBudgetBytes(std::size_t bytes);
  // Test hook: owned slices per slab at most this (0: as many as the budget allows).
  void setMaxOwnedSlices(int slices);

  // Device bytes of the slab and score buffers it holds now.
  std::size_t deviceBytesHeld() const;
  // Frees the device and pinned buffers (allocated again on the next call).
  void release();

private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

} // namespace cuda
} // namespace mcv
