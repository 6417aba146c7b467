// The point arrays VTK and ParaView add for their own bookkeeping, never channels: the ghost
// markers (vtkGhostType) and ResampleToImage's vtkValidPointMask. Shared by the filters
// (mcvChannelArrays.h) and the Channels properties' domain (vtkSMChannelArrayListDomain),
// so the list a user sees is what the filters would take. Header-only, no dependency.
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

} // namespace vtkhelpers
} // namespace mcv
