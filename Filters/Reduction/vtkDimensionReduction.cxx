#include "vtkDimensionReduction.h"

#include "vtkDataArray.h"
#include "vtkDataObject.h"
#include "vtkDoubleArray.h"
#include "vtkFieldData.h"
#include "vtkFloatArray.h"
#include "vtkImageData.h"
#include "vtkInformation.h"
#include "vtkInformationVector.h"
#include "vtkIntArray.h"
#include "vtkObjectFactory.h"
#include "vtkPointData.h"
#include "vtkSmartPointer.h"
#include "vtkStreamingDemandDrivenPipeline.h"
#include "vtkStringArray.h"
#include "vtkTable.h"
#include "vtkUnsignedCharArray.h"

// The VTK-free core (Filters/Core).
#include "DimensionReduction.h"
#include "MemoryBudget.h"

#include "../Common/mcvChannelArrays.h" // availableArrays
#include "../Common/mcvPieces.h"        // PieceLayout

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <sstream>
#include <string>
#include <vector>

vtkStandardNewMacro(vtkDimensionReduction);

struct vtkDimensionReduction::vtkInternals
{
  vtkNew<vtkDoubleArray> Spectrum;
};

namespace
{

const char* methodName(int method)
{
  switch (method)
  {
    case vtkDimensionReduction::PCA:
      return "PCA";
    case vtkDimensionReduction::ISOMAP:
      return "Isomap";
    case vtkDimensionReduction::LLE:
      return "LLE";
    case vtkDimensionReduction::UMAP:
      return "UMAP";
    default:
      return "unknown";
  }
}

void addFieldValue(vtkFieldData* fd, const char* name, double value)
{
  vtkNew<vtkDoubleArray> a;
  a->SetName(name);
  a->SetNumberOfTuples(1);
  a->SetValue(0, value);
  fd->AddArray(a);
}

void addFieldString(vtkFieldData* fd, const char* name, const std::string& value)
{
  vtkNew<vtkStringArray> a;
  a->SetName(name);
  a->InsertNextValue(value);
  fd->AddArray(a);
}

} // namespace

//------------------------------------------------------------------------------
vtkDimensionReduction::vtkDimensionReduction()
  : Internals(new vtkInternals)
{
  this->SetNumberOfOutputPorts(2);
  this->Internals->Spectrum->SetName("EigenvalueSpectrum");
  // Default feature array: `Features` (the output of MultichannelFeatures).
  this->SetInputArrayToProcess(
    0, 0, 0, vtkDataObject::FIELD_ASSOCIATION_POINTS, "Features");
}

//------------------------------------------------------------------------------
vtkDimensionReduction::~vtkDimensionReduction() = default;

//------------------------------------------------------------------------------
vtkDoubleArray* vtkDimensionReduction::GetEigenvalueSpectrum()
{
  return this->Internals->Spectrum;
}

//------------------------------------------------------------------------------
int vtkDimensionReduction::FillOutputPortInformation(int port, vtkInformation* info)
{
  info->Set(vtkDataObject::DATA_TYPE_NAME(), port == 0 ? "vtkImageData" : "vtkTable");
  return 1;
}

//------------------------------------------------------------------------------
int vtkDimensionReduction::RequestInformation(
  vtkInformation* request, vtkInformationVector** inputVector, vtkInformationVector* outputVector)
{
  if (!this->Superclass::RequestInformation(request, inputVector, outputVector))
  {
    return 0;
  }
  // The spectrum table is not structured: no extent on its port.
  vtkInformation* tableInfo = outputVector->GetInformationObject(1);
  tableInfo->Remove(vtkStreamingDemandDrivenPipeline::WHOLE_EXTENT());
  tableInfo->Remove(vtkDataObject::ORIGIN());
  tableInfo->Remove(vtkDataObject::SPACING());
  return 1;
}

//------------------------------------------------------------------------------
void vtkDimensionReduction::ResetResults()
{
  this->Internals->Spectrum->Initialize();
  this->Internals->Spectrum->SetName("EigenvalueSpectrum");
  this->VarianceRetained = 0.0;
  this->Trustworthiness = 0.0;
  this->NumberOfFeaturesUsed = 0;
  this->NumberOfSampledVoxels = 0;
  for (double& t : this->StageTimings)
  {
    t = 0.0;
  }
}

//------------------------------------------------------------------------------
int vtkDimensionReduction::RequestMultichannelData(
  vtkInformation*, vtkInformationVector** inputVector, vtkInformationVector* outputVector)
{
  this->ResetResults();
  vtkImageData* output = vtkImageData::GetData(outputVector, 0);
  vtkTable* spectrumTable = vtkTable::GetData(outputVector, 1);
  if (!output || !spectrumTable)
  {
    vtkErrorMacro("Missing output (image data on port 0, table on port 1).");
    return 0;
  }

  // ---- Argument checks -----------------------------------------------------------
  vtkImageData* image =
    this->GetInputImage(inputVector, "with a point array of feature vectors.");
  if (!image)
  {
    return 0;
  }
  if (this->OutputDimension != 2 && this->OutputDimension != 3)
  {
    vtkErrorMacro("OutputDimension must be 2 or 3 (got " << this->OutputDimension << ").");
    return 0;
  }
  if (this->NumberOfNeighbors <= 0)
  {
    vtkErrorMacro("NumberOfNeighbors must be positive (got " << this->NumberOfNeighbors << ").");
    return 0;
  }
  if (this->NumberOfLandmarks <= 0)
  {
    vtkErrorMacro("NumberOfLandmarks must be positive (got " << this->NumberOfLandmarks << ").");
    return 0;
  }
  if (this->ReferenceSampleSize <= 0)
  {
    vtkErrorMacro(
      "ReferenceSampleSize must be positive (got " << this->ReferenceSampleSize << ").");
    return 0;
  }
  mcv::ImageGrid grid;
  mcv::GridPiece piece;
  if (!this->GetImageBlock(image, grid, piece))
  {
    return 0;
  }
  const std::size_t count = grid.voxelCount();
  const mcv::vtkhelpers::PieceLayout& layout = this->GetPieceLayout();

  // ---- The feature array -----------------------------------------------------------
  vtkPointData* pd = image->GetPointData();
  if (pd->GetNumberOfArrays() == 0)
  {
    vtkErrorMacro("Input has no point arrays: no feature vectors to reduce. Compute them "
                  "first, e.g. with the MultichannelFeatures filter (array 'Features').");
    return 0;
  }
  vtkInformation* arrayInfo = this->GetInputArrayInformation(0);
  const char* requested = arrayInfo && arrayInfo->Has(vtkDataObject::FIELD_NAME())
    ? arrayInfo->Get(vtkDataObject::FIELD_NAME())
    : nullptr;
  // ParaView leaves "0" in the property when the filter was made before its input had
  // run (pvpython: DimensionReduction(Input=MultichannelFeatures(...))): no choice was made
  // then, so the default array applies.
  if ((!requested || !*requested || std::string(requested) == "0") && pd->GetArray("Features"))
  {
    requested = "Features";
  }
  if (!requested || !*requested)
  {
    vtkErrorMacro("No feature array selected: set the Features property to a point array "
                  "of feature vectors (point arrays: "
      << mcv::vtkhelpers::availableArrays(pd) << ").");
    return 0;
  }
  const int association = arrayInfo->Has(vtkDataObject::FIELD_ASSOCIATION())
    ? arrayInfo->Get(vtkDataObject::FIELD_ASSOCIATION())
    : vtkDataObject::FIELD_ASSOCIATION_POINTS;
  if (association != vtkDataObject::FIELD_ASSOCIATION_POINTS &&
    association != vtkDataObject::FIELD_ASSOCIATION_POINTS_THEN_CELLS)
  {
    vtkErrorMacro("Feature array '" << requested
                                    << "' must be a point array (one feature vector per "
                                       "voxel); convert cell data with Cell Data to Point Data.");
    return 0;
  }
  vtkAbstractArray* abstractArray = pd->GetAbstractArray(requested);
  if (!abstractArray)
  {
    vtkErrorMacro("No point array named '"
      << requested << "' in the input (point arrays: " << mcv::vtkhelpers::availableArrays(pd)
      << "). Compute feature vectors first, e.g. with the MultichannelFeatures filter.");
    return 0;
  }
  vtkDataArray* features = vtkDataArray::SafeDownCast(abstractArray);
  if (!features)
  {
    vtkErrorMacro("Feature array '" << requested << "' is not numeric ("
                                    << abstractArray->GetClassName() << ").");
    return 0;
  }
  const int components = features->GetNumberOfComponents();
  if (components < 2)
  {
    vtkErrorMacro("Feature array '"
      << requested << "' has " << components
      << " component: nothing to reduce (DimensionReduction needs feature vectors of at least "
         "2 components, e.g. the 6D or 24D set of MultichannelFeatures).");
    return 0;
  }
  if (static_cast<std::size_t>(features->GetNumberOfTuples()) != count)
  {
    vtkErrorMacro("Feature array '" << requested << "' has " << features->GetNumberOfTuples()
                                    << " tuples for " << count << " voxels.");
    return 0;
  }

  const bool isFloat = features->GetDataType() == VTK_FLOAT && features->HasStandardMemoryLayout();
  if (this->ReportError(
        mcv::checkReductionMemory(count, components, this->OutputDimension, isFloat)))
  {
    return 0;
  }

  // float32 as the core reads it: the array's own memory when it is a contiguous float
  // array, else one converted copy.
  vtkSmartPointer<vtkFloatArray> converted;
  const float* data = nullptr;
  if (features->GetDataType() == VTK_FLOAT && features->HasStandardMemoryLayout())
  {
    data = static_cast<const float*>(features->GetVoidPointer(0));
  }
  else
  {
    converted = vtkSmartPointer<vtkFloatArray>::New();
    converted->DeepCopy(features); // converts every numeric type to float32
    data = converted->GetPointer(0);
  }

  mcv::FeatureMatrix matrix;
  matrix.data = data;
  matrix.rows = count;
  matrix.cols = components;

  mcv::ReductionOptions options;
  options.method = static_cast<mcv::ReductionMethod>(this->Method);
  options.outputDimension = this->OutputDimension;
  options.numberOfNeighbors = this->NumberOfNeighbors;
  options.numberOfLandmarks = this->NumberOfLandmarks;
  options.minimumDistance = this->MinimumDistance;
  options.numberOfEpochs = this->NumberOfEpochs;
  options.referenceSampleSize = static_cast<std::size_t>(this->ReferenceSampleSize);
  options.randomSeed = static_cast<std::uint64_t>(static_cast<std::uint32_t>(this->RandomSeed));
  options.device = this->GetRequestedDevice();
  options.progress = this->StageProgressCallback();
  options.sampleMask = this->ForegroundMask(pd, count);

  if (layout.IsSplit())
  {
    options.communicator = this->GetCommunicator();
    options.piece = piece;
    options.block.dims = grid.dims;
  }

  // ---- The core ----------------------------------------------------------------------
  if (!this->AllProcessesReady())
  {
    return 0;
  }
  // The output array, written by the core in place (no second coordinates buffer).
  vtkNew<vtkFloatArray> reduced;
  reduced->SetName("ReducedCoordinates");
  reduced->SetNumberOfComponents(this->OutputDimension);
  for (int c = 0; c < this->OutputDimension; ++c)
  {
    const std::string name = "dim" + std::to_string(c + 1);
    reduced->SetComponentName(c, name.c_str());
  }
  reduced->SetNumberOfTuples(static_cast<vtkIdType>(count));
  options.coordinatesOutput = reduced->GetPointer(0);

  this->UpdateProgress(0.0);
  const mcv::ReductionResult result = mcv::reduceDimension(matrix, options);
  this->SetProgressText(nullptr);
  this->ReportWarnings(result.warnings);
  if (!result.ok())
  {
    vtkErrorMacro(<< methodName(this->Method) << " on '" << requested << "': " << result.error);
    return 0;
  }
  if (result.outputDimension != this->OutputDimension)
  {
    vtkErrorMacro("The reduction returned " << result.outputDimension << " dimensions, not "
                                            << this->OutputDimension << ".");
    return 0;
  }

  // ---- Output port 0: the input plus ReducedCoordinates (filled above) -----------------

  this->SetDeviceUsed(result.deviceUsed);
  this->VarianceRetained = result.varianceRetained;
  this->Trustworthiness = result.trustworthiness;
  this->NumberOfFeaturesUsed = static_cast<int>(result.usedColumns.size());
  this->StageTimings[0] = result.fitMs;
  this->StageTimings[1] = result.placeMs;
  this->StageTimings[2] = result.totalMs;
  this->NumberOfSampledVoxels = static_cast<vtkIdType>(result.sampledVoxels);
  vtkDoubleArray* spectrum = this->Internals->Spectrum;
  spectrum->SetNumberOfTuples(static_cast<vtkIdType>(result.eigenvalues.size()));
  for (std::size_t i = 0; i < result.eigenvalues.size(); ++i)
  {
    spectrum->SetValue(static_cast<vtkIdType>(i), result.eigenvalues[i]);
  }

  output->ShallowCopy(image);
  output->GetPointData()->AddArray(reduced);
  vtkFieldData* fd = output->GetFieldData();
  addFieldValue(fd, "Trustworthiness", this->Trustworthiness);
  addFieldValue(fd, "VarianceRetained", this->VarianceRetained);
  vtkNew<vtkDoubleArray> spectrumCopy;
  spectrumCopy->DeepCopy(spectrum);
  spectrumCopy->SetName("EigenvalueSpectrum");
  fd->AddArray(spectrumCopy);
  addFieldString(fd, "ReductionMethod", methodName(this->Method));
  addFieldString(fd, "DeviceUsed", this->GetDeviceUsed());
  this->CropToRequestedExtent(output, outputVector);

  // ---- Output port 1: the spectrum table (one process of a split run: no copies) ------
  if (layout.IsSplit() && layout.Piece != 0)
  {
    this->UpdateProgress(1.0);
    return 1;
  }

  double positiveSum = 0.0;
  for (double v : result.eigenvalues)
  {
    if (std::isfinite(v) && v > 0)
    {
      positiveSum += v;
    }
  }
  // LLE's and UMAP's eigenvalues are not variances.
  const bool fractions = this->Method != LLE && this->Method != UMAP && positiveSum > 0;
  const vtkIdType n = static_cast<vtkIdType>(result.eigenvalues.size());
  vtkNew<vtkIntArray> indexColumn;
  indexColumn->SetName("index");
  indexColumn->SetNumberOfTuples(n);
  vtkNew<vtkDoubleArray> valueColumn;
  valueColumn->SetName("value");
  valueColumn->SetNumberOfTuples(n);
  vtkNew<vtkDoubleArray> fractionColumn;
  fractionColumn->SetName("fraction");
  fractionColumn->SetNumberOfTuples(n);
  for (vtkIdType i = 0; i < n; ++i)
  {
    const double v = result.eigenvalues[static_cast<std::size_t>(i)];
    indexColumn->SetValue(i, static_cast<int>(i + 1));
    valueColumn->SetValue(i, v);
    fractionColumn->SetValue(i, fractions ? std::max(0.0, v) / positiveSum : 0.0);
  }
  spectrumTable->AddColumn(indexColumn);
  spectrumTable->AddColumn(valueColumn);
  spectrumTable->AddColumn(fractionColumn);

  this->UpdateProgress(1.0);
  return 1;
}

//------------------------------------------------------------------------------
const unsigned char* vtkDimensionReduction::ForegroundMask(vtkPointData* pd, std::size_t count)
{
  vtkAbstractArray* array = pd->GetAbstractArray("Foreground");
  if (!array)
  {
    return nullptr;
  }
  auto* mask = vtkUnsignedCharArray::SafeDownCast(array);
  if (!mask || mask->GetNumberOfComponents() != 1 ||
    static_cast<std::size_t>(mask->GetNumberOfTuples()) != count)
  {
    // Someone else's array of that name: sampling everything is still a valid reduction.
    vtkWarningMacro("The point array 'Foreground' is not a one-component uint8 mask of the "
      << count << " voxels; the reference sample is drawn from every voxel.");
    return nullptr;
  }
  return mask->GetPointer(0);
}

//------------------------------------------------------------------------------
void vtkDimensionReduction::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "Method: " << methodName(this->Method) << "\n";
  os << indent << "OutputDimension: " << this->OutputDimension << "\n";
  os << indent << "NumberOfNeighbors: " << this->NumberOfNeighbors << "\n";
  os << indent << "NumberOfLandmarks: " << this->NumberOfLandmarks << "\n";
  os << indent << "MinimumDistance: " << this->MinimumDistance << "\n";
  os << indent << "NumberOfEpochs: " << this->NumberOfEpochs << "\n";
  os << indent << "ReferenceSampleSize: " << this->ReferenceSampleSize << "\n";
  os << indent << "RandomSeed: " << this->RandomSeed << "\n";
  os << indent << "VarianceRetained: " << this->VarianceRetained << "\n";
  os << indent << "Trustworthiness: " << this->Trustworthiness << "\n";
}
