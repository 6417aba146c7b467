#include "BackgroundMask.h"

#include "TypedChannel.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>

namespace mcv
{

namespace
{
constexpr double kInf = std::numeric_limits<double>::infinity();

// Finite extremes of one channel over the block. Ghost and shared voxels are voxels of the
// volume too: min and max do not care that they are seen twice.
void channelRange(const ChannelView& c, std::size_t n, double& lo, double& hi)
{
  double l = kInf, h = -kInf;
  withTypedData(c, [&](const auto* data) {
    const std::int64_t count = static_cast<std::int64_t>(n);
    const std::int64_t stride = c.numComponents;
#pragma omp parallel for reduction(min : l) reduction(max : h)
    for (std::int64_t v = 0; v < count; ++v)
    {
      const double x = static_cast<double>(data[v * stride + c.component]);
      if (std::isfinite(x))
      {
        l = std::min(l, x);
        h = std::max(h, x);
      }
    }
  });
  lo = l;
  hi = h;
}

// foreground[v] |= value > cut; a non-finite value, or a NaN cut, leaves the voxel empty.
void markAboveCut(const ChannelView& c, std::size_t n, double cut, unsigned char* foreground)
{
  withTypedData(c, [&](const auto* data) {
    const std::int64_t count = static_cast<std::int64_t>(n);
    const std::int64_t stride = c.numComponents;
#pragma omp parallel for
    for (std::int64_t v = 0; v < count; ++v)
    {
      const double x = static_cast<double>(data[v * stride + c.component]);
      foreground[v] |= (std::isfinite(x) && x > cut) ? 1 : 0;
    }
  });
}

// Background voxels among those this process owns.
std::size_t countOwnedBackground(const unsigned char* foreground, const ImageGrid& grid, const GridPiece& piece)
{
  std::size_t background = 0;
  const std::int64_t nx = grid.dims[0], nxy = nx * grid.dims[1];
  for (int k = piece.ownedLo[2]; k <= piece.ownedHi[2]; ++k)
  {
    for (int j = piece.ownedLo[1]; j <= piece.ownedHi[1]; ++j)
    {
      const unsigned char* line = foreground + k * nxy + j * nx;
      for (int i = piece.ownedLo[0]; i <= piece.ownedHi[0]; ++i)
      {
        background += line[i] ? 0 : 1;
      }
    }
  }
  return background;
}

std::string checkArguments(const std::vector<ChannelView>& channels, const ImageGrid& grid,
  const BackgroundMaskOptions& options, const unsigned char* foreground)
{
  if (channels.empty())
  {
    return "no channel: the background mask needs at least one channel";
  }
  if (grid.voxelCount() == 0)
  {
    return "the input volume is empty (no voxels)";
  }
  if (!foreground)
  {
    return "no output buffer for the background mask";
  }
  if (!(options.threshold >= 0.0 && options.threshold <= 1.0))
  {
    return "BackgroundThreshold must be in [0, 1] (a fraction of each channel's range), not " +
      std::to_string(options.threshold);
  }
  for (std::size_t c = 0; c < channels.size(); ++c)
  {
    const ChannelView& ch = channels[c];
    if (!ch.data || ch.numComponents < 1 || ch.component < 0 || ch.component >= ch.numComponents)
    {
      return "channel " + std::to_string(c + 1) + " has no data or an invalid component";
    }
  }
  return "";
}
} // namespace

double backgroundCut(double channelMin, double channelMax, double threshold)
{
  if (!(channelMin <= channelMax))
  {
    return std::numeric_limits<double>::quiet_NaN(); // no finite value in the channel
  }
  // At threshold 0 the cut is the minimum itself (no rounding can move it).
  return threshold > 0.0 ? channelMin + threshold * (channelMax - channelMin) : channelMin;
}

bool computeBackgroundMask(const std::vector<ChannelView>& channels, const ImageGrid& grid,
  const BackgroundMaskOptions& options, unsigned char* foreground, BackgroundMaskResult& result)
{
  result = BackgroundMaskResult();
  const Communicator* comm = options.communicator;
  result.error = checkArguments(channels, grid, options, foreground);
  // One process with bad arguments stops all of them (the others would wait below).
  if (!allTrue(comm, result.error.empty()))
  {
    if (result.error.empty())
    {
      result.error = "another process of the parallel run reported an error";
    }
    return false;
  }
  const std::size_t n = grid.voxelCount();
  const std::size_t C = channels.size();
  result.channelMin.assign(C, kInf);
  result.channelMax.assign(C, -kInf);
  for (std::size_t c = 0; c < C; ++c)
  {
    channelRange(channels[c], n, result.channelMin[c], result.channelMax[c]);
  }
  if (isDistributed(comm))
  {
    comm->min(result.channelMin);
    comm->max(result.channelMax);
  }

  std::fill(foreground, foreground + n, static_cast<unsigned char>(0));
  result.cut.resize(C);
  for (std::size_t c = 0; c < C; ++c)
  {
    result.cut[c] = backgroundCut(result.channelMin[c], result.channelMax[c], options.threshold);
    markAboveCut(channels[c], n, result.cut[c], foreground);
  }

  const GridPiece piece = options.piece.wholeDims[0] > 0 ? options.piece : GridPiece::whole(grid);
  std::vector<double> counts{ static_cast<double>(piece.ownedCount()),
    static_cast<double>(countOwnedBackground(foreground, grid, piece)) };
  if (isDistributed(comm))
  {
    comm->sum(counts);
  }
  result.voxels = static_cast<std::size_t>(counts[0]);
  result.backgroundVoxels = static_cast<std::size_t>(counts[1]);
  bool anyRange = false; // a channel with a range to set a threshold in
  for (std::size_t c = 0; c < result.channelMin.size(); ++c)
  {
    anyRange = anyRange || result.channelMax[c] > result.channelMin[c];
  }
  if (result.voxels > 0 && result.backgroundVoxels == result.voxels && !anyRange)
  {
    // Lowering BackgroundThreshold cannot help there: say what can.
    result.warnings.push_back("Every voxel is background: every channel is constant (or holds no "
                              "finite value), so no voxel rises above its minimum. The Foreground "
                              "array is all 0; turn off MaskBackground to keep every voxel.");
  }
  else if (result.voxels > 0 && result.backgroundVoxels == result.voxels)
  {
    result.warnings.push_back("Every voxel is background (no channel rises above BackgroundThreshold = " +
      std::to_string(options.threshold) +
      " of its range anywhere): lower BackgroundThreshold or turn off MaskBackground. The "
      "Foreground array is all 0.");
  }
  return true;
}

} // namespace mcv
