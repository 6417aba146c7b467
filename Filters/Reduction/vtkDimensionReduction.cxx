#include "vtkDimensionReduction.h"

#include "vtkDataArray.h"
#include "vtkDataObject.h"
#include "vtkDemandDrivenPipeline.h"
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
#include "vtkStructuredData.h"
#include "vtkStringArray.h"
#include "vtkTable.h"
#include "vtkTypeUInt16Array.h"
#include "vtkUnsignedCharArray.h"

#include <vtksys/SystemTools.hxx>

// The VTK-free core (Filters/Core).
#include "BackgroundMask.h"
#include "CoordinateTexture.h" // CoordinateRange: the decoded range of float16 coordinates
#include "DimensionReduction.h"
#include "FeatureBricks.h"
#include "FeatureRows.h"
#include "MemoryBudget.h"
#include "ReductionMethods.h"
#include "mcvReductionModelFile.h"
#include "vtkDimensionReductionInternals.h"

#include "../Common/mcvChannelArrays.h" // availableArrays
#include "../Common/mcvPieces.h"        // PieceLayout

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <functional>
#include <memory>
#include <sstream>
#include <string>
#include <vector>

vtkStandardNewMacro(vtkDimensionReduction);

namespace
{

const char* const kFeaturesName = "Features";
const char* const kMaskName = "Foreground";
const char* const kCoordinatesName = "ReducedCoordinates";
const char* const kModelDistanceName = "ModelDistance";
const char* const kModelArrayName = "ReductionModel";

// The feature set computed from the channels: FeatureSet's, the 24D set for the automatic
// choice (the filter's 6D, 24D and Custom are the core's FeaturePreset values).
const char* computedFeatureSetName(int featureSet)
{
  return mcv::presetName(static_cast<mcv::FeaturePreset>(
    featureSet <= vtkDimensionReduction::FEATURES_CUSTOM ? featureSet
                                                         : vtkDimensionReduction::FEATURES_24D));
}

// The filter's Method values are the core's ReductionMethod values (checked below).
const mcv::ReductionMethodInfo* methodInfo(int method)
{
  return mcv::findReductionMethod(static_cast<mcv::ReductionMethod>(method));
}
static_assert(static_cast<int>(mcv::ReductionMethod::PCA) == vtkDimensionReduction::PCA &&
    static_cast<int>(mcv::ReductionMethod::Isomap) == vtkDimensionReduction::ISOMAP &&
    static_cast<int>(mcv::ReductionMethod::LLE) == vtkDimensionReduction::LLE &&
    static_cast<int>(mcv::ReductionMethod::UMAP) == vtkDimensionReduction::UMAP,
  "vtkDimensionReduction's Method values follow mcv::ReductionMethod (ReductionMethods.h)");

const char* methodName(int method)
{
  const mcv::ReductionMethodInfo* info = methodInfo(method);
  return info ? info->name : "unknown";
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

// The channels of `all` that the model names, in the model's order; "" or the first one
// missing, with the channels there are.
std::string pickModelChannels(const mcv::vtkhelpers::ChannelArrays& all, const std::vector<std::string>& wanted,
  const std::string& modelPath, mcv::vtkhelpers::ChannelArrays& picked)
{
  picked = mcv::vtkhelpers::ChannelArrays();
  picked.converted = all.converted;
  for (const std::string& name : wanted)
  {
    const auto at = std::find(all.names.begin(), all.names.end(), name);
    if (at == all.names.end())
    {
      std::string have;
      for (const std::string& n : all.names)
      {
        have += (have.empty() ? "" : ", ") + n;
      }
      return "The input has no channel '" + name + "', which the reduction model " + modelPath +
        " was fitted with (channels here: " + (have.empty() ? "none" : have) + ").";
    }
    const std::size_t i = static_cast<std::size_t>(at - all.names.begin());
    picked.views.push_back(all.views[i]);
    picked.labels.push_back(all.labels[i]);
    picked.names.push_back(all.names[i]);
  }
  return {};
}

// The string of the field-data array `name` of `image`, or "".
std::string fieldString(vtkImageData* image, const char* name)
{
  auto* a = vtkStringArray::SafeDownCast(image->GetFieldData()->GetAbstractArray(name));
  return a && a->GetNumberOfValues() > 0 ? a->GetValue(0) : std::string();
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
vtkMTimeType vtkDimensionReduction::PipelineKey()
{
  vtkMTimeType key = this->GetMTime();
  if (this->GetNumberOfInputConnections(0) > 0)
  {
    if (auto* upstream = vtkDemandDrivenPipeline::SafeDownCast(this->GetInputExecutive(0, 0)))
    {
      key = std::max(key, upstream->GetPipelineMTime());
    }
  }
  return key;
}

//------------------------------------------------------------------------------
void vtkDimensionReduction::SetFitTime(int fitTime)
{
  fitTime = std::min(std::max(fitTime, static_cast<int>(FIT_EACH_STEP)), static_cast<int>(FIT_ALL_STEPS));
  if (fitTime != this->FitTime)
  {
    this->FitTime = fitTime;
    this->Internals->HasCurrentStep = false;
    this->Modified();
  }
}

//------------------------------------------------------------------------------
void vtkDimensionReduction::SetFitTimeStep(int step)
{
  step = std::max(step, -1);
  if (step != this->FitTimeStep)
  {
    this->FitTimeStep = step;
    this->Internals->HasCurrentStep = false;
    this->Modified();
  }
}

//------------------------------------------------------------------------------
int vtkDimensionReduction::RequestUpdateExtent(
  vtkInformation* request, vtkInformationVector** inputVector, vtkInformationVector* outputVector)
{
  if (!this->Superclass::RequestUpdateExtent(request, inputVector, outputVector))
  {
    return 0;
  }
  vtkInternals& internals = *this->Internals;
  internals.FittingPass = false;
  internals.ApplyOneStep = false;
  internals.CollectingPass = false;
  if (this->FitTime != FIT_ONE_STEP)
  {
    this->FittedTimeStep = -1;
  }
  vtkInformation* inInfo = inputVector[0]->GetInformationObject(0);
  const bool modelFile = this->ModelFile && *this->ModelFile;
  if (this->FitTime == FIT_EACH_STEP || modelFile || !inInfo ||
    !inInfo->Has(vtkStreamingDemandDrivenPipeline::TIME_STEPS()))
  {
    return 1;
  }
  const int steps = inInfo->Length(vtkStreamingDemandDrivenPipeline::TIME_STEPS());
  if (steps <= 0)
  {
    return 1;
  }
  const double* times = inInfo->Get(vtkStreamingDemandDrivenPipeline::TIME_STEPS());
  vtkInformation* outInfo = outputVector->GetInformationObject(0);
  internals.HasDownstreamTime = outInfo->Has(vtkStreamingDemandDrivenPipeline::UPDATE_TIME_STEP());
  internals.DownstreamTime =
    internals.HasDownstreamTime ? outInfo->Get(vtkStreamingDemandDrivenPipeline::UPDATE_TIME_STEP()) : times[0];
  const bool all = this->FitTime == FIT_ALL_STEPS;
  double fitTime = times[0];
  if (!all && this->FitTimeStep >= 0)
  {
    fitTime = times[std::min(this->FitTimeStep, steps - 1)];
  }
  else if (!all)
  {
    if (!internals.HasCurrentStep)
    {
      // The step the downstream time falls in (the last one at or before it).
      int current = 0;
      while (current + 1 < steps && times[current + 1] <= internals.DownstreamTime)
      {
        ++current;
      }
      internals.CurrentStepTime = times[current];
      internals.HasCurrentStep = true;
    }
    fitTime = internals.CurrentStepTime;
  }
  const vtkMTimeType key = this->PipelineKey();
  const bool fitted = internals.OneStepModel && internals.OneStepKey == key && internals.OneStepAll == all &&
    (all || internals.OneStepTime == fitTime);
  internals.ApplyOneStep = fitted;
  if (fitted)
  {
    return 1;
  }
  internals.FittingPass = true;
  if (all)
  {
    if (internals.CollectKey != key || internals.StepCount != steps)
    {
      internals.ResetSeries();
      internals.CollectKey = key;
      internals.StepCount = steps;
    }
    internals.CollectingPass = true;
    inInfo->Set(vtkStreamingDemandDrivenPipeline::UPDATE_TIME_STEP(), times[internals.NextStep]);
    return 1;
  }
  inInfo->Set(vtkStreamingDemandDrivenPipeline::UPDATE_TIME_STEP(), fitTime);
  internals.OneStepTime = fitTime;
  this->FittedTimeStep = static_cast<int>(std::find(times, times + steps, fitTime) - times);
  return 1;
}

//------------------------------------------------------------------------------
mcv::ReductionOptions vtkDimensionReduction::MethodOptions()
{
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
  return options;
}

//------------------------------------------------------------------------------
std::shared_ptr<mcv::vtkhelpers::ModelFile> vtkDimensionReduction::NewModelFile(mcv::vtkhelpers::FeatureRecipe recipe,
  mcv::ReductionModel fitted, const mcv::ReductionResult& result, std::uint64_t seed,
  const std::array<int, 3>& volumeDimensions, const std::string& fittedOn)
{
  auto made = std::make_shared<mcv::vtkhelpers::ModelFile>();
  made->features = std::move(recipe);
  made->reduction = std::move(fitted);
  made->fit.numberOfNeighbors = this->NumberOfNeighbors;
  made->fit.numberOfLandmarks = this->NumberOfLandmarks;
  made->fit.numberOfEpochs = this->NumberOfEpochs;
  made->fit.minimumDistance = this->MinimumDistance;
  made->fit.referenceSampleSize = static_cast<std::uint64_t>(this->ReferenceSampleSize);
  made->fit.randomSeed = seed;
  made->fit.sampledVoxels = result.sampledVoxels;
  made->fit.volumeDimensions = volumeDimensions;
  made->fit.fittedOn = fittedOn;
  return made;
}

//------------------------------------------------------------------------------
bool vtkDimensionReduction::ReadModelFile()
{
  vtkInternals& internals = *this->Internals;
  const std::string path = this->ModelFile;
  unsigned long long size = 0;
  long time = 0;
  if (vtksys::SystemTools::FileExists(path, true))
  {
    size = vtksys::SystemTools::FileLength(path);
    time = vtksys::SystemTools::ModifiedTime(path);
  }
  if (internals.ReadModel && internals.ReadPath == path && internals.ReadSize == size && internals.ReadTime == time)
  {
    return true;
  }
  internals.ReadModel = nullptr;
  internals.ReadBytes.clear();
  std::vector<char> bytes;
  std::string error = mcv::vtkhelpers::readFileBytes(path, bytes);
  if (!error.empty())
  {
    vtkErrorMacro("The reduction model " << path << " " << error << ".");
    return false;
  }
  auto model = std::make_shared<mcv::vtkhelpers::ModelFile>();
  error = mcv::vtkhelpers::decodeModel(bytes, path, *model);
  if (!error.empty())
  {
    vtkErrorMacro(<< error);
    return false;
  }
  internals.ReadPath = path;
  internals.ReadSize = size;
  internals.ReadTime = time;
  internals.ReadModel = model;
  internals.ReadBytes = std::move(bytes);
  return true;
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
  this->NumberOfOutOfModelVoxels = 0;
  this->VarianceSpectrum = false;
  for (double& t : this->StageTimings)
  {
    t = 0.0;
  }
}

//------------------------------------------------------------------------------
int vtkDimensionReduction::RequestMultichannelData(
  vtkInformation* request, vtkInformationVector** inputVector, vtkInformationVector* outputVector)
{
  // A pass that fits for the others asks for another pass (CONTINUE_EXECUTING); any other
  // ends here, also when it fails (the request object outlives the pass).
  request->Remove(vtkStreamingDemandDrivenPipeline::CONTINUE_EXECUTING());
  this->ResetResults();
  vtkImageData* output = vtkImageData::GetData(outputVector, 0);
  vtkTable* spectrumTable = vtkTable::GetData(outputVector, 1);
  if (!output || !spectrumTable)
  {
    vtkErrorMacro("Missing output (image data on port 0, table on port 1).");
    return 0;
  }
  vtkImageData* image =
    this->GetInputImage(inputVector, "with a point array of feature vectors.");
  Run run;
  if (!image || !this->CheckArguments() || !this->GetImageBlock(image, run.grid, run.piece))
  {
    return 0;
  }
  // A split run's output holds its piece, not the ghost layers: the coordinates are made
  // at that extent, the other arrays cut to it (PassInputAtExtent).
  image->GetExtent(run.blockExtent);
  this->GetOutputExtent(image, outputVector, run.outputExtent);
  run.outputCount = static_cast<std::size_t>(vtkStructuredData::GetNumberOfPoints(run.outputExtent));
  if (image->GetPointData()->GetNumberOfArrays() == 0)
  {
    vtkErrorMacro("Input has no point arrays: no feature vectors to reduce. Compute them "
                  "first, e.g. with the MultichannelFeatures filter (array 'Features').");
    return 0;
  }
  vtkInternals& internals = *this->Internals;
  if (internals.CollectingPass)
  {
    return this->CollectSeriesStep(request, image, run.grid, run.piece, output);
  }
  // The pass that fits one time step for the others, when another step was asked for.
  run.fitOnly = internals.FittingPass && internals.HasDownstreamTime &&
    internals.DownstreamTime != internals.OneStepTime;
  if (!this->ChooseModel(image, run))
  {
    return 0;
  }
  // A converted feature array lives as long as the run (rows point into it).
  struct ReleaseCopy
  {
    vtkInternals& internals;
    ~ReleaseCopy() { internals.ConvertedFeatures = nullptr; }
  } releaseCopy{ internals };
  if (!this->ReduceRows(image, run))
  {
    return 0;
  }
  if (run.fitOnly)
  {
    // The step asked for comes next, placed with this fit.
    request->Set(vtkStreamingDemandDrivenPipeline::CONTINUE_EXECUTING(), 1);
    output->Initialize();
    return 1;
  }
  request->Remove(vtkStreamingDemandDrivenPipeline::CONTINUE_EXECUTING());
  if (!this->StoreResults(run))
  {
    return 0;
  }
  this->WriteImageOutput(image, run, output);
  // Output port 1, the spectrum table: on one process of a split run only (no copies).
  const mcv::vtkhelpers::PieceLayout& layout = this->GetPieceLayout();
  if (!layout.IsSplit() || layout.Piece == 0)
  {
    this->WriteSpectrumTable(run, spectrumTable);
  }
  this->UpdateProgress(1.0);
  return 1;
}

// ---- Argument checks -----------------------------------------------------------
bool vtkDimensionReduction::CheckArguments()
{
  if (this->OutputDimension != 2 && this->OutputDimension != 3)
  {
    vtkErrorMacro("OutputDimension must be 2 or 3 (got " << this->OutputDimension << ").");
    return false;
  }
  if (this->NumberOfNeighbors <= 0)
  {
    vtkErrorMacro("NumberOfNeighbors must be positive (got " << this->NumberOfNeighbors << ").");
    return false;
  }
  if (this->NumberOfLandmarks <= 0)
  {
    vtkErrorMacro("NumberOfLandmarks must be positive (got " << this->NumberOfLandmarks << ").");
    return false;
  }
  if (this->ReferenceSampleSize <= 0)
  {
    vtkErrorMacro(
      "ReferenceSampleSize must be positive (got " << this->ReferenceSampleSize << ").");
    return false;
  }
  return true;
}

// ---- The model: a file's, the fit of one or all time steps, or none (fit here) ---------
bool vtkDimensionReduction::ChooseModel(vtkImageData* image, Run& run)
{
  vtkInternals& internals = *this->Internals;
  if (this->ModelFile && *this->ModelFile)
  {
    if (!this->ReadModelFile())
    {
      return false;
    }
    run.model = internals.ReadModel;
    run.modelBytes = &internals.ReadBytes;
    run.modelSource = this->ModelFile;
    run.modelFromFile = true;
  }
  else if (internals.ApplyOneStep && internals.OneStepModel)
  {
    run.model = internals.OneStepModel;
    run.modelBytes = &internals.OneStepBytes;
    std::ostringstream os;
    if (internals.OneStepAll)
    {
      os << "the fit of all time steps";
    }
    else
    {
      os << "the fit of time " << internals.OneStepTime;
    }
    run.modelSource = os.str();
  }
  if (!run.model)
  {
    return true;
  }
  double spacing[3];
  image->GetSpacing(spacing);
  const std::array<double, 3>& fitted = run.model->features.spacing;
  for (int a = 0; a < 3; ++a)
  {
    if (std::abs(std::abs(spacing[a]) - fitted[a]) > 1e-6 * fitted[a])
    {
      std::ostringstream os;
      os << "The volume's spacing (" << spacing[0] << ", " << spacing[1] << ", " << spacing[2]
         << ") differs from that of the volume the model" << run.ModelNamed() << " was fitted on (" << fitted[0]
         << ", " << fitted[1] << ", " << fitted[2] << (run.model->features.lengthUnit.empty() ? "" : " ")
         << run.model->features.lengthUnit
         << "): gradients are per world unit, so the same tissue may get other features and coordinates.";
      this->ReportWarnings({ os.str() });
      break;
    }
  }
  return true;
}

// ---- The rows (a feature array, or the features of the channels: fused) and the core ----
bool vtkDimensionReduction::ReduceRows(vtkImageData* image, Run& run)
{
  vtkPointData* pd = image->GetPointData();
  run.fromChannels = run.model || this->UsesChannels(pd);
  mcv::vtkhelpers::FeatureRecipe recipe;
  std::string what;
  std::unique_ptr<mcv::FeatureRows> rows;
  if (run.fromChannels)
  {
    what = std::string("the ") + computedFeatureSetName(this->FeatureSet) + " features of the channels";
    // Collective from AllProcessesReady() on, which it calls.
    rows = this->ChannelRows(image, run.grid, run.piece, run.foreground, run.model.get(), &recipe);
  }
  else
  {
    const char* requested = nullptr;
    rows = this->InputArrayRows(image, run.grid.voxelCount(), requested);
    if (rows && !this->AllProcessesReady())
    {
      rows.reset();
    }
    what = std::string("'") + (requested ? requested : "") + "'";
  }
  if (!rows)
  {
    return false;
  }
  mcv::ReductionModel fittedModel;
  mcv::ReductionOptions options = this->RunOptions(pd, run, fittedModel);
  mcv::ReductionResult result = mcv::reduceDimension(*rows, options);
  // The slab buffers and a converted feature array go before the output is assembled.
  rows.reset();
  this->Internals->ConvertedFeatures = nullptr;
  this->SetProgressText(nullptr);
  this->ReportWarnings(result.warnings);
  run.method = run.model ? mcv::reductionMethodName(run.model->reduction.method) : methodName(this->Method);
  if (!result.ok())
  {
    vtkErrorMacro(<< run.method << (run.model ? " (the model" + run.ModelNamed() + ")" : std::string()) << " on "
                  << what << ": " << result.error);
    return false;
  }
  this->KeepModel(run, std::move(recipe), std::move(fittedModel), result, options);
  run.result = std::move(result);
  return true;
}

// The core's options of this run: the method's, the sample's mask, progress, the model to
// apply or to fit, the piece of a split run and the output arrays (made here, written by
// the core in place).
mcv::ReductionOptions vtkDimensionReduction::RunOptions(vtkPointData* pd, Run& run, mcv::ReductionModel& fittedModel)
{
  mcv::ReductionOptions options = this->MethodOptions();
  options.sampleMask = run.fromChannels ? (run.foreground ? run.foreground->GetPointer(0) : nullptr)
                                        : this->ForegroundMask(pd, run.grid.voxelCount());
  // The channels' features took the first tenth of the progress.
  const std::function<void(const char*, double)> staged = this->StageProgressCallback();
  const double first = run.fromChannels ? 0.1 : 0.0;
  options.progress = [staged, first](const char* stage, double f) { staged(stage, first + (1 - first) * f); };
  if (run.model)
  {
    options.model = &run.model->reduction;
  }
  else if (run.fromChannels)
  {
    options.fittedModel = &fittedModel;
    options.fitOnly = run.fitOnly;
  }
  if (this->GetPieceLayout().IsSplit())
  {
    options.communicator = this->GetCommunicator();
    options.piece = run.piece;
    options.block.dims = run.grid.dims;
    for (int a = 0; a < 3; ++a)
    {
      options.outputLo[a] = run.outputExtent[2 * a] - run.blockExtent[2 * a];
      options.outputHi[a] = run.outputExtent[2 * a + 1] - run.blockExtent[2 * a];
    }
  }
  this->NewCoordinates(run, options);
  if (run.model)
  {
    run.modelDistance = vtkSmartPointer<vtkFloatArray>::New();
    run.modelDistance->SetName(kModelDistanceName);
    run.modelDistance->SetNumberOfTuples(static_cast<vtkIdType>(run.outputCount));
    options.modelDistanceOutput = run.modelDistance->GetPointer(0);
  }
  return options;
}

// The output array, written by the core in place (no second coordinates buffer): float32,
// or binary16 bits in uint16 (the core rounds a chunk of rows at a time into it).
void vtkDimensionReduction::NewCoordinates(Run& run, mcv::ReductionOptions& options)
{
  run.half = this->CoordinatePrecision == FLOAT16;
  if (run.half)
  {
    run.reduced = vtkSmartPointer<vtkTypeUInt16Array>::New();
  }
  else
  {
    run.reduced = vtkSmartPointer<vtkFloatArray>::New();
  }
  run.reduced->SetName(kCoordinatesName);
  run.reduced->SetNumberOfComponents(this->OutputDimension);
  for (int c = 0; c < this->OutputDimension; ++c)
  {
    const std::string name = "dim" + std::to_string(c + 1);
    run.reduced->SetComponentName(c, name.c_str());
  }
  run.reduced->SetNumberOfTuples(static_cast<vtkIdType>(run.outputCount));
  if (run.half)
  {
    options.coordinatesHalfOutput = static_cast<vtkTypeUInt16Array*>(run.reduced.Get())->GetPointer(0);
  }
  else
  {
    options.coordinatesOutput = static_cast<vtkFloatArray*>(run.reduced.Get())->GetPointer(0);
  }
}

// ---- The model: kept for the writer and for the other time steps ---------------------
void vtkDimensionReduction::KeepModel(Run& run, mcv::vtkhelpers::FeatureRecipe recipe,
  mcv::ReductionModel fittedModel, const mcv::ReductionResult& result, const mcv::ReductionOptions& options)
{
  vtkInternals& internals = *this->Internals;
  if (run.model)
  {
    internals.Model = run.model;
    internals.ModelBytes = *run.modelBytes;
  }
  else if (run.fromChannels)
  {
    std::string fittedOn;
    if (internals.FittingPass)
    {
      std::ostringstream os;
      os << "time " << internals.OneStepTime;
      fittedOn = os.str();
    }
    auto made = this->NewModelFile(std::move(recipe), std::move(fittedModel), result, options.randomSeed,
      options.piece.wholeDims[0] > 0 ? options.piece.wholeDims : run.grid.dims, fittedOn);
    internals.Model = made;
    internals.ModelBytes = mcv::vtkhelpers::encodeModel(*made);
    if (internals.FittingPass)
    {
      internals.OneStepModel = made;
      internals.OneStepBytes = internals.ModelBytes;
      internals.OneStepKey = this->PipelineKey();
      internals.OneStepAll = false;
    }
  }
  else
  {
    internals.Model = nullptr;
    internals.ModelBytes.clear();
  }
}

// The results of the core as the filter's information properties; false when the core
// returned another dimension than asked.
bool vtkDimensionReduction::StoreResults(const Run& run)
{
  const mcv::ReductionResult& result = run.result;
  this->NumberOfOutOfModelVoxels = static_cast<vtkIdType>(result.outOfModelVoxels);
  if (run.model && result.outOfModelVoxels > 0)
  {
    std::ostringstream os;
    os << result.outOfModelVoxels << " voxel(s) lie outside the reduction model" << run.ModelNamed()
       << ": farther than " << mcv::kOutOfModelRatio
       << " x its reference radius from every reference, they get the colour of the nearest known tissue "
          "(see the point array ModelDistance).";
    this->ReportWarnings({ os.str() });
  }
  if (result.outputDimension != this->OutputDimension)
  {
    vtkErrorMacro("The reduction returned " << result.outputDimension << " dimensions, not "
                                            << this->OutputDimension << ".");
    return false;
  }
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
  return true;
}

// ---- Output port 0: the input plus ReducedCoordinates (filled by the core) -----------------
void vtkDimensionReduction::WriteImageOutput(vtkImageData* image, Run& run, vtkImageData* output)
{
  // A mask from upstream would describe other channels or settings: ours, or none. Ours
  // (block-sized, the sample's) is cut to the output's extent first and let go.
  vtkSmartPointer<vtkDataArray> mask = this->CropPointArray(run.foreground, run.blockExtent, run.outputExtent);
  run.foreground = nullptr;
  this->PassInputAtExtent(image, run.outputExtent, output,
    run.fromChannels ? std::vector<std::string>{ kMaskName, kCoordinatesName, kModelDistanceName }
                     : std::vector<std::string>{ kCoordinatesName, kModelDistanceName });
  if (mask)
  {
    output->GetPointData()->AddArray(mask);
  }
  output->GetPointData()->AddArray(run.reduced);
  if (run.modelDistance)
  {
    output->GetPointData()->AddArray(run.modelDistance);
  }
  vtkFieldData* fd = output->GetFieldData();
  if (run.model)
  {
    addFieldValue(fd, "OutOfModelVoxels", static_cast<double>(run.result.outOfModelVoxels));
    addFieldString(fd, "ReductionModelSource", run.modelSource);
  }
  addFieldValue(fd, "Trustworthiness", this->Trustworthiness);
  addFieldValue(fd, "VarianceRetained", this->VarianceRetained);
  vtkNew<vtkDoubleArray> spectrumCopy;
  spectrumCopy->DeepCopy(this->Internals->Spectrum);
  spectrumCopy->SetName("EigenvalueSpectrum");
  fd->AddArray(spectrumCopy);
  addFieldString(fd, "ReductionMethod", run.method);
  addFieldString(fd, "DeviceUsed", this->GetDeviceUsed());
  if (run.half)
  {
    // ParaView's data information would give the range of the bits: the values' range
    // (finite ones; this process's piece, which ParaView merges across processes) goes
    // with them as ReducedCoordinatesRange, a tuple of minima and one of maxima.
    mcv::CoordinateRange range;
    range.AddHalf(
      static_cast<vtkTypeUInt16Array*>(run.reduced.Get())->GetPointer(0), run.outputCount, this->OutputDimension);
    vtkNew<vtkDoubleArray> bounds;
    bounds->SetName((std::string(kCoordinatesName) + "Range").c_str());
    bounds->SetNumberOfComponents(this->OutputDimension);
    bounds->SetNumberOfTuples(range.empty ? 0 : 2);
    for (int c = 0; c < this->OutputDimension && !range.empty; ++c)
    {
      bounds->SetComponent(0, c, range.min[c]);
      bounds->SetComponent(1, c, range.max[c]);
    }
    fd->AddArray(bounds);
  }
}

// ---- Output port 1: the spectrum table and the model file's bytes ------------------------
void vtkDimensionReduction::WriteSpectrumTable(const Run& run, vtkTable* spectrumTable)
{
  const std::vector<double>& eigenvalues = run.result.eigenvalues;
  double positiveSum = 0.0;
  for (double v : eigenvalues)
  {
    if (std::isfinite(v) && v > 0)
    {
      positiveSum += v;
    }
  }
  // Only a variance spectrum has shares (LLE's and UMAP's eigenvalues are a graph operator's).
  const mcv::ReductionMethodInfo* info =
    run.model ? mcv::findReductionMethod(run.model->reduction.method) : methodInfo(this->Method);
  this->VarianceSpectrum = info && info->varianceSpectrum;
  const bool fractions = this->VarianceSpectrum && positiveSum > 0;
  const vtkIdType n = static_cast<vtkIdType>(eigenvalues.size());
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
    const double v = eigenvalues[static_cast<std::size_t>(i)];
    indexColumn->SetValue(i, static_cast<int>(i + 1));
    valueColumn->SetValue(i, v);
    fractionColumn->SetValue(i, fractions ? std::max(0.0, v) / positiveSum : 0.0);
  }
  spectrumTable->AddColumn(indexColumn);
  spectrumTable->AddColumn(valueColumn);
  spectrumTable->AddColumn(fractionColumn);
  const std::vector<char>& modelBytes = this->Internals->ModelBytes;
  if (!modelBytes.empty())
  {
    // The model file's bytes, for the model writer (ParaView's Save Data, mx.save_model).
    vtkNew<vtkUnsignedCharArray> bytes;
    bytes->SetName(kModelArrayName);
    bytes->SetNumberOfTuples(static_cast<vtkIdType>(modelBytes.size()));
    std::memcpy(bytes->GetPointer(0), modelBytes.data(), modelBytes.size());
    spectrumTable->GetFieldData()->AddArray(bytes);
  }
}

//------------------------------------------------------------------------------
bool vtkDimensionReduction::UsesChannels(vtkPointData* pd)
{
  switch (this->FeatureSet)
  {
    case FEATURES_INPUT_ARRAY:
      return false;
    case FEATURES_AUTOMATIC:
      return pd->GetAbstractArray(kFeaturesName) == nullptr;
    default:
      return true;
  }
}

//------------------------------------------------------------------------------
std::vector<vtkDataArray*> vtkDimensionReduction::GetDefaultChannels(vtkPointData* pd)
{
  std::vector<vtkDataArray*> picked = this->Superclass::GetDefaultChannels(pd);
  // Features, the mask and the coordinates of an earlier run are not channels.
  auto isOutput = [](vtkDataArray* a) {
    const std::string name = a->GetName() ? a->GetName() : "";
    return name == kFeaturesName || name == kMaskName || name == kCoordinatesName || name == kModelDistanceName;
  };
  picked.erase(std::remove_if(picked.begin(), picked.end(), isOutput), picked.end());
  return picked;
}

//------------------------------------------------------------------------------
std::unique_ptr<mcv::FeatureRows> vtkDimensionReduction::InputArrayRows(
  vtkImageData* image, std::size_t count, const char*& requested)
{
  vtkPointData* pd = image->GetPointData();
  vtkInformation* arrayInfo = this->GetInputArrayInformation(0);
  requested = arrayInfo && arrayInfo->Has(vtkDataObject::FIELD_NAME())
    ? arrayInfo->Get(vtkDataObject::FIELD_NAME())
    : nullptr;
  // ParaView leaves "0" in the property when the filter was made before its input had
  // run (pvpython: DimensionReduction(Input=MultichannelFeatures(...))): no choice was made
  // then, so the default array applies.
  if ((!requested || !*requested || std::string(requested) == "0") && pd->GetArray(kFeaturesName))
  {
    requested = kFeaturesName;
  }
  if (!requested || !*requested)
  {
    vtkErrorMacro("No feature array selected: set the Features property to a point array "
                  "of feature vectors (point arrays: "
      << mcv::vtkhelpers::availableArrays(pd) << ").");
    return nullptr;
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
    return nullptr;
  }
  vtkAbstractArray* abstractArray = pd->GetAbstractArray(requested);
  if (!abstractArray)
  {
    vtkErrorMacro("No point array named '"
      << requested << "' in the input (point arrays: " << mcv::vtkhelpers::availableArrays(pd)
      << "). Compute feature vectors first, e.g. with the MultichannelFeatures filter.");
    return nullptr;
  }
  vtkDataArray* features = vtkDataArray::SafeDownCast(abstractArray);
  if (!features)
  {
    vtkErrorMacro("Feature array '" << requested << "' is not numeric ("
                                    << abstractArray->GetClassName() << ").");
    return nullptr;
  }
  const int components = features->GetNumberOfComponents();
  if (components < 2)
  {
    vtkErrorMacro("Feature array '"
      << requested << "' has " << components
      << " component: nothing to reduce (DimensionReduction needs feature vectors of at least "
         "2 components, e.g. the 6D or 24D set of MultichannelFeatures).");
    return nullptr;
  }
  if (static_cast<std::size_t>(features->GetNumberOfTuples()) != count)
  {
    vtkErrorMacro("Feature array '" << requested << "' has " << features->GetNumberOfTuples()
                                    << " tuples for " << count << " voxels.");
    return nullptr;
  }

  const bool isFloat = features->GetDataType() == VTK_FLOAT && features->HasStandardMemoryLayout();
  if (this->ReportError(
        mcv::checkReductionMemory(count, components, this->OutputDimension, isFloat,
          this->CoordinatePrecision == FLOAT16)))
  {
    return nullptr;
  }

  // float32 as the core reads it: the array's own memory when it is a contiguous float
  // array, else one converted copy.
  const float* data = nullptr;
  if (isFloat)
  {
    data = static_cast<const float*>(features->GetVoidPointer(0));
  }
  else
  {
    auto converted = vtkSmartPointer<vtkFloatArray>::New();
    converted->DeepCopy(features); // converts every numeric type to float32
    data = converted->GetPointer(0);
    this->Internals->ConvertedFeatures = converted;
  }
  return std::unique_ptr<mcv::FeatureRows>(new mcv::MatrixRows(data, count, components));
}

//------------------------------------------------------------------------------
std::unique_ptr<mcv::FeatureRows> vtkDimensionReduction::ChannelRows(vtkImageData* image, mcv::ImageGrid grid,
  const mcv::GridPiece& piece, vtkSmartPointer<vtkUnsignedCharArray>& foreground,
  const mcv::vtkhelpers::ModelFile* model, mcv::vtkhelpers::FeatureRecipe* recipe)
{
  const std::size_t count = grid.voxelCount();
  this->SetGridSpacing(image, grid);
  mcv::vtkhelpers::ChannelArrays channels;
  if (model)
  {
    // The model's channels by name, whatever the Channels property says.
    std::vector<vtkDataArray*> arrays;
    mcv::vtkhelpers::ChannelArrays all;
    std::string error = mcv::vtkhelpers::selectChannelArrays(
      image, {}, [this](vtkPointData* pd) { return this->GetDefaultChannels(pd); }, "DimensionReduction", arrays);
    if (error.empty())
    {
      error = mcv::vtkhelpers::toChannels(arrays, count, all);
    }
    if (error.empty())
    {
      error = pickModelChannels(all, model->features.channels, this->ModelFile ? this->ModelFile : "", channels);
    }
    if (this->ReportError(error))
    {
      return nullptr;
    }
  }
  else if (!this->SelectChannels(image, count, channels))
  {
    return nullptr;
  }
  mcv::FeatureOptions options;
  this->SetFeatureOptions(this->FeatureSet <= FEATURES_CUSTOM ? this->FeatureSet : FEATURES_24D, options);
  options.channelNames = channels.names;
  options.communicator = this->GetCommunicator();
  options.piece = piece;
  options.device = this->GetRequestedDevice(); // the statistics pass runs where the reduction does
  options.progress = this->ProgressCallback(0.0, 0.1);
  bool maskBackground = this->MaskBackground;
  double backgroundThreshold = this->BackgroundThreshold;
  if (model)
  {
    const mcv::vtkhelpers::FeatureRecipe& made = model->features;
    options.preset = made.preset;
    options.custom = made.selection;
    options.normalization = made.normalization;
    options.givenOffset = made.offset;
    options.givenScale = made.scale;
    maskBackground = made.maskBackground;
    backgroundThreshold = made.backgroundThreshold;
  }
  const int F = mcv::featureCount(channels.views.size(), options);
  if (!this->CheckFeatureCount(F))
  {
    return nullptr;
  }
  this->ReportWarnings({ mcv::vtkhelpers::oneChannelWarning(channels, F) });
  const std::size_t slab =
    mcv::FeatureBricks::workingBytes(grid, F, mcv::FeatureBricks::slabBytesFor(grid, piece, F));
  if (this->ReportError(mcv::checkFusedReductionMemory(
        count, F, this->OutputDimension, slab, this->CoordinatePrecision == FLOAT16)))
  {
    return nullptr;
  }
  if (maskBackground)
  {
    foreground = vtkSmartPointer<vtkUnsignedCharArray>::New();
    foreground->SetName(kMaskName);
    foreground->SetNumberOfTuples(static_cast<vtkIdType>(count));
  }
  if (!this->AllProcessesReady())
  {
    return nullptr;
  }
  // The statistics pass over the slabs (collective), then the mask (collective).
  std::unique_ptr<mcv::FeatureBricks> bricks(new mcv::FeatureBricks(channels.views, grid, options));
  mcv::FeatureResult prepared;
  bricks->prepare(prepared);
  this->ReportWarnings(prepared.warnings);
  if (!prepared.ok())
  {
    vtkErrorMacro("Features of the channels: " << prepared.error);
    return nullptr;
  }
  if (foreground)
  {
    mcv::BackgroundMaskOptions maskOptions;
    maskOptions.threshold = backgroundThreshold;
    maskOptions.communicator = options.communicator;
    maskOptions.piece = piece;
    mcv::BackgroundMaskResult mask;
    const bool ok = mcv::computeBackgroundMask(channels.views, grid, maskOptions, foreground->GetPointer(0), mask);
    this->ReportWarnings(mask.warnings);
    if (!ok)
    {
      vtkErrorMacro("Background mask: " << mask.error);
      return nullptr;
    }
  }
  if (recipe)
  {
    recipe->channels = channels.names;
    recipe->preset = options.preset;
    recipe->selection = mcv::FeatureSelection::forPreset(options.preset, options.custom);
    recipe->normalization = options.normalization;
    recipe->featureNames = prepared.names;
    recipe->offset = prepared.columnOffset;
    recipe->scale = prepared.columnScale;
    for (int a = 0; a < 3; ++a)
    {
      recipe->spacing[a] = grid.spacing[a];
    }
    recipe->lengthUnit = fieldString(image, "LengthUnit");
    recipe->maskBackground = maskBackground;
    recipe->backgroundThreshold = backgroundThreshold;
  }
  // The channel arrays are the input's own (or kept by `channels`, which ends here): a
  // converted channel would dangle, so the bricks keep every converted copy.
  bricks->keepAlive(std::make_shared<mcv::vtkhelpers::ChannelArrays>(std::move(channels)));
  return std::unique_ptr<mcv::FeatureRows>(bricks.release());
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
  os << indent << "FeatureSet: " << this->FeatureSet << "\n";
  os << indent << "Method: " << methodName(this->Method) << "\n";
  os << indent << "OutputDimension: " << this->OutputDimension << "\n";
  os << indent << "CoordinatePrecision: " << (this->CoordinatePrecision == FLOAT16 ? "Float16" : "Float32") << "\n";
  os << indent << "NumberOfNeighbors: " << this->NumberOfNeighbors << "\n";
  os << indent << "NumberOfLandmarks: " << this->NumberOfLandmarks << "\n";
  os << indent << "MinimumDistance: " << this->MinimumDistance << "\n";
  os << indent << "NumberOfEpochs: " << this->NumberOfEpochs << "\n";
  os << indent << "ReferenceSampleSize: " << this->ReferenceSampleSize << "\n";
  os << indent << "RandomSeed: " << this->RandomSeed << "\n";
  os << indent << "VarianceRetained: " << this->VarianceRetained << "\n";
  os << indent << "Trustworthiness: " << this->Trustworthiness << "\n";
}
