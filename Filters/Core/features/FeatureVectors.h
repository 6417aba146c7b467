// Per-voxel feature vectors of a multichannel volume (dissertation chapter 5): the input of
// the dimensionality reduction (DimensionReduction.h) that gives the multichannel transfer
// function its small 2D/3D domain.
//
// Per channel, in this column order (only the selected ones):
//   intensity      the channel's value f
//   gradX/Y/Z      central differences in WORLD units, (f[i+1] - f[i-1]) / (2 h_axis);
//                  border voxels replicated (index clamped), exactly like HarrisResponse:
//                  at a border the difference is (f[1] - f[0]) / (2 h)
//   gradMag        |grad f|
//   laplacian      discrete 6-neighbour Laplacian / 6 in INDEX units:
//                  (f[i-1] + f[i+1] + f[j-1] + f[j+1] + f[k-1] + f[k+1]) / 6 - f,
//                  the deviation of f from the mean of its 6 face neighbours (border
//                  replicated). Index units on purpose: the /6 form is an "average of the
//                  neighbours minus the centre" and, like the 3x3x3 mean and variance, is
//                  taken over the voxel neighbourhood, not per world unit (with spacing it
//                  would weight thin axes by 1/h^2 and mix units inside one number).
//   mean           mean of the 3x3x3 neighbourhood (27 values, border replicated)
//   variance       population variance (divide by 27) of the same 27 values
// Names: "<channel>.intensity", "<channel>.gradX", "<channel>.gradY", "<channel>.gradZ",
// "<channel>.gradMag", "<channel>.laplacian", "<channel>.mean", "<channel>.variance",
// with the channel names passed in (default ch1, ch2, ...).
//
// Presets: SixD = intensity + gradMag per channel (6 columns for 3 channels); TwentyFourD =
// all 8 per channel (24 for 3 channels); Custom = the toggles of FeatureSelection.
//
// Normalisation, per output column, over the voxels whose channels are all finite:
// ZScore (default) (x - mean) / std (population std); MinMax (x - min) / (max - min) in
// [0, 1]; None: raw values. A constant column under ZScore/MinMax is left at 0 (warning).
//
// Non-finite input: a voxel whose value is NaN/Inf in any channel gets a feature row of
// zeros (after normalisation) and is left out of the column statistics; as a neighbour it
// is replaced by the centre voxel's value (like a border), so it does not spread NaN.
// The output never holds NaN/Inf (a raw feature that overflows float is set to 0, with a
// warning).
//
// Arithmetic is float32 per voxel (same on CPU and GPU), statistics in double.
#pragma once

#include "Communicator.h"
#include "Device.h"
#include "GridPiece.h"
#include "ImageGrid.h"
#include "ChannelView.h"

#include <cstddef>
#include <functional>
#include <string>
#include <vector>

namespace mcv
{

enum class FeaturePreset
{
  SixD = 0,        // intensity + gradient magnitude per channel
  TwentyFourD = 1, // all 8 per channel
  Custom = 2       // FeatureOptions::custom
};

enum class FeatureNormalization
{
  ZScore = 0,
  MinMax = 1,
  None = 2
};

// Which features each channel contributes (the same for every channel).
struct FeatureSelection
{
  bool intensity = true;
  bool gradient = false; // the vector: 3 columns gradX, gradY, gradZ
  bool gradientMagnitude = true;
  bool laplacian = false;
  bool localMean = false;
  bool localVariance = false;

  int perChannel() const
  {
    return int(intensity) + 3 * int(gradient) + int(gradientMagnitude) + int(laplacian) +
      int(localMean) + int(localVariance);
  }
  static FeatureSelection forPreset(FeaturePreset preset, const FeatureSelection& custom);
};

struct FeatureOptions
{
  FeaturePreset preset = FeaturePreset::SixD;
  FeatureSelection custom; // used when preset == Custom
  FeatureNormalization normalization = FeatureNormalization::ZScore;
  Device device = Device::Auto;
  // One name per channel for the column names; empty: ch1, ch2, ...
  std::vector<std::string> channelNames;
  std::function<void(double)> progress; // optional, receives [0,1] (called on the caller's thread)
  // Split over processes (MPI ranks): the grid passed in is this process's block with ghost
  // layers for the 3x3x3 neighbourhoods, `piece` says where it lies and which voxels it
  // owns, and the normalisation uses the statistics of the owned voxels of all processes,
  // so every process writes what one process would write for the whole volume. Default
  // (no communicator, empty piece): the grid is the whole volume.
  const Communicator* communicator = nullptr;
  GridPiece piece;
  // Optional (FeatureBricks): the normalisation's offsets and scales given, one per column
  // as FeatureResult::columnOffset/columnScale report them (a reduction model's, fitted on
  // another volume): no statistics pass runs and this volume's own statistics are never
  // used, so a voxel gets the features it would have had in the fit volume. Empty: computed.
  std::vector<double> givenOffset, givenScale;
};

// Where the features go: rows (voxels) x cols (features), row-major float32, owned by the
// caller (the VTK filter passes its output array's own memory: no copy is made).
struct FeatureOutput
{
  float* data = nullptr;
  std::size_t rows = 0;
  int cols = 0;
};

struct FeatureResult
{
  std::string error;                 // non-empty: the output is not meaningful
  std::vector<std::string> warnings; // one line each
  std::vector<std::string> names;    // one per column
  Device deviceUsed = Device::CPU;
  std::size_t nonFiniteVoxels = 0;   // voxels with a NaN/Inf value in some channel (whole
                                     // volume when split over processes)
  std::vector<int> constantColumns;  // columns left at 0 (ZScore/MinMax)
  std::vector<double> columnOffset;  // per column: mean (ZScore), min (MinMax), 0 (None)
  std::vector<double> columnScale;   // per column: 1/std, 1/(max-min), 1; 0 when constant
  double totalMs = 0;
  bool ok() const { return error.empty(); }
};

// Number of columns for `channels` channels under `options` (to size FeatureOutput).
int featureCount(std::size_t channels, const FeatureOptions& options);

// The names a file or a message uses: "ZScore", "MinMax", "None"; "6D", "24D", "Custom".
const char* normalizationName(FeatureNormalization normalization);
const char* presetName(FeaturePreset preset);
// And back: the value of a name; false (the value untouched) for an unknown name.
bool normalizationNamed(const std::string& name, FeatureNormalization& normalization);
bool presetNamed(const std::string& name, FeaturePreset& preset);

// Column names, in output order, for the given channel names.
std::vector<std::string> featureNames(
  const std::vector<std::string>& channelNames, const FeatureSelection& selection);

// The capability's one entry point. Every channel holds grid.voxelCount() values (x
// fastest). `out` must be rows = grid.voxelCount(), cols = featureCount(...). Returns
// result.ok(); on an error the output is left untouched or zero.
bool computeFeatures(const std::vector<ChannelView>& channels, const ImageGrid& grid,
  const FeatureOptions& options, const FeatureOutput& out, FeatureResult& result);

namespace detail
{
// Building blocks shared by the CPU and GPU paths (and the GPU tests).

// Per-column statistics over the valid rows (mask 0) and finite values.
struct ColumnStats
{
  std::vector<double> count, sum, min, max, sqdev; // sqdev: sum (x - sum/count)^2
  void reset(int cols);
};

// Channel -> float working copy; non-finite voxels counted and marked in `mask` (set to 1;
// mask must hold n bytes, or be null when the caller does not need it).
std::size_t channelToFloat(const ChannelView& channel, std::size_t n, float* values,
  unsigned char* mask);

// Raw (unnormalised) features of one float channel into columns [firstColumn, firstColumn +
// selection.perChannel()) of `out`. `hasNonFinite`: guard neighbours (slower path).
void channelFeaturesCPU(const float* values, bool hasNonFinite, const ImageGrid& grid,
  const FeatureSelection& selection, const FeatureOutput& out, int firstColumn);

// The same features of single voxels: `grid` is out.rows neighbourhoods of 3 x 3 x 3 voxels
// side by side along x (3 out.rows x 3 x 3, spacing as the volume's), and row b of `out`
// receives the features of centre (3b + 1, 1, 1) alone, with the expressions of
// channelFeaturesCPU (the same bits). Serial: callers run batches on their own threads.
void channelFeaturesCentresCPU(const float* values, bool hasNonFinite, const ImageGrid& grid,
  const FeatureSelection& selection, const FeatureOutput& out, int firstColumn);

// Pass 1 (count, sum, min, max) and, when `deviation`, pass 2 (sqdev about sum/count).
void columnStatsCPU(
  const FeatureOutput& out, const unsigned char* mask, bool deviation, ColumnStats& stats);

// out = (x - offset) * scale per column; 0 where scale is 0, the row is masked, or the
// result is not finite.
void applyNormalizationCPU(const FeatureOutput& out, const unsigned char* mask,
  const std::vector<double>& offset, const std::vector<double>& scale);

// The checks of the channels, grid and options of computeFeatures; "" when usable.
std::string checkInput(const std::vector<ChannelView>& channels, const ImageGrid& grid,
  const FeatureOptions& options);

// Statistics of the whole volume (every voxel counted once, whatever the split).
struct VolumeStats
{
  bool ready = false;
  ColumnStats columns;
  std::vector<double> badPerChannel;
  double badVoxels = 0, voxels = 0;
};

// The statistics of parts of the volume (slabs, processes) as one: sums, extremes, and the
// squared deviations by Chan's pairwise formula.
ColumnStats mergeStats(const std::vector<ColumnStats>& parts);

// Collective: this process's statistics combined with every other process's (serial: as
// they are).
VolumeStats combineStats(const ColumnStats& local, const std::vector<double>& badPerChannel,
  double badVoxels, double voxels, const Communicator* comm);

// Offsets and scales of the normalisation (result.columnOffset/columnScale); constant
// columns get scale 0 (result.constantColumns).
void normalizationFromStats(
  FeatureNormalization norm, const ColumnStats& stats, FeatureResult& result);

// Raw feature values that overflowed float32 (finite voxels whose value is not counted).
std::size_t overflowCount(const VolumeStats& volume);

// The warnings of the statistics: non-finite voxels per channel, overflows, constant
// columns (options.channelNames and result.names filled).
void addStatsWarnings(const VolumeStats& volume, const FeatureOptions& options, std::size_t overflow,
  FeatureResult& result);
} // namespace detail

} // namespace mcv
