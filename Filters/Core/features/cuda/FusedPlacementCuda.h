// GPU path of the fused reduction: the features of a slab of z slices are
// computed on the device from its channels (uploaded with one ghost slice each side),
// normalised there with the statistics pass's offsets and scales, and placed there by the
// out-of-sample kernels (OutOfSampleCuda.h, PlacementOnDevice) against references uploaded
// once. Only channel slabs go up and coordinates come down: a volume far larger than the
// device runs slab by slab. Two streams and pinned staging buffers overlap the host's
// conversion of slab s + 1, the transfers and the kernels of slab s.
//
// Same function as the CPU path (FeatureBricks::block + placeOutOfSample): the feature
// kernel is the whole-volume one (FeatureKernels.cuh, bit-equal to the CPU) run on the slab
// with its ghost slices, the normalisation rounds like applyNormalizationCPU, and the
// placement picks the neighbours the CPU picks.
//
// Plain C++ interface (no CUDA types); built only with MCV_ENABLE_CUDA. Any CUDA failure
// (allocation included) returns false with `error`; rowsDone says how many rows are placed
// (whole slabs, in order), so the core places the rest on the CPU.
#pragma once

#include "cuda/OutOfSampleCuda.h"

#include "FeatureVectors.h"
#include "NonCopyable.h"

#include <cstddef>
#include <functional>
#include <string>
#include <utility>
#include <vector>

namespace mcv
{
namespace cuda
{

// The volume's channels (as float) kept on the device between the fused passes, when they
// fit in at most half the device memory the passes may use: the first pass fills it as it
// streams the slabs, the later ones compute their features from it instead of converting and
// uploading the channels again (FeatureBricks keeps one from its statistics pass to its
// placement). nonFinite: per channel, whether the volume holds a non-finite value (known
// once filled; the slabs then use the guarded feature kernel, which equals the other on
// finite data).
class ResidentChannels : NonCopyable
{
public:
  ResidentChannels() = default;
  ~ResidentChannels();

  // Reserves channels x voxels floats when they fit (see above; deviceBytes 0: the free
  // memory less a margin); false, holding nothing, when they do not or the allocation fails.
  bool reserveIfFits(int channels, std::size_t voxels, std::size_t deviceBytes);
  void release();
  float* data() const { return data_; }
  std::size_t voxels() const { return voxels_; }
  std::size_t bytes() const { return static_cast<std::size_t>(channels_) * voxels_ * sizeof(float); }

  bool filled = false;
  std::vector<bool> nonFinite;

  // Pinned host buffers the passes over this volume hand on to each other: pinning costs
  // about as much as the copy it serves (the 85 MB staging of the 7.1 M-voxel brain ~45 ms
  // on the H200 host), so the placement reuses the statistics pass's staging. takePinned:
  // the smallest kept buffer of at least `bytes` (it leaves the cache; *capacity: its whole
  // size, which the caller gives back with it), or null when none is (the caller pins one);
  // keepPinned: `p` (cudaMallocHost, `bytes` long) for a later pass. The strata pass's
  // 7 MB of strata thus borrow the statistics pass's 86 MB staging without shrinking it for
  // the placement's 85 MB of coordinates. The kept buffers are freed with the channels
  // (release, destructor).
  void* takePinned(std::size_t bytes, std::size_t* capacity);
  void keepPinned(void* p, std::size_t bytes);

private:
  void freePinned();

  float* data_ = nullptr;
  int channels_ = 0;
  std::size_t voxels_ = 0;
  std::vector<std::pair<void*, std::size_t>> pinned_;
};

// The device memory the fused passes may use: deviceBytes, or the free memory less a margin
// (1/16 of the card, at least 512 MiB); false with error when the card cannot be asked.
bool fusedDeviceBudget(std::size_t deviceBytes, std::size_t* budget, std::size_t* cardBytes, std::string* error);

struct FusedPlacementSetup
{
  ImageGrid grid; // the volume (or this process's block); rows are its voxels, x fastest
  int channels = 0;
  FeatureSelection selection;
  int cols = 0;                      // channels * selection.perChannel()
  std::vector<double> offset, scale; // per column, as applyNormalizationCPU takes them
  PlacementInput references;         // refX, refY, M, D, d, columns, neighbors, ...; dim = cols
  // Device memory the path may use; 0: the free memory less a margin (1/16 of the card, at
  // least 512 MiB). The slab is the thickest that fits (at most kMaxSlabVoxels voxels).
  std::size_t deviceBytes = 0;
  // A run of consecutive voxels with equal features (a uniform background) is placed once;
  // false places every voxel (the benchmark's baseline). Same coordinates either way.
  bool mergeEqualRows = true;
  // Optional: the channels already on the device (filled by an earlier pass), or to be kept.
  ResidentChannels* resident = nullptr;
  // Optional: takes each slab's coordinates (rows [firstRow, firstRow + rows), from the
  // pinned staging buffer) instead of the copy into `out`, which may then be null; the
  // float16 output rounds them there (FeatureBricks::placeOnDevice).
  std::function<void(std::size_t firstRow, std::size_t rows, const float* coordinates)> writeCoordinates;
  // Optional: takes each slab's distances to the model (one float per row, computed on the
  // device as ModelDistance.cpp does with modelRadius), from the pinned staging buffer.
  std::function<void(std::size_t firstRow, std::size_t rows, const float* distances)> writeDistances;
  double modelRadius = 0.0;
};

// Fills `values` with channel c's voxels [first, first + count) of the grid as float
// (what detail::channelToFloat gives); returns how many of them are not finite.
using FusedChannelFill = std::function<std::size_t(int c, std::size_t first, std::size_t count, float* values)>;

struct FusedPlacementStats
{
  int slabSlices = 0;
  std::size_t slabs = 0;
  std::size_t bytesToDevice = 0, bytesFromDevice = 0;
  std::size_t deviceBytes = 0;     // allocated by this path (references, slabs, scratch)
  std::size_t deviceUsedPeak = 0;  // the card's used memory at its highest (cudaMemGetInfo)
  std::size_t pinnedBytes = 0;     // host staging buffers
  std::size_t radiusScans = 0;
  double setupMs = 0, fillMs = 0, waitMs = 0, totalMs = 0; // fill: host conversion; wait: for the device
};

// The thickest slab: 8 M voxels keep the pinned staging buffers, allocated by every pass,
// small, so that allocating them is a small part of the placement's setup (the placement
// works 1 M rows at a time either way).
constexpr std::size_t kMaxSlabVoxels = std::size_t(8) << 20;

// The device bytes the path needs for slabs of `slices` z slices (so tests and callers can
// ask for a given slab thickness through deviceBytes).
std::size_t fusedPlacementBytes(const FusedPlacementSetup& setup, int slices);

// Places every voxel of setup.grid into out (voxels x d floats). progress: fraction of the
// rows placed, from the calling thread. rowsDone: see the header comment.
bool placeFused(const FusedPlacementSetup& setup, const FusedChannelFill& fill, float* out,
  const std::function<void(double)>& progress, FusedPlacementStats* stats, std::size_t* rowsDone,
  std::string* error);

} // namespace cuda
} // namespace mcv
