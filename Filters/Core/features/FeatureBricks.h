// The features of a volume a slab of z slices at a time, never stored whole: the fused
// path of DimensionReduction, where the 24 floats per voxel of the whole
// Features array (5.5 GB at 57 M voxels) would not fit.
//
// A slab is computed from the channels with one ghost slice on each side (the reach of the
// gradient, Laplacian and 3x3x3 stencils), so its raw features are those computeFeatures
// gives for the whole volume, bit for bit. The normalisation's statistics come from a
// first streaming pass over the slabs (per-slab sums and squared deviations in double,
// combined by Chan's formula, then across processes as computeFeatures combines them), so
// the offsets and scales agree with the whole-volume ones to ~1e-16 relative. The
// features of single voxels (the reference sample's) are computed from their 3x3x3
// neighbourhoods alone, with the same code and the same values.
//
// As FeatureRows (common/FeatureRows.h) the rows are the voxels of the grid passed in
// (x fastest), normalised; blocks are slabs.
//
// GPU (CUDA builds): placeOnDevice runs the placement slab by slab on the device
// (cuda/FusedPlacementCuda.h): the channels of a slab go up, its features are computed,
// normalised with prepare()'s offsets and scales and placed there, its coordinates come
// down (for float16 output, DevicePlacement::outHalf, rounded from the slab's staging buffer). The slab is sized from the device memory it may use (setDeviceBytes; default: the
// free memory less a margin), so the volume may be larger than the device.
#pragma once

#include "ChannelView.h"
#include "FeatureRows.h"
#include "FeatureVectors.h"
#include "GridPiece.h"
#include "ImageGrid.h"

#include <cstddef>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

namespace mcv
{

class FeatureBricks final : public FeatureRows
{
public:
  // `options` as for computeFeatures (Device: where the GPU passes may run, see prepare();
  // communicator and piece for a split volume). slabBytes: the feature buffer of one slab
  // (at least one slice is taken); kScaledSlab: slabBytesFor(grid, options.piece, ...). The
  // channels' memory must outlive the bricks (keepAlive).
  FeatureBricks(const std::vector<ChannelView>& channels, const ImageGrid& grid, const FeatureOptions& options,
    std::size_t slabBytes = kScaledSlab);

  // Collective: checks the arguments and runs the statistics pass (progress per slab through
  // options.progress). Fills result (names, offsets and scales, warnings) as
  // computeFeatures does; false with result.error, after which nothing else may be called.
  // With options.device Auto or GPU, a CUDA build and a single-process volume, the pass runs
  // on the GPU (cuda/FusedPassesCuda.h; result.deviceUsed says so); a GPU failure reruns it
  // on the CPU with a warning.
  bool prepare(FeatureResult& result);

  // The statistics pass's column statistics of the whole volume (all processes), from which
  // prepare() took the offsets and scales; empty with given ones. Those of several volumes
  // merge (detail::mergeStats) into the statistics of all of them: the normalisation of a
  // fit over the time steps of a series.
  const detail::ColumnStats& statistics() const { return statistics_; }

  std::size_t rows() const override { return grid_.voxelCount(); }
  int cols() const override { return cols_; }
  std::size_t blockCount() const override;
  std::size_t blockBegin(std::size_t b) const override;
  const float* block(std::size_t b) override;
  void gather(const std::size_t* index, std::size_t n, float* out) override;

  // The GPU placement of every row (see the top of this file); attempted is false in a
  // build without CUDA or before prepare().
  DevicePlacementReport placeOnDevice(const DevicePlacement& request) override;
  // The column check and the strata on the GPU (cuda/FusedPassesCuda.h): attempted is false
  // in a build without CUDA, before prepare(), or for one process's piece of a volume.
  DeviceColumnSums columnSumsOnDevice(const std::function<void(double)>& progress) override;
  DevicePassReport strataOnDevice(const DeviceStrata& request) override;
  // Passes over the volume before the placement that ran on the GPU (statistics, column
  // sums, strata).
  int passesOnDevice() const;
  // Holds `owner` (what the channel views point into, e.g. converted copies) as long as the
  // bricks live, so that a caller can hand the bricks on alone.
  void keepAlive(std::shared_ptr<void> owner) { owner_ = std::move(owner); }

  // Device memory the GPU path may use (0: the free memory less a margin).
  void setDeviceBytes(std::size_t bytes) { deviceBytes_ = bytes; }
  // What the last placeOnDevice did (also after a failure: up to it).
  struct DeviceStats
  {
    int slabSlices = 0;
    std::size_t slabs = 0, bytesToDevice = 0, bytesFromDevice = 0, deviceBytes = 0, deviceUsedPeak = 0,
                pinnedBytes = 0;
    double setupMs = 0, fillMs = 0, waitMs = 0, totalMs = 0;
  };
  const DeviceStats& deviceStats() const { return deviceStats_; }
  // Every GPU pass so far, in order: "statistics", "column sums", "strata", "placement".
  struct DevicePass
  {
    std::string name;
    bool ok = false;
    DeviceStats stats;
  };
  const std::vector<DevicePass>& devicePasses() const { return devicePasses_; }

  int slabSlices() const { return slices_; }
  // The bytes one slab holds at a time (features with ghost slices, a float channel, masks):
  // what the fused path adds to its coordinates.
  std::size_t workingBytes() const;
  static std::size_t workingBytes(const ImageGrid& grid, int features, std::size_t slabBytes);

  // The slab budget of the whole volume (one process), and the constructor's default.
  static constexpr std::size_t kDefaultSlabBytes = std::size_t(256) << 20;
  static constexpr std::size_t kScaledSlab = 0;
  // The slab budget of a block of which `piece` says what the process owns: the whole
  // volume's kDefaultSlabBytes shared out in proportion to the voxels owned, so that a
  // process of a split run (1/R of the voxels) holds about 1/R of the working set, as it
  // holds 1/R of the coordinates; a fixed 256 MiB kept the peak per process far above 1/R
  // (docs/benchmarks.md §7.2). At least 4 slices of the block, unless that exceeds
  // kDefaultSlabBytes: a slab computes one ghost slice on each side, so thinner slabs would
  // spend more than half their time on ghosts (4 slices is what one process pays at
  // 57 M voxels). One process (whole piece): kDefaultSlabBytes. The slab size
  // never changes the features, only how many slabs compute them.
  static std::size_t slabBytesFor(const ImageGrid& grid, const GridPiece& piece, int features);

private:
  // Raw features of slices [z0, z1) of the grid, computed on [z0 - 1, z1 + 1) clipped to
  // the grid; returns the first row of slice z0. bad_ holds, per row of [z0, z1), 1 when a
  // channel is not finite there; badPerChannel (optional) counts the owned ones.
  float* rawSlab(int z0, int z1, std::vector<double>* badPerChannel);
  // One process holds the whole volume: the GPU passes apply.
  bool wholeVolumeHere() const;
  // ... and prepare() has run: the column sums and strata may run on the GPU.
  bool normalisedPassesApply() const;
  // Logs a GPU pass (devicePasses); a failure without a message gets one.
  bool recordDevicePass(const char* name, const DeviceStats& stats, bool ok, std::string& error);
  // CUDA builds: runs one pass over the normalised features (column sums, strata) when
  // normalisedPassesApply(); pass(setup, stats, error) returns false on a device failure,
  // which is logged. Returns whether the pass was attempted.
  template <class Pass>
  bool normalisedDevicePass(const char* name, std::string& error, Pass pass);
  // The statistics pass on the GPU; false (with error) leaves the CPU to run it.
  bool deviceStatistics(std::vector<detail::ColumnStats>& parts, std::vector<double>& badPerChannel,
    double& badVoxels, std::string& error);
  static int slicesFor(const ImageGrid& grid, int features, std::size_t slabBytes);

  std::vector<ChannelView> channels_;
  ImageGrid grid_;
  FeatureOptions options_;
  FeatureSelection selection_;
  int cols_ = 0;
  int slices_ = 1;
  std::vector<double> offset_, scale_;
  detail::ColumnStats statistics_;
  std::size_t deviceBytes_ = 0;
  DeviceStats deviceStats_;
  std::vector<DevicePass> devicePasses_;
  std::shared_ptr<void> owner_;
  // CUDA builds: the channels kept on the device from the statistics pass to the placement
  // when they fit (cuda::ResidentChannels, type-erased so that this header needs no CUDA).
  std::shared_ptr<void> resident_;
  std::vector<float> features_, values_;
  std::vector<unsigned char> bad_, channelBad_;
};

} // namespace mcv
