// Chosen voxels of a volume as a vertex cloud: ExtractVoxels (the listed voxels) and
// ReducedDomain (a sample) output one vertex per voxel with the voxel's point data copied
// exactly (tuples, not interpolated), and the voxel ids as `VoxelId`. Header-only, like
// mcvChannelArrays.h.
#pragma once

#include "vtkAbstractArray.h"
#include "vtkCellArray.h"
#include "vtkIdTypeArray.h"
#include "vtkNew.h"
#include "vtkPointData.h"
#include "vtkPolyData.h"
#include "vtkSmartPointer.h"

#include "mcvInternalArrays.h"

#include <algorithm>
#include <functional>
#include <vector>

namespace mcv
{
namespace vtkhelpers
{

// One vertex cell per point of `output` (count points).
inline void addVertexPerPoint(vtkPolyData* output, vtkIdType count)
{
  vtkNew<vtkCellArray> verts;
  verts->AllocateExact(count, count);
  for (vtkIdType i = 0; i < count; ++i)
  {
    verts->InsertNextCell(1, &i);
  }
  output->SetVerts(verts);
}

// Tuple ids[i] of each named point array of `in` into tuple i of a copy in `out`; the
// internal arrays (vtkGhostType, ...) and those `skip` names are left out.
inline void copyPointTuples(vtkPointData* in, const std::vector<vtkIdType>& ids,
  vtkPointData* out, const std::function<bool(vtkAbstractArray*)>& skip)
{
  const vtkIdType m = static_cast<vtkIdType>(ids.size());
  for (int a = 0; a < in->GetNumberOfArrays(); ++a)
  {
    vtkAbstractArray* source = in->GetAbstractArray(a);
    if (!source || !source->GetName() || isInternalArray(source->GetName()) || skip(source))
    {
      continue;
    }
    vtkSmartPointer<vtkAbstractArray> copy = vtk::TakeSmartPointer(source->NewInstance());
    copy->SetName(source->GetName());
    copy->SetNumberOfComponents(source->GetNumberOfComponents());
    copy->SetNumberOfTuples(m);
    for (vtkIdType i = 0; i < m; ++i)
    {
      copy->SetTuple(i, ids[i], source);
    }
    out->AddArray(copy);
  }
}

// `VoxelId` (vtkIdType): the voxel ids of the cloud's points, in the whole volume.
inline void addVoxelIds(vtkPointData* out, const std::vector<vtkIdType>& voxelIds)
{
  vtkNew<vtkIdTypeArray> array;
  array->SetName("VoxelId");
  array->SetNumberOfTuples(static_cast<vtkIdType>(voxelIds.size()));
  std::copy(voxelIds.begin(), voxelIds.end(), array->GetPointer(0));
  out->AddArray(array);
}

} // namespace vtkhelpers
} // namespace mcv
