#include "vtkMultichannelFeatures.h"

#include "vtkCellData.h"
#include "vtkDataArray.h"
#include "vtkDataObject.h"
#include "vtkFloatArray.h"
#include "vtkImageData.h"
#include "vtkInformation.h"
#include "vtkInformationVector.h"
#include "vtkObjectFactory.h"
#include "vtkPointData.h"
#include "vtkSmartPointer.h"
#include "vtkStreamingDemandDrivenPipeline.h"

// The VTK-free core (Filters/Core).
#include "FeatureVectors.h"

// VTK arrays -> core channels, shared with the other filters of the suite.
#include "../Common/mcvChannelArrays.h"

#include <algorithm>
#include <cmath>
#include <string>
#include <thread>
#include <vector>

vtkStandardNewMacro(vtkMultichannelFeatures);

struct vtkMultichannelFeatures::vtkInternals
{
  std::vector<std::string> Channels;
  std::string DeviceUsed = "CPU";
};

namespace
{
const char* const kOutputName = "Features";

bool isDefaultChannel(vtkDataArray* a)
{
  const char* name = a ? a->GetName() : nullptr;
  if (!a)
  {
    return false;
  }
  if (!name)
  {
    return true;
  }
  const std::string s(name);
  return s != "vtkGhostType" && s != "vtkValidPointMask" && s != kOutputName;
}
} // namespace

//------------------------------------------------------------------------------
vtkMultichannelFeatures::vtkMultichannelFeatures()
  : Internals(new vtkInternals)
{
  this->SetNumberOfInputPorts(1);
  this->SetNumberOfOutputPorts(1);
}

//------------------------------------------------------------------------------
vtkMultichannelFeatures::~vtkMultichannelFeatures() = default;

//------------------------------------------------------------------------------
void vtkMultichannelFeatures::AddChannel(const char* arrayName)
{
  if (arrayName && *arrayName)
  {
    this->Internals->Channels.emplace_back(arrayName);
    this->Modified();
  }
}

//------------------------------------------------------------------------------
void vtkMultichannelFeatures::ClearChannels()
{
  if (!this->Internals->Channels.empty())
  {
    this->Internals->Channels.clear();
    this->Modified();
  }
}

//------------------------------------------------------------------------------
int vtkMultichannelFeatures::GetNumberOfChannels()
{
  return static_cast<int>(this->Internals->Channels.size());
}

//------------------------------------------------------------------------------
const char* vtkMultichannelFeatures::GetChannel(int index)
{
  if (index < 0 || index >= this->GetNumberOfChannels())
  {
    return nullptr;
  }
  return this->Internals->Channels[index].c_str();
}

//------------------------------------------------------------------------------
const char* vtkMultichannelFeatures::GetDeviceUsed()
{
  return this->Internals->DeviceUsed.c_str();
}

//------------------------------------------------------------------------------
int vtkMultichannelFeatures::FillInputPortInformation(int, vtkInformation* info)
{
  // vtkDataSet rather than vtkImageData so that other inputs get this filter's own,
  // explicit error message (ParaView's XML restricts the input to image data anyway).
  info->Set(vtkAlgorithm::INPUT_REQUIRED_DATA_TYPE(), "vtkDataSet");
  return 1;
}

//------------------------------------------------------------------------------
int vtkMultichannelFeatures::RequestInformation(
  vtkInformation*, vtkInformationVector** inputVector, vtkInformationVector* outputVector)
{
  // The output has the input's geometry; with a non-image input there is none to pass on
  // (RequestData then reports the error).
  vtkInformation* inInfo = inputVector[0]->GetInformationObject(0);
  vtkInformation* outInfo = outputVector->GetInformationObject(0);
  if (inInfo->Has(vtkStreamingDemandDrivenPipeline::WHOLE_EXTENT()))
  {
    int wholeExtent[6];
    inInfo->Get(vtkStreamingDemandDrivenPipeline::WHOLE_EXTENT(), wholeExtent);
    outInfo->Set(vtkStreamingDemandDrivenPipeline::WHOLE_EXTENT(), wholeExtent, 6);
  }
  if (inInfo->Has(vtkDataObject::SPACING()))
  {
    outInfo->Set(vtkDataObject::SPACING(), inInfo->Get(vtkDataObject::SPACING()), 3);
  }
  if (inInfo->Has(vtkDataObject::ORIGIN()))
  {
    outInfo->Set(vtkDataObject::ORIGIN(), inInfo->Get(vtkDataObject::ORIGIN()), 3);
  }
  if (inInfo->Has(vtkDataObject::DIRECTION()))
  {
    outInfo->Set(vtkDataObject::DIRECTION(), inInfo->Get(vtkDataObject::DIRECTION()), 9);
  }
  return 1;
}

//------------------------------------------------------------------------------
int vtkMultichannelFeatures::RequestUpdateExtent(
  vtkInformation*, vtkInformationVector** inputVector, vtkInformationVector*)
{
  // Neighbourhood features and global column statistics: every rank asks for the whole
  // volume.
  vtkInformation* inInfo = inputVector[0]->GetInformationObject(0);
  if (inInfo->Has(vtkStreamingDemandDrivenPipeline::WHOLE_EXTENT()))
  {
    int wholeExtent[6];
    inInfo->Get(vtkStreamingDemandDrivenPipeline::WHOLE_EXTENT(), wholeExtent);
    inInfo->Set(vtkStreamingDemandDrivenPipeline::UPDATE_EXTENT(), wholeExtent, 6);
  }
  inInfo->Set(vtkStreamingDemandDrivenPipeline::UPDATE_PIECE_NUMBER(), 0);
  inInfo->Set(vtkStreamingDemandDrivenPipeline::UPDATE_NUMBER_OF_PIECES(), 1);
  inInfo->Set(vtkStreamingDemandDrivenPipeline::UPDATE_NUMBER_OF_GHOST_LEVELS(), 0);
  return 1;
}

//------------------------------------------------------------------------------
int vtkMultichannelFeatures::RequestData(
  vtkInformation*, vtkInformationVector** inputVector, vtkInformationVector* outputVector)
{
  this->NumberOfFeatures = 0;
  this->NumberOfNonFiniteVoxels = 0;
  this->ComputeTime = 0.0;
  this->Internals->DeviceUsed = "CPU";
  vtkDataObject* inputObject = vtkDataObject::GetData(inputVector[0], 0);
  vtkImageData* output = vtkImageData::GetData(outputVector, 0);
  if (!output)
  {
    vtkErrorMacro("No output image data.");
    return 0;
  }
  output->Initialize(); // nothing half-written on an error

  // ---- Argument checks -----------------------------------------------------------
  vtkImageData* image = vtkImageData::SafeDownCast(inputObject);
  if (!image)
  {
    vtkErrorMacro("Input is " << (inputObject ? inputObject->GetClassName() : "missing")
                              << ", not image data: MultichannelFeatures needs a vtkImageData "
                                 "(resample other data to an image first).");
    return 0;
  }
  int extent[6];
  image->GetExtent(extent);
  mcv::ImageGrid grid;
  for (int a = 0; a < 3; ++a)
  {
    grid.dims[a] = extent[2 * a + 1] - extent[2 * a] + 1;
  }
  if (grid.dims[0] <= 0 || grid.dims[1] <= 0 || grid.dims[2] <= 0)
  {
    vtkErrorMacro("Input image has an empty extent (" << extent[0] << " " << extent[1] << " "
                                                      << extent[2] << " " << extent[3] << " "
                                                      << extent[4] << " " << extent[5] << ").");
    return 0;
  }
  const std::size_t count = grid.voxelCount();
  // Gradients in world units along the image's own axes (an oriented image's direction
  // matrix rotates them; the features are per axis of the grid, like vtkImageGradient).
  double spacing[3];
  image->GetSpacing(spacing);
  for (int a = 0; a < 3; ++a)
  {
    grid.spacing[a] = std::abs(spacing[a]);
  }

  vtkPointData* pd = image->GetPointData();
  std::vector<vtkDataArray*> arrays;
  if (!this->Internals->Channels.empty())
  {
    for (const std::string& name : this->Internals->Channels)
    {
      vtkAbstractArray* abstractArray = pd->GetAbstractArray(name.c_str());
      if (!abstractArray)
      {
        vtkErrorMacro("No point array named '"
          << name << "' in the input (point arrays: "
          << mcv::vtkhelpers::availableArrays(pd) << ").");
        return 0;
      }
      vtkDataArray* dataArray = vtkDataArray::SafeDownCast(abstractArray);
      if (!dataArray)
      {
        vtkErrorMacro("Point array '" << name << "' is not numeric ("
                                      << abstractArray->GetClassName() << ").");
        return 0;
      }
      if (std::find(arrays.begin(), arrays.end(), dataArray) == arrays.end())
      {
        arrays.push_back(dataArray);
      }
    }
  }
  else
  {
    for (int i = 0; i < pd->GetNumberOfArrays(); ++i)
    {
      vtkDataArray* dataArray = pd->GetArray(i);
      if (isDefaultChannel(dataArray))
      {
        arrays.push_back(dataArray);
      }
    }
  }
  if (arrays.empty())
  {
    const bool cellArrays = image->GetCellData()->GetNumberOfArrays() > 0;
    vtkErrorMacro("Input has no point scalar array: MultichannelFeatures needs at least one "
                  "numeric point-data array (point arrays: "
      << mcv::vtkhelpers::availableArrays(pd) << ")"
      << (cellArrays ? "; it has cell arrays: convert them with Cell Data to Point Data."
                     : "."));
    return 0;
  }
  mcv::vtkhelpers::ChannelArrays channels;
  const std::string channelError = mcv::vtkhelpers::toChannels(arrays, count, channels);
  if (!channelError.empty())
  {
    vtkErrorMacro(<< channelError);
    return 0;
  }

  // ---- The core ----------------------------------------------------------------------
  mcv::FeatureOptions options;
  options.preset = static_cast<mcv::FeaturePreset>(this->FeatureSet);
  options.custom.intensity = this->Intensity;
  options.custom.gradient = this->Gradient;
  options.custom.gradientMagnitude = this->GradientMagnitude;
  options.custom.laplacian = this->Laplacian;
  options.custom.localMean = this->LocalMean;
  options.custom.localVariance = this->LocalVariance;
  options.normalization = static_cast<mcv::FeatureNormalization>(this->Normalization);
  options.device = static_cast<mcv::Device>(this->Device);
  options.channelNames = channels.names;
  const std::thread::id callingThread = std::this_thread::get_id();
  options.progress = [this, callingThread](double p) {
    // UpdateProgress fires VTK events: only from the thread that runs the pipeline.
    if (std::this_thread::get_id() == callingThread)
    {
      this->UpdateProgress(p);
    }
  };
  const int F = mcv::featureCount(channels.views.size(), options);
  if (F <= 0)
  {
    vtkErrorMacro("No feature selected: FeatureSet is Custom and every feature toggle "
                  "(Intensity, Gradient, GradientMagnitude, Laplacian, LocalMean, "
                  "LocalVariance) is off.");
    return 0;
  }

  // The core writes straight into the output array's own memory.
  vtkNew<vtkFloatArray> features;
  features->SetName(kOutputName);
  features->SetNumberOfComponents(F);
  if (!features->Allocate(static_cast<vtkIdType>(count) * F))
  {
    vtkErrorMacro("Cannot allocate the Features array (" << count << " x " << F
                                                         << " floats).");
    return 0;
  }
  features->SetNumberOfTuples(static_cast<vtkIdType>(count));
  mcv::FeatureOutput out;
  out.data = features->GetPointer(0);
  out.rows = count;
  out.cols = F;

  this->UpdateProgress(0.0);
  mcv::FeatureResult result;
  mcv::computeFeatures(channels.views, grid, options, out, result);
  for (const std::string& warning : result.warnings)
  {
    vtkWarningMacro(<< warning);
  }
  if (!result.ok())
  {
    vtkErrorMacro(<< result.error);
    return 0;
  }
  for (int c = 0; c < F && c < static_cast<int>(result.names.size()); ++c)
  {
    features->SetComponentName(c, result.names[c].c_str());
  }
  this->NumberOfFeatures = F;
  this->NumberOfNonFiniteVoxels = static_cast<vtkIdType>(result.nonFiniteVoxels);
  this->ComputeTime = result.totalMs;
  this->Internals->DeviceUsed = mcv::deviceName(result.deviceUsed);

  // ---- Output: the input plus Features ------------------------------------------------
  output->ShallowCopy(image);
  output->GetPointData()->AddArray(features);
  this->UpdateProgress(1.0);
  return 1;
}

//------------------------------------------------------------------------------
void vtkMultichannelFeatures::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "Channels:";
  for (const std::string& name : this->Internals->Channels)
  {
    os << " " << name;
  }
  os << "\n";
  os << indent << "FeatureSet: " << this->FeatureSet << "\n";
  os << indent << "Intensity: " << this->Intensity << "\n";
  os << indent << "Gradient: " << this->Gradient << "\n";
  os << indent << "GradientMagnitude: " << this->GradientMagnitude << "\n";
  os << indent << "Laplacian: " << this->Laplacian << "\n";
  os << indent << "LocalMean: " << this->LocalMean << "\n";
  os << indent << "LocalVariance: " << this->LocalVariance << "\n";
  os << indent << "Normalization: " << this->Normalization << "\n";
  os << indent << "Device: " << this->Device << "\n";
  os << indent << "NumberOfFeatures: " << this->NumberOfFeatures << "\n";
}
