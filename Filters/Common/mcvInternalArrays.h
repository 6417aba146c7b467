// The point arrays that are never channels: those VTK and ParaView add for their own
// bookkeeping, the ghost markers (vtkGhostType) and ResampleToImage's vtkValidPointMask, and
// the suite's own outputs. Shared by the filters (mcvChannelArrays.h) and the Channels
// properties' domain (vtkSMChannelArrayListDomain), so the list a user sees is what the
// filters would take. Header-only, no dependency.
#pragma once

#include <cstring>

namespace mcv
{
namespace vtkhelpers
{

inline bool isInternalArray(const char* name)
{
  return name && (std::strcmp(name, "vtkGhostType") == 0 || std::strcmp(name, "vtkValidPointMask") == 0);
}

// The point arrays the suite's filters write, which are results, not channels: Features and
// Foreground (MultichannelFeatures, DimensionReduction), ReducedCoordinates
// (DimensionReduction), HarrisScore and VoxelIndex (BestViewpoint's interest points). The
// Channels lists leave them out.
inline bool isSuiteOutputArray(const char* name)
{
  static const char* const outputs[] = { "Features", "Foreground", "ReducedCoordinates",
    "HarrisScore", "VoxelIndex" };
  for (const char* output : outputs)
  {
    if (name && std::strcmp(name, output) == 0)
    {
      return true;
    }
  }
  return false;
}

} // namespace vtkhelpers
} // namespace mcv
