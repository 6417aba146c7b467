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
#include "vtkUnsignedCharArray.h"

// The VTK-free core (Filters/Core).
#include "BackgroundMask.h"
#include "FeatureVectors.h"
#include "MemoryBudget.h"

// VTK arrays -> core channels, shared with the other filters of the suite.
#include "../Common/mcvChannelArrays.h"
#include "../Common/mcvPrintMembers.h"

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

vtkStandardNewMacro(vtkMultichannelFeatures);

namespace
{
const char* const kOutputName = "Features";
const char* const kMaskName = "Foreground";

// The Foreground array (1 = foreground) of the channels, written by the core in place;
// nullptr when the core failed (result.error says why).
vtkSmartPointer<vtkUnsignedCharArray> computeForeground(const std::vector<mcv::ChannelView>& channels,
  const mcv::ImageGrid& grid, const mcv::BackgroundMaskOptions& options, mcv::BackgroundMaskResult& result)
{
  auto mask = vtkSmartPointer<vtkUnsignedCharArray>::New();
  mask->SetName(kMaskName);
  mask->SetNumberOfTuples(static_cast<vtkIdType>(grid.voxelCount()));
  if (!mcv::computeBackgroundMask(channels, grid, options, mask->GetPointer(0), result))
  {
    return nullptr;
  }
  return mask;
}
} // namespace

//------------------------------------------------------------------------------
vtkMultichannelFeatures::vtkMultichannelFeatures() = default;

//------------------------------------------------------------------------------
vtkMultichannelFeatures::~vtkMultichannelFeatures() = default;

//------------------------------------------------------------------------------
std::vector<vtkDataArray*> vtkMultichannelFeatures::GetDefaultChannels(vtkPointData* pd)
{
  std::vector<vtkDataArray*> picked = this->Superclass::GetDefaultChannels(pd);
  // Neither the features nor the mask of an earlier run are channels.
  auto isOutput = [](vtkDataArray* a) {
    return a->GetName() && (a->GetName() == std::string(kOutputName) || a->GetName() == std::string(kMaskName));
  };
  picked.erase(std::remove_if(picked.begin(), picked.end(), isOutput), picked.end());
  return picked;
}

//------------------------------------------------------------------------------
int vtkMultichannelFeatures::RequestInformation(
  vtkInformation* request, vtkInformationVector** inputVector, vtkInformationVector* outputVector)
{
  if (!this->Superclass::RequestInformation(request, inputVector, outputVector))
  {
    return 0;
  }
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
int vtkMultichannelFeatures::RequestMultichannelData(
  vtkInformation*, vtkInformationVector** inputVector, vtkInformationVector* outputVector)
{
  this->NumberOfFeatures = 0;
  this->NumberOfNonFiniteVoxels = 0;
  this->ComputeTime = 0.0;
  this->NumberOfBackgroundVoxels = 0;
  vtkImageData* output = vtkImageData::GetData(outputVector, 0);
  if (!output)
  {
    vtkErrorMacro("No output image data.");
    return 0;
  }
  output->Initialize(); // nothing half-written on an error

  // ---- Argument checks -----------------------------------------------------------
  vtkImageData* image =
    this->GetInputImage(inputVector, "(resample other data to an image first).");
  mcv::ImageGrid grid;
  mcv::GridPiece piece;
  if (!image || !this->GetImageBlock(image, grid, piece))
  {
    return 0;
  }
  this->SetGridSpacing(image, grid);
  mcv::vtkhelpers::ChannelArrays channels;
  if (!this->SelectChannels(image, grid.voxelCount(), channels))
  {
    return 0;
  }
  vtkSmartPointer<vtkFloatArray> features = this->ComputeFeatureArray(channels, grid, piece);
  if (!features)
  {
    return 0;
  }
  // The output's extent (a split run: the piece without the ghost layers). The block's
  // features are let go once cut, before anything else is made.
  int blockExtent[6], outputExtent[6];
  image->GetExtent(blockExtent);
  this->GetOutputExtent(image, outputVector, outputExtent);
  vtkSmartPointer<vtkDataArray> outputFeatures =
    this->CropPointArray(features, blockExtent, outputExtent);
  features = nullptr;

  // ---- The background mask (collective, like the features' statistics) -----------------
  vtkSmartPointer<vtkUnsignedCharArray> foreground;
  if (this->MaskBackground && !this->ComputeForegroundMask(channels, grid, piece, foreground))
  {
    return 0;
  }

  // ---- Output: the input plus Features (and Foreground) ----------------------------------
  // A mask from upstream would describe other channels or settings: ours, or none.
  vtkSmartPointer<vtkDataArray> mask = this->CropPointArray(foreground, blockExtent, outputExtent);
  foreground = nullptr;
  this->PassInputAtExtent(image, outputExtent, output, { kOutputName, kMaskName });
  output->GetPointData()->AddArray(outputFeatures);
  if (mask)
  {
    output->GetPointData()->AddArray(mask);
  }
  this->UpdateProgress(1.0);
  return 1;
}

// ---- The core: the block's features, written straight into the array's own memory -------
vtkSmartPointer<vtkFloatArray> vtkMultichannelFeatures::ComputeFeatureArray(
  const mcv::vtkhelpers::ChannelArrays& channels, const mcv::ImageGrid& grid, const mcv::GridPiece& piece)
{
  const std::size_t count = grid.voxelCount();
  mcv::FeatureOptions options;
  this->SetFeatureOptions(this->FeatureSet, options);
  options.device = this->GetRequestedDevice();
  options.channelNames = channels.names;
  options.communicator = this->GetCommunicator();
  options.piece = piece;
  options.progress = this->ProgressCallback();
  const int F = mcv::featureCount(channels.views.size(), options);
  if (!this->CheckFeatureCount(F) || this->ReportError(mcv::checkFeatureMemory(count, F)))
  {
    return nullptr;
  }
  this->ReportWarnings({ mcv::vtkhelpers::oneChannelWarning(channels, F) });

  // The block's array (a split run's output gets its piece cut from it).
  vtkSmartPointer<vtkFloatArray> features = vtkSmartPointer<vtkFloatArray>::New();
  features->SetName(kOutputName);
  features->SetNumberOfComponents(F);
  if (!features->Allocate(static_cast<vtkIdType>(count) * F))
  {
    vtkErrorMacro("Cannot allocate the Features array (" << count << " x " << F
                                                         << " floats).");
    return nullptr;
  }
  features->SetNumberOfTuples(static_cast<vtkIdType>(count));
  mcv::FeatureOutput out;
  out.data = features->GetPointer(0);
  out.rows = count;
  out.cols = F;

  if (!this->AllProcessesReady())
  {
    return nullptr;
  }
  this->UpdateProgress(0.0);
  mcv::FeatureResult result;
  mcv::computeFeatures(channels.views, grid, options, out, result);
  this->ReportWarnings(result.warnings);
  if (!result.ok())
  {
    vtkErrorMacro(<< result.error);
    return nullptr;
  }
  for (int c = 0; c < F && c < static_cast<int>(result.names.size()); ++c)
  {
    features->SetComponentName(c, result.names[c].c_str());
  }
  this->NumberOfFeatures = F;
  this->NumberOfNonFiniteVoxels = static_cast<vtkIdType>(result.nonFiniteVoxels);
  this->ComputeTime = result.totalMs;
  this->SetDeviceUsed(result.deviceUsed);
  return features;
}

// The Foreground array of the block (collective); false after an error (reported).
bool vtkMultichannelFeatures::ComputeForegroundMask(const mcv::vtkhelpers::ChannelArrays& channels,
  const mcv::ImageGrid& grid, const mcv::GridPiece& piece, vtkSmartPointer<vtkUnsignedCharArray>& foreground)
{
  mcv::BackgroundMaskOptions maskOptions;
  maskOptions.threshold = this->BackgroundThreshold;
  maskOptions.communicator = this->GetCommunicator();
  maskOptions.piece = piece;
  mcv::BackgroundMaskResult mask;
  foreground = computeForeground(channels.views, grid, maskOptions, mask);
  this->ReportWarnings(mask.warnings);
  if (!foreground)
  {
    vtkErrorMacro("Background mask: " << mask.error);
    return false;
  }
  this->NumberOfBackgroundVoxels = static_cast<vtkIdType>(mask.backgroundVoxels);
  return true;
}

//------------------------------------------------------------------------------
void vtkMultichannelFeatures::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  mcvPrintMembersMacro(
    os, indent, this->FeatureSet, this->NumberOfFeatures, this->NumberOfBackgroundVoxels);
}
