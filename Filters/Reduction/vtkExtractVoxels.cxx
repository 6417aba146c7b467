#include "vtkExtractVoxels.h"

#include "vtkCellArray.h"
#include "vtkDoubleArray.h"
#include "vtkFieldData.h"
#include "../Common/mcvLabelTables.h"
#include "vtkIdTypeArray.h"
#include "vtkImageData.h"
#include "vtkInformation.h"
#include "vtkInformationVector.h"
#include "vtkIntArray.h"
#include "vtkMatrix3x3.h"
#include "vtkObjectFactory.h"
#include "vtkPointData.h"
#include "vtkPoints.h"
#include "vtkPolyData.h"
#include "vtkSmartPointer.h"
#include "vtkStreamingDemandDrivenPipeline.h"

#include "../Common/mcvInternalArrays.h" // vtkGhostType, vtkValidPointMask
#include "../Common/mcvPieces.h"         // PieceLayout: the voxels this process owns
#include "../Common/mcvVoxelCloud.h"     // vertices, copied tuples, VoxelId

#include <algorithm>
#include <sstream>

vtkStandardNewMacro(vtkExtractVoxels);

//------------------------------------------------------------------------------
vtkExtractVoxels::vtkExtractVoxels() = default;

//------------------------------------------------------------------------------
vtkExtractVoxels::~vtkExtractVoxels() = default;

//------------------------------------------------------------------------------
vtkPolyData* vtkExtractVoxels::GetOutput()
{
  return vtkPolyData::SafeDownCast(this->GetOutputDataObject(0));
}

//------------------------------------------------------------------------------
void vtkExtractVoxels::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "VoxelIds: " << this->VoxelIds.size() << "\n";
}

//------------------------------------------------------------------------------
void vtkExtractVoxels::SetNumberOfVoxelIds(int count)
{
  const std::size_t n = static_cast<std::size_t>(std::max(count, 0));
  if (n != this->VoxelIds.size())
  {
    this->VoxelIds.resize(n, 0);
    this->Modified();
  }
}

//------------------------------------------------------------------------------
void vtkExtractVoxels::SetVoxelId(int index, vtkIdType id)
{
  if (index < 0)
  {
    return;
  }
  if (static_cast<std::size_t>(index) >= this->VoxelIds.size())
  {
    this->VoxelIds.resize(static_cast<std::size_t>(index) + 1, 0);
  }
  else if (this->VoxelIds[index] == id)
  {
    return;
  }
  this->VoxelIds[index] = id;
  this->Modified();
}

//------------------------------------------------------------------------------
int vtkExtractVoxels::GetNumberOfVoxelIds()
{
  return static_cast<int>(this->VoxelIds.size());
}

//------------------------------------------------------------------------------
vtkIdType vtkExtractVoxels::GetVoxelId(int index)
{
  return index >= 0 && static_cast<std::size_t>(index) < this->VoxelIds.size()
    ? this->VoxelIds[index]
    : -1;
}

//------------------------------------------------------------------------------
int vtkExtractVoxels::FillOutputPortInformation(int, vtkInformation* info)
{
  info->Set(vtkDataObject::DATA_TYPE_NAME(), "vtkPolyData");
  return 1;
}

//------------------------------------------------------------------------------
int vtkExtractVoxels::RequestMultichannelData(
  vtkInformation*, vtkInformationVector** inputVector, vtkInformationVector* outputVector)
{
  vtkPolyData* output = vtkPolyData::GetData(outputVector, 0);
  vtkImageData* image = this->GetInputImage(inputVector, "(a volume) to extract voxels from.");
  if (!image || !output)
  {
    return 0;
  }

  // The whole volume and the voxels of it this process owns (all of them unless split).
  const mcv::vtkhelpers::PieceLayout& layout = this->GetPieceLayout();
  int whole[6], owned[6], extent[6];
  image->GetExtent(extent);
  vtkInformation* inInfo = inputVector[0]->GetInformationObject(0);
  if (layout.IsSplit())
  {
    std::copy(layout.Whole, layout.Whole + 6, whole);
    std::copy(layout.Owned, layout.Owned + 6, owned);
  }
  else
  {
    if (inInfo->Has(vtkStreamingDemandDrivenPipeline::WHOLE_EXTENT()))
    {
      inInfo->Get(vtkStreamingDemandDrivenPipeline::WHOLE_EXTENT(), whole);
    }
    else
    {
      std::copy(extent, extent + 6, whole);
    }
    std::copy(whole, whole + 6, owned);
  }
  vtkIdType dims[3];
  for (int a = 0; a < 3; ++a)
  {
    dims[a] = whole[2 * a + 1] - whole[2 * a] + 1;
    if (dims[a] <= 0)
    {
      vtkErrorMacro("The input volume has an empty extent: there are no voxels to extract.");
      return 0;
    }
    // An owned voxel that the block does not hold would be silently lost.
    if (owned[2 * a] <= owned[2 * a + 1] &&
      (extent[2 * a] > owned[2 * a] || extent[2 * a + 1] < owned[2 * a + 1]))
    {
      vtkErrorMacro("The input delivered extent "
        << extent[0] << " " << extent[1] << " " << extent[2] << " " << extent[3] << " "
        << extent[4] << " " << extent[5] << ", which does not hold this process's piece of "
        << "the volume.");
      return 0;
    }
  }
  const vtkIdType count = dims[0] * dims[1] * dims[2];
  for (vtkIdType id : this->VoxelIds)
  {
    if (id < 0 || id >= count)
    {
      vtkErrorMacro("Voxel id " << id << " is outside the volume (" << dims[0] << " x "
                                << dims[1] << " x " << dims[2] << " = " << count
                                << " voxels, ids 0 to " << count - 1 << ").");
      return 0;
    }
  }
  if (!this->AllProcessesReady())
  {
    return 0;
  }

  // The listed voxels this process owns: (input point id, global id, index).
  std::vector<vtkIdType> inputIds, globalIds;
  std::vector<int> ijk;
  for (vtkIdType id : this->VoxelIds)
  {
    int index[3] = { static_cast<int>(id % dims[0]), static_cast<int>((id / dims[0]) % dims[1]),
      static_cast<int>(id / (dims[0] * dims[1])) };
    int absolute[3];
    bool mine = true;
    for (int a = 0; a < 3 && mine; ++a)
    {
      absolute[a] = index[a] + whole[2 * a];
      mine = owned[2 * a] <= absolute[a] && absolute[a] <= owned[2 * a + 1];
    }
    if (!mine)
    {
      continue;
    }
    inputIds.push_back(image->ComputePointId(absolute));
    globalIds.push_back(id);
    ijk.insert(ijk.end(), index, index + 3);
  }

  const vtkIdType m = static_cast<vtkIdType>(inputIds.size());
  vtkNew<vtkPoints> points;
  points->SetDataTypeToDouble();
  points->SetNumberOfPoints(m);
  for (vtkIdType s = 0; s < m; ++s)
  {
    const int* index = ijk.data() + 3 * s;
    double xyz[3];
    image->TransformIndexToPhysicalPoint(
      index[0] + whole[0], index[1] + whole[2], index[2] + whole[4], xyz);
    points->SetPoint(s, xyz);
  }
  output->SetPoints(points);
  mcv::vtkhelpers::addVertexPerPoint(output, m);

  // The voxels' values, exact (tuples copied, not interpolated).
  vtkPointData* outPD = output->GetPointData();
  mcv::vtkhelpers::copyPointTuples(
    image->GetPointData(), inputIds, outPD, [](vtkAbstractArray*) { return false; });
  mcv::vtkhelpers::addVoxelIds(outPD, globalIds);
  vtkNew<vtkIntArray> voxelIJK;
  voxelIJK->SetName("VoxelIJK");
  voxelIJK->SetNumberOfComponents(3);
  voxelIJK->SetNumberOfTuples(m);
  std::copy(ijk.begin(), ijk.end(), voxelIJK->GetPointer(0));
  outPD->AddArray(voxelIJK);

  // The volume's grid, the same on every process.
  auto fieldArray = [output](const char* name, int n, const double* values) {
    vtkNew<vtkDoubleArray> array;
    array->SetName(name);
    array->SetNumberOfTuples(n);
    std::copy(values, values + n, array->GetPointer(0));
    output->GetFieldData()->AddArray(array);
  };
  // The channels' label tables (an atlas's names: mcvLabelTables.h): the probe's one fetch
  // brings the voxel and the names of its values.
  vtkFieldData* inFD = image->GetFieldData();
  for (int a = 0; a < inFD->GetNumberOfArrays(); ++a)
  {
    vtkAbstractArray* array = inFD->GetAbstractArray(a);
    if (array && mcv::vtkhelpers::isLabelTableName(array->GetName()))
    {
      output->GetFieldData()->AddArray(array);
    }
  }
  fieldArray("Origin", 3, image->GetOrigin());
  fieldArray("Spacing", 3, image->GetSpacing());
  fieldArray("Direction", 9, image->GetDirectionMatrix()->GetData());
  vtkNew<vtkIntArray> wholeExtent;
  wholeExtent->SetName("WholeExtent");
  wholeExtent->SetNumberOfTuples(6);
  std::copy(whole, whole + 6, wholeExtent->GetPointer(0));
  output->GetFieldData()->AddArray(wholeExtent);
  return 1;
}
