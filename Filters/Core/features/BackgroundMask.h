// The background of a multichannel volume: voxels that are empty in every channel (the
// zero field around an MRI head, the dark field of a micrograph). Left in, they fall inside
// the seeded Gaussian widgets and the bounding box glows as a translucent box around the
// structures; the suite marks them once, here, and the reduction, the widget seeding and
// the volume representation leave them out (the `Foreground` point array).
//
// A voxel is background when EVERY channel c has value <= cut_c, where
//   cut_c = min_c + threshold * (max_c - min_c)
// and min_c, max_c are the channel's finite extremes over the WHOLE volume (combined over
// processes when the volume is split; ghost voxels are voxels of the volume too, so they
// change neither). threshold 0 marks exactly the voxels at every channel's minimum. A
// non-finite value counts as empty (it carries no signal); a channel with no finite value
// at all is empty everywhere.
#pragma once

#include "ChannelView.h"
#include "Communicator.h"
#include "GridPiece.h"
#include "ImageGrid.h"

#include <cstddef>
#include <string>
#include <vector>

namespace mcv
{

struct BackgroundMaskOptions
{
  double threshold = 0.0; // fraction of each channel's range above its minimum, in [0, 1]
  // Split over processes (GridPiece.h, Communicator.h): the grid is this process's block,
  // `piece` says which voxels it owns (they are counted once). Default: the whole volume.
  const Communicator* communicator = nullptr;
  GridPiece piece;
};

struct BackgroundMaskResult
{
  std::string error;                  // non-empty: the mask is not meaningful
  std::vector<std::string> warnings;  // one line each
  std::vector<double> channelMin;     // per channel, whole volume (finite values)
  std::vector<double> channelMax;
  std::vector<double> cut;            // per channel: values <= cut are empty
  std::size_t voxels = 0;             // of the whole volume
  std::size_t backgroundVoxels = 0;   // of the whole volume
  bool ok() const { return error.empty(); }
};

// Writes grid.voxelCount() bytes to `foreground` (1 = foreground, 0 = background), ghost
// voxels included. Collective over options.communicator. Warns when every voxel is
// background (the mask is still written as computed).
bool computeBackgroundMask(const std::vector<ChannelView>& channels, const ImageGrid& grid,
  const BackgroundMaskOptions& options, unsigned char* foreground, BackgroundMaskResult& result);

// The cut of one channel (the formula above); NaN when the channel has no finite value.
double backgroundCut(double channelMin, double channelMax, double threshold);

} // namespace mcv
