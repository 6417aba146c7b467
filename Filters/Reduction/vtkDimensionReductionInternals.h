// The state vtkDimensionReduction keeps between executions (its .cxx files only).
#pragma once

#include "vtkDimensionReduction.h"

#include "vtkDoubleArray.h"
#include "vtkFloatArray.h"
#include "vtkImageData.h"
#include "vtkNew.h"
#include "vtkSmartPointer.h"
#include "vtkUnsignedCharArray.h"

#include "DimensionReduction.h" // ReductionResult
#include "FeatureVectors.h" // detail::ColumnStats
#include "ImageGrid.h"
#include "mcvReductionModelFile.h"

#include <memory>
#include <string>
#include <vector>

struct vtkDimensionReduction::vtkInternals
{
  vtkNew<vtkDoubleArray> Spectrum;
  // A float32 copy of a feature array of another type, for the length of one run.
  vtkSmartPointer<vtkFloatArray> ConvertedFeatures;

  // The model of the last run (fitted or applied) and its file bytes, which the Spectrum
  // output carries as field data `ReductionModel` for the model writer.
  std::shared_ptr<const mcv::vtkhelpers::ModelFile> Model;
  std::vector<char> ModelBytes;

  // ModelFile as last read: the path, its size and modification time (a changed file is
  // read again), and what it held.
  std::string ReadPath;
  unsigned long long ReadSize = 0;
  long ReadTime = 0;
  std::shared_ptr<const mcv::vtkhelpers::ModelFile> ReadModel;
  std::vector<char> ReadBytes;

  // FIT_ONE_STEP: the fit of step OneStepTime, made while the filter and its input were at
  // OneStepKey (their modification times); a pass that fits (FittingPass) asks the input
  // for that step, and the next one for DownstreamTime, the step asked of this filter.
  std::shared_ptr<const mcv::vtkhelpers::ModelFile> OneStepModel;
  std::vector<char> OneStepBytes;
  vtkMTimeType OneStepKey = 0;
  double OneStepTime = 0;
  bool FittingPass = false;
  bool ApplyOneStep = false; // this pass places with OneStepModel
  bool HasDownstreamTime = false;
  double DownstreamTime = 0;
  bool OneStepAll = false; // OneStepModel is the fit of all steps (FIT_ALL_STEPS)
  // FIT_ONE_STEP with FitTimeStep -1: the step current at the first update after the
  // setting, kept until FitTime or FitTimeStep is set again.
  bool HasCurrentStep = false;
  double CurrentStepTime = 0;

  // FIT_ALL_STEPS: a pass that collects a step (CollectingPass) asks the input for step
  // NextStep of StepCount; each keeps a copy of its channels (the input's arrays change
  // with the step) and its feature statistics, under CollectKey.
  bool CollectingPass = false;
  int NextStep = 0;
  int StepCount = 0;
  vtkMTimeType CollectKey = 0;
  std::vector<vtkSmartPointer<vtkImageData>> StepImages;
  std::vector<mcv::detail::ColumnStats> StepStatistics;
  mcv::vtkhelpers::FeatureRecipe StepRecipe;
  void ResetSeries()
  {
    this->NextStep = 0;
    this->StepImages.clear();
    this->StepStatistics.clear();
  }
};

// One execution of RequestMultichannelData: its block and output extent, the model it
// applies (if any), where its rows come from, its output arrays and the core's result.
struct vtkDimensionReduction::Run
{
  mcv::ImageGrid grid;
  mcv::GridPiece piece;
  int blockExtent[6] = { 0, -1, 0, -1, 0, -1 };
  int outputExtent[6] = { 0, -1, 0, -1, 0, -1 };
  std::size_t outputCount = 0;
  bool fitOnly = false; // the pass that fits one time step for the others
  // The model applied: a file's, or the fit of one or all time steps; null: fit here.
  std::shared_ptr<const mcv::vtkhelpers::ModelFile> model;
  const std::vector<char>* modelBytes = nullptr;
  std::string modelSource;
  bool modelFromFile = false;
  // The model as messages name it: " 'brain.mcvmodel'" or " (the fit of time 20)".
  std::string ModelNamed() const
  {
    return this->modelFromFile ? " '" + this->modelSource + "'" : " (" + this->modelSource + ")";
  }
  bool fromChannels = false; // the features are computed from the channels (fused)
  vtkSmartPointer<vtkUnsignedCharArray> foreground;
  bool half = false; // float16 coordinates
  vtkSmartPointer<vtkDataArray> reduced;
  vtkSmartPointer<vtkFloatArray> modelDistance;
  const char* method = "";
  mcv::ReductionResult result;
};
