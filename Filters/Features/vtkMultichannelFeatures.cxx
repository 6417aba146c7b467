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
#include "MemoryBudget.h"

// VTK arrays -> core channels, shared with the other filters of the suite.
#include "../Common/mcvChannelArrays.h"
#include "../Common/mcvControllerCommunicator.h"
#include "../Common/mcvPieces.h"

#include <algorithm>
#include <cmath>
#include <string>
#include <thread>
#include <vector>

vtkStandardNewMacro(vtkMultichannelFeatures);

struct vtkMultichannelFeatures::vtkInternals
{
  mcv::vtkhelpers::ChannelSelection Channels;
  std::string DeviceUsed = "CPU";
};

namespace
{
const char* const kOutputName = "Features";

// Default channels: every numeric point array but ParaView's bookkeeping and our output.
bool isDefaultChannel(vtkDataArray* a)
{
  return a && !mcv::vtkhelpers::isInternalArray(a->GetName()) &&
    !(a->GetName() && std::string(a->GetName()) == kOutputName);
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
  if (this->Internals->Channels.Add(arrayName))
  {
    this->Modified();
  }
}

//------------------------------------------------------------------------------
void vtkMultichannelFeatures::ClearChannels()
{
  if (this->Internals->Channels.Clear())
  {
    this->Modified();
  }
}

//------------------------------------------------------------------------------
int vtkMultichannelFeatures::GetNumberOfChannels()
{
  return this->Internals->Channels.Size();
}

//------------------------------------------------------------------------------
const char* vtkMultichannelFeatures::GetChannel(int index)
{
  return this->Internals->Channels.Get(index);
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
  // Piece requests become extents (vtkExtentTranslator), so a split run computes pieces.
  outInfo->Set(vtkAlgorithm::CAN_PRODUCE_SUB_EXTENT(), 1);
  return 1;
}

//------------------------------------------------------------------------------
int vtkMultichannelFeatures::RequestUpdateExtent(
  vtkInformation*, vtkInformationVector** inputVector, vtkInformationVector* outputVector)
{
  // Split runs: the extent asked of the output, plus one ghost layer for the gradient,
  // Laplacian and 3x3x3 statistics.
  return mcv::vtkhelpers::requestOutputExtentWithGhosts(inputVector, outputVector, 1);
}

//------------------------------------------------------------------------------
int vtkMultichannelFeatures::RequestData(
  vtkInformation*, vtkInformationVector** inputVector, vtkInformationVector* outputVector)
{
  this->NumberOfFeatures = 0;
  this->NumberOfNonFiniteVoxels = 0;
  this->ComputeTime = 0.0;
  this->Internals->DeviceUsed = "CPU";
  // A run split over processes: which voxels this one owns, and the collectives. Every
  // return before check.AllPassed() votes "failed" there.
  vtkInformation* outInfo = outputVector->GetInformationObject(0);
  const mcv::vtkhelpers::PieceLayout layout =
    mcv::vtkhelpers::pieceLayout(outInfo, inputVector[0]->GetInformationObject(0));
  mcv::vtkhelpers::ControllerCommunicator communicator(layout.Controller);
  const mcv::Communicator* comm = layout.IsSplit() ? &communicator : nullptr;
  mcv::vtkhelpers::CollectiveCheck check(comm);

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
  mcv::GridPiece piece;
  const std::string pieceError = mcv::vtkhelpers::gridPiece(image, layout, piece);
  if (!pieceError.empty())
  {
    vtkErrorMacro(<< pieceError);
    return 0;
  }
  // Gradients in world units along the image's own axes (an oriented image's direction
  // matrix rotates them; the features are per axis of the grid, like vtkImageGradient).
  double spacing[3];
  image->GetSpacing(spacing);
  for (int a = 0; a < 3; ++a)
  {
    grid.spacing[a] = std::abs(spacing[a]);
  }

  std::vector<vtkDataArray*> arrays;
  const std::string selectionError = mcv::vtkhelpers::selectChannelArrays(image,
    this->Internals->Channels.GetNames(),
    [](vtkPointData* pd) {
      std::vector<vtkDataArray*> picked;
      for (int i = 0; i < pd->GetNumberOfArrays(); ++i)
      {
        if (isDefaultChannel(pd->GetArray(i)))
        {
          picked.push_back(pd->GetArray(i));
        }
      }
      return picked;
    },
    "MultichannelFeatures", arrays);
  if (!selectionError.empty())
  {
    vtkErrorMacro(<< selectionError);
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
  options.communicator = comm;
  options.piece = piece;
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

  const std::string memoryError = mcv::checkFeatureMemory(count, F);
  if (!memoryError.empty())
  {
    vtkErrorMacro(<< memoryError);
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

  if (!check.AllPassed())
  {
    vtkErrorMacro("Another process of the parallel run reported an error (see its output).");
    return 0;
  }
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
  if (layout.IsSplit() && outInfo->Has(vtkStreamingDemandDrivenPipeline::UPDATE_EXTENT()))
  {
    // The ghost layers were for this filter only: the output is the extent asked of it.
    output->Crop(outInfo->Get(vtkStreamingDemandDrivenPipeline::UPDATE_EXTENT()));
  }
  this->UpdateProgress(1.0);
  return 1;
}

//------------------------------------------------------------------------------
void vtkMultichannelFeatures::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "Channels:";
  for (const std::string& name : this->Internals->Channels.GetNames())
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
