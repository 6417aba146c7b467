#include "vtkMergeChannels.h"

#include "vtkDataArray.h"
#include "vtkDataObject.h"
#include "vtkImageData.h"
#include "vtkInformation.h"
#include "vtkInformationVector.h"
#include "vtkObjectFactory.h"
#include "vtkPointData.h"
#include "vtkStreamingDemandDrivenPipeline.h"

#include <cmath>
#include <sstream>

vtkStandardNewMacro(vtkMergeChannels);

namespace
{
struct Grid
{
  int extent[6] = { 0, -1, 0, -1, 0, -1 };
  double spacing[3] = { 1, 1, 1 };
  double origin[3] = { 0, 0, 0 };
};

Grid gridOf(vtkInformation* info)
{
  Grid g;
  info->Get(vtkStreamingDemandDrivenPipeline::WHOLE_EXTENT(), g.extent);
  if (info->Has(vtkDataObject::SPACING()))
  {
    info->Get(vtkDataObject::SPACING(), g.spacing);
  }
  if (info->Has(vtkDataObject::ORIGIN()))
  {
    info->Get(vtkDataObject::ORIGIN(), g.origin);
  }
  return g;
}

// Spacing and origin written by different readers may differ in the last bits.
bool close(double a, double b, double scale)
{
  return std::abs(a - b) <= 1e-6 * scale;
}

bool sameGrid(const Grid& a, const Grid& b)
{
  for (int i = 0; i < 6; ++i)
  {
    if (a.extent[i] != b.extent[i])
    {
      return false;
    }
  }
  for (int i = 0; i < 3; ++i)
  {
    const double scale = std::abs(a.spacing[i]);
    if (!close(a.spacing[i], b.spacing[i], scale) || !close(a.origin[i], b.origin[i], scale))
    {
      return false;
    }
  }
  return true;
}

std::string describe(int input, vtkImageData* image, const Grid& g)
{
  std::ostringstream os;
  os << "input " << input + 1 << " (";
  vtkPointData* pd = image ? image->GetPointData() : nullptr;
  const int arrays = pd ? pd->GetNumberOfArrays() : 0;
  for (int a = 0; a < arrays; ++a)
  {
    const char* name = pd->GetArrayName(a);
    os << (a ? ", " : "") << "'" << (name ? name : "unnamed") << "'";
  }
  os << (arrays ? "" : "no point arrays") << "): " << g.extent[1] - g.extent[0] + 1 << " x "
     << g.extent[3] - g.extent[2] + 1 << " x " << g.extent[5] - g.extent[4] + 1
     << " voxels, spacing " << g.spacing[0] << " " << g.spacing[1] << " " << g.spacing[2]
     << ", origin " << g.origin[0] << " " << g.origin[1] << " " << g.origin[2];
  return os.str();
}
} // namespace

//------------------------------------------------------------------------------
int vtkMergeChannels::FillInputPortInformation(int port, vtkInformation* info)
{
  this->Superclass::FillInputPortInformation(port, info);
  info->Set(vtkAlgorithm::INPUT_REQUIRED_DATA_TYPE(), "vtkImageData");
  return 1;
}

//------------------------------------------------------------------------------
int vtkMergeChannels::RequestInformation(
  vtkInformation* request, vtkInformationVector** inputVector, vtkInformationVector* outputVector)
{
  this->GridsDiffer = false;
  this->ReportedError.clear();
  const int inputs = inputVector[0]->GetNumberOfInformationObjects();
  if (inputs > 0)
  {
    const Grid first = gridOf(inputVector[0]->GetInformationObject(0));
    for (int i = 1; i < inputs; ++i)
    {
      this->GridsDiffer =
        this->GridsDiffer || !sameGrid(first, gridOf(inputVector[0]->GetInformationObject(i)));
    }
  }
  return this->Superclass::RequestInformation(request, inputVector, outputVector);
}

//------------------------------------------------------------------------------
int vtkMergeChannels::RequestUpdateExtent(
  vtkInformation* request, vtkInformationVector** inputVector, vtkInformationVector* outputVector)
{
  if (!this->GridsDiffer)
  {
    return this->Superclass::RequestUpdateExtent(request, inputVector, outputVector);
  }
  // Each input whole, so that the error can name its arrays (asking every input for the
  // first one's extent is what gives AppendAttributes' extent error).
  for (int i = 0; i < inputVector[0]->GetNumberOfInformationObjects(); ++i)
  {
    vtkInformation* info = inputVector[0]->GetInformationObject(i);
    info->Set(vtkStreamingDemandDrivenPipeline::UPDATE_EXTENT(),
      info->Get(vtkStreamingDemandDrivenPipeline::WHOLE_EXTENT()), 6);
  }
  return 1;
}

//------------------------------------------------------------------------------
int vtkMergeChannels::RequestData(
  vtkInformation* request, vtkInformationVector** inputVector, vtkInformationVector* outputVector)
{
  if (!this->GridsDiffer)
  {
    return this->Superclass::RequestData(request, inputVector, outputVector);
  }
  vtkInformation* firstInfo = inputVector[0]->GetInformationObject(0);
  const Grid first = gridOf(firstInfo);
  std::ostringstream os;
  os << "The channels are not on one grid: ";
  for (int i = 1; i < inputVector[0]->GetNumberOfInformationObjects(); ++i)
  {
    vtkInformation* info = inputVector[0]->GetInformationObject(i);
    const Grid g = gridOf(info);
    if (!sameGrid(first, g))
    {
      os << describe(i, vtkImageData::GetData(info), g) << " differs from ";
    }
  }
  os << describe(0, vtkImageData::GetData(firstInfo), first)
     << ". Resample the channels onto one grid first (e.g. Resample To Image of each onto "
        "the first one's bounds and dimensions), then merge them.";
  if (os.str() != this->ReportedError)
  {
    this->ReportedError = os.str();
    vtkErrorMacro(<< this->ReportedError);
  }
  vtkDataObject::GetData(outputVector, 0)->Initialize();
  return 1;
}
