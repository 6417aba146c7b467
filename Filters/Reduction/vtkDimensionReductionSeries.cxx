// FitTime "All time steps": one fit on every step of a series. Each step is a pass of the
// pipeline (the input holds one step at a time), so the fit collects: a pass per step keeps
// a copy of the step's channels and the statistics of its features; after the last, the
// normalisation comes from all the statistics merged (the same offsets and scales as one
// volume holding every step), and the core fits on every step's rows at once
// (ReductionOptions::timeSteps), its reference sample drawn across the steps.
#include "vtkDimensionReduction.h"
#include "vtkDimensionReductionInternals.h"

#include "vtkDataArray.h"
#include "vtkFieldData.h"
#include "vtkInformation.h"
#include "vtkPointData.h"
#include "vtkStreamingDemandDrivenPipeline.h"
#include "vtkUnsignedCharArray.h"

#include "ConcatenatedRows.h"
#include "DimensionReduction.h"
#include "FeatureBricks.h"
#include "FeatureRows.h"

#include "../Common/mcvPieces.h" // PieceLayout

#include <sstream>
#include <utility>

//------------------------------------------------------------------------------
int vtkDimensionReduction::CollectSeriesStep(vtkInformation* request, vtkImageData* image,
  const mcv::ImageGrid& grid, const mcv::GridPiece& piece, vtkImageData* output)
{
  vtkInternals& internals = *this->Internals;
  const int step = internals.NextStep, steps = internals.StepCount;
  std::ostringstream text;
  text << "Fitting on all time steps: statistics of step " << step + 1 << " of " << steps;
  this->SetProgressText(text.str().c_str());
  if (!internals.StepImages.empty())
  {
    const int* first = internals.StepImages.front()->GetDimensions();
    if (first[0] != grid.dims[0] || first[1] != grid.dims[1] || first[2] != grid.dims[2])
    {
      vtkErrorMacro("Time step " << step << " has " << grid.dims[0] << " x " << grid.dims[1] << " x " << grid.dims[2]
                                 << " voxels, step 0 " << first[0] << " x " << first[1] << " x " << first[2]
                                 << ": one fit covers steps of one grid.");
      internals.ResetSeries();
      return 0;
    }
  }
  vtkSmartPointer<vtkUnsignedCharArray> foreground;
  mcv::vtkhelpers::FeatureRecipe recipe;
  std::unique_ptr<mcv::FeatureRows> rows = this->ChannelRows(image, grid, piece, foreground, nullptr, &recipe);
  auto* bricks = dynamic_cast<mcv::FeatureBricks*>(rows.get());
  if (!bricks)
  {
    internals.ResetSeries();
    return 0;
  }
  if (!internals.StepImages.empty() && recipe.channels != internals.StepRecipe.channels)
  {
    vtkErrorMacro("Time step " << step << " has other channels than step 0: one fit cannot cover them.");
    internals.ResetSeries();
    return 0;
  }
  internals.StepStatistics.push_back(bricks->statistics());
  internals.StepRecipe = std::move(recipe);
  rows.reset();

  // A copy of the channel arrays: the input's own change with the next step.
  vtkNew<vtkImageData> copy;
  copy->CopyStructure(image);
  copy->GetFieldData()->ShallowCopy(image->GetFieldData());
  for (vtkDataArray* channel : this->GetDefaultChannels(image->GetPointData()))
  {
    vtkSmartPointer<vtkDataArray> kept;
    kept.TakeReference(channel->NewInstance());
    kept->DeepCopy(channel);
    copy->GetPointData()->AddArray(kept);
  }
  internals.StepImages.emplace_back(copy.Get());

  if (step + 1 < steps)
  {
    ++internals.NextStep;
  }
  else if (!this->FitSeries(grid, piece))
  {
    internals.ResetSeries();
    return 0;
  }
  // The next pass reads the next step, or places the step asked of this filter.
  request->Set(vtkStreamingDemandDrivenPipeline::CONTINUE_EXECUTING(), 1);
  output->Initialize();
  return 1;
}

//------------------------------------------------------------------------------
int vtkDimensionReduction::FitSeries(const mcv::ImageGrid& grid, const mcv::GridPiece& piece)
{
  vtkInternals& internals = *this->Internals;
  const int steps = static_cast<int>(internals.StepImages.size());
  std::ostringstream text;
  text << "Fitting on all " << steps << " time steps";
  this->SetProgressText(text.str().c_str());

  // The normalisation of all the steps as one volume.
  mcv::FeatureResult normalisation;
  mcv::detail::normalizationFromStats(
    internals.StepRecipe.normalization, mcv::detail::mergeStats(internals.StepStatistics), normalisation);
  mcv::vtkhelpers::ModelFile across;
  across.features = internals.StepRecipe;
  across.features.offset = normalisation.columnOffset;
  across.features.scale = normalisation.columnScale;

  // Every step's rows with that normalisation (no statistics pass), one after another.
  std::vector<std::unique_ptr<mcv::FeatureRows>> parts;
  std::vector<unsigned char> mask;
  bool masked = true;
  for (const vtkSmartPointer<vtkImageData>& stepImage : internals.StepImages)
  {
    vtkSmartPointer<vtkUnsignedCharArray> foreground;
    std::unique_ptr<mcv::FeatureRows> rows = this->ChannelRows(stepImage, grid, piece, foreground, &across, nullptr);
    if (!rows)
    {
      return 0;
    }
    parts.push_back(std::move(rows));
    masked = masked && foreground;
    if (foreground)
    {
      const unsigned char* fg = foreground->GetPointer(0);
      mask.insert(mask.end(), fg, fg + foreground->GetNumberOfTuples());
    }
  }
  mcv::ConcatenatedRows rows(std::move(parts));

  mcv::ReductionOptions options = this->MethodOptions();
  options.sampleMask = masked && !mask.empty() ? mask.data() : nullptr;
  options.progress = this->StageProgressCallback();
  options.timeSteps = steps;
  options.fitOnly = true;
  mcv::ReductionModel fitted;
  options.fittedModel = &fitted;
  if (this->GetPieceLayout().IsSplit())
  {
    options.communicator = this->GetCommunicator();
    options.piece = piece;
    options.block.dims = grid.dims;
  }
  const mcv::ReductionResult result = mcv::reduceDimension(rows, options);
  this->SetProgressText(nullptr);
  this->ReportWarnings(result.warnings);
  if (!result.ok())
  {
    vtkErrorMacro("The fit on all " << steps << " time steps: " << result.error);
    return 0;
  }
  std::ostringstream fittedOn;
  fittedOn << "all " << steps << " time steps";
  auto made = this->NewModelFile(std::move(across.features), std::move(fitted), result, options.randomSeed,
    options.piece.wholeDims[0] > 0 ? options.piece.wholeDims : grid.dims, fittedOn.str());
  internals.OneStepModel = made;
  internals.OneStepBytes = mcv::vtkhelpers::encodeModel(*made);
  internals.OneStepKey = this->PipelineKey();
  internals.OneStepAll = true;
  internals.ResetSeries();
  return 1;
}
