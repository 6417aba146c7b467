// The slabs of a volume streamed through the device for the fused reduction's passes:
// per slab of z slices, the host converts its channels (with one ghost slice each
// side) into pinned staging, they go up, the slab's raw features are computed there by the
// whole-volume kernel (FeatureKernels.cuh, bit-equal to the CPU) and, when asked, normalised
// as applyNormalizationCPU rounds; then the pass queues its own kernels and downloads on the
// slab's stream. Two slots (streams, buffers) alternate, so the host's conversion of one slab
// overlaps the other's transfers and kernels. The slab is the thickest whose buffers fit the
// device memory the pass may use, so the volume may be far larger than the device.
//
// The passes (FusedPlacementCuda.cu: placement; FusedPassesCuda.cu: statistics, column sums,
// strata) differ only in what they add per slab; the stream is theirs to share.
#pragma once

#include "FusedPlacementCuda.h"
#include "NonCopyable.h"

#include <cuda_runtime.h>

#include <chrono>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

namespace mcv
{
namespace cuda
{

constexpr int kSlabSlots = 2; // slabs in flight: one per stream

// What a pass adds to the stream's own buffers, so the slab thickness accounts for it.
struct SlabPassBytes
{
  std::size_t fixedDevice = 0;   // held once (references, statistics, ...)
  std::size_t perRowDevice = 0;  // per slot, per row of a slab
  std::function<std::size_t(std::size_t slabRows)> perSlotDevice; // optional: per slot, for a slab of slabRows
  std::size_t perRowPinned = 0;  // per slot, per row: the pass's pinned host buffer
};

struct SlabStreamSetup
{
  ImageGrid grid;
  int channels = 0;
  FeatureSelection selection;
  int cols = 0;                      // channels * selection.perChannel()
  std::vector<double> offset, scale; // empty: the raw features are left as they are
  std::size_t deviceBytes = 0;       // 0: the free memory less a margin (1/16 of the card, >= 512 MiB)
  std::size_t maxSlabVoxels = kMaxSlabVoxels;
  SlabPassBytes pass;
  // Optional: the whole volume's channels on the device (FusedPlacementCuda.h). Not yet
  // filled: the stream uploads into it (each slice once) instead of per-slab buffers; filled:
  // nothing is converted or uploaded.
  ResidentChannels* resident = nullptr;
};

// The stream's part of a pass's setup (FusedPlacementSetup, FusedPassSetup: the same names).
template <class PassSetup>
SlabStreamSetup slabStreamSetup(const PassSetup& s)
{
  SlabStreamSetup st;
  st.grid = s.grid;
  st.channels = s.channels;
  st.selection = s.selection;
  st.cols = s.cols;
  st.offset = s.offset;
  st.scale = s.scale;
  st.deviceBytes = s.deviceBytes;
  st.resident = s.resident;
  return st;
}

// One slab in its slot, as the pass's callbacks see it.
struct Slab
{
  int slot = 0;
  cudaStream_t stream = nullptr;
  int z0 = 0, z1 = 0;
  std::size_t firstRow = 0, rows = 0; // rows of the slab (its slices [z0, z1)), voxels of the grid
  float* features = nullptr;          // device, rows x cols
  const float* channels = nullptr;    // device, C planes of `plane` floats (with ghost slices)
  std::size_t plane = 0;
  std::int64_t vBegin = 0;            // the slab's first row within a plane
  std::vector<bool> nonFinite;        // per channel: a non-finite value in the slab or its ghosts
  bool anyNonFinite = false;
  unsigned char* pinned = nullptr;    // the pass's pinned buffer of this slot (perRowPinned x rows)
};

struct SlabStreamStats
{
  int slabSlices = 0;
  std::size_t slabs = 0, bytesToDevice = 0, bytesFromDevice = 0, deviceBytes = 0, deviceUsedPeak = 0, pinnedBytes = 0;
  double setupMs = 0, fillMs = 0, waitMs = 0, totalMs = 0; // fill: host conversion; wait: for the device
};

class SlabStream : NonCopyable
{
public:
  SlabStream() = default;
  ~SlabStream();

  // The device bytes of the stream and the pass for slabs of `slices` slices.
  static std::size_t bytesFor(const SlabStreamSetup& setup, int slices);
  // Chooses the slab thickness and allocates the slots; false with `error` when not even a
  // slab of one slice fits.
  bool open(const SlabStreamSetup& setup, std::string* error);
  int slabSlices() const { return slices_; }
  std::size_t slabRows() const; // the rows of the thickest slab
  // The slots the slabs use: kSlabSlots, or fewer when the volume has fewer slabs (a volume
  // of one slab allocates and pins the buffers of one slot only).
  int slotsUsed() const { return slotsUsed_; }

  // Every slab in order: `fill` converts channel c's voxels into pinned floats (returns the
  // non-finite ones); `launch` (host, after the slab's features are queued) queues the
  // pass's kernels and downloads on slab.stream; `done` (host) runs when the slab's stream
  // has finished, in slab order. Either callback returning false stops the stream.
  using Launch = std::function<bool(Slab&)>;
  using Done = std::function<bool(const Slab&)>;
  bool run(const FusedChannelFill& fill, const Launch& launch, const Done& done, std::string* error);

  SlabStreamStats& stats() { return stats_; }

private:
  void release();
  // Puts slab s's channels on the device (or finds them there) and sets s.channels, s.plane
  // and the non-finite flags.
  bool channelsUp(Slab& s, int g0, int g1, std::size_t withGhosts, const FusedChannelFill& fill, std::string* error);

  SlabStreamSetup setup_;
  int slices_ = 1;
  int slotsUsed_ = kSlabSlots;
  std::size_t plane_ = 0;
  cudaStream_t streams_[kSlabSlots] = { nullptr, nullptr };
  float* channels_[kSlabSlots] = { nullptr, nullptr };      // device, C x plane (not resident)
  cudaEvent_t uploaded_[kSlabSlots] = { nullptr, nullptr }; // filling a resident copy: a slab's slices are up
  float* features_[kSlabSlots] = { nullptr, nullptr };      // device, slab rows x F
  float* stageIn_[kSlabSlots] = { nullptr, nullptr };       // pinned host, C x plane
  unsigned char* passPinned_[kSlabSlots] = { nullptr, nullptr };
  // Per slot: the capacity of each pinned buffer (a buffer taken from the resident cache may
  // be larger than asked for, and goes back with its whole size for a later, larger need).
  std::size_t stageInBytes_[kSlabSlots] = { 0, 0 }, passPinnedBytes_[kSlabSlots] = { 0, 0 };
  double* columnParams_ = nullptr;                          // device, offset then scale
  SlabStreamStats stats_;
  int uploadedEnd_ = 0;                     // filling the resident copy: slices [0, uploadedEnd_) are up
  std::vector<bool> residentNonFinite_;     // and their non-finite flags per channel
  std::chrono::steady_clock::time_point opened_;
};

// Grid-stride launch size for `work` items of 256 threads.
int slabBlocksFor(std::int64_t work);

} // namespace cuda
} // namespace mcv
