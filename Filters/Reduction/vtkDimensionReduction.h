/**
 * @class   vtkDimensionReduction
 * @brief   reduces per-voxel feature vectors to a 2D/3D domain (PCA, Isomap, LLE, UMAP).
 *
 * Input: a vtkImageData whose point data holds either a multi-component array of feature
 * vectors, one tuple per voxel (the `Features` array of MultichannelFeatures by default;
 * select another with SetInputArrayToProcess(0, 0, 0, POINTS, name), the `Features`
 * property in ParaView), or the channels themselves (the fused path). A contiguous
 * float32 array is handed to the core without a copy; any other numeric type is converted
 * to float32 once.
 *
 * FeatureSet says which: FEATURES_AUTOMATIC (default) reduces the input's `Features` array
 * when it has one, else computes the 24D set from the channels; FEATURES_INPUT_ARRAY always
 * the selected array (features computed upstream); FEATURES_6D, FEATURES_24D and
 * FEATURES_CUSTOM (with the Intensity ... LocalVariance toggles) compute that set from the
 * channels (the `Channels` property; none named: every numeric point array but
 * `Features`, `Foreground`, `ReducedCoordinates` and ParaView's own), with Normalization,
 * MaskBackground and BackgroundThreshold as in MultichannelFeatures. The fused path never
 * stores the features: mcv::FeatureBricks computes them a slab of z slices at a time (with
 * a ghost slice each side) for the normalisation statistics, the column statistics and
 * strata of the sample, and the placement; the reference sample's voxels are computed
 * alone. The result equals MultichannelFeatures -> DimensionReduction with the same
 * settings (to rounding in the normalisation's offsets and scales); the memory is the
 * coordinates, two bytes per voxel and one slab. Progress is reported per slab and an
 * abort stops between slabs with empty outputs. The output then holds ReducedCoordinates
 * and, with MaskBackground, the `Foreground` mask it computed, but no `Features`.
 *
 * The work is done by mcv::reduceDimension (Filters/Core, no VTK): the embedding is fitted
 * on a reference sample of ReferenceSampleSize voxels (a value >= the number of voxels
 * fits on all of them) and every voxel is placed by its 3 nearest reference vectors in
 * feature space with barycentric weights.
 *
 * Background: when the input has the uint8 point array `Foreground` of
 * MultichannelFeatures (1 = foreground), the reference sample is drawn from foreground
 * voxels only, so the embedding, its spectrum and trustworthiness describe the data and not
 * the empty field around it; background voxels are still placed (every voxel gets
 * ReducedCoordinates) and `Foreground` is passed on. A mask that marks no voxel is ignored
 * (warning).
 *
 * Output port 0: the input (shallow copy) plus the point array `ReducedCoordinates`
 * (float32, OutputDimension components named dim1, dim2[, dim3]; with CoordinatePrecision
 * FLOAT16 a vtkTypeUInt16Array of IEEE binary16 bits, see HalfCoordinates.h) and field-data arrays
 * `Trustworthiness`, `VarianceRetained`, `EigenvalueSpectrum`, `ReductionMethod`,
 * `DeviceUsed`.
 * Output port 1: a vtkTable `Spectrum` with columns `index` (1-based), `value` and
 * `fraction` (value / sum of the positive values of the spectrum, PCA and Isomap; LLE's
 * and UMAP's eigenvalues are not variances: their fraction column is 0).
 *
 * Errors (vtkErrorMacro, the filter fails, outputs stay empty): input not image data,
 * empty extent, no feature array selected or present, a non-numeric array, a single
 * feature component (nothing to reduce), OutputDimension not 2 or 3, a non-positive
 * NumberOfNeighbors / NumberOfLandmarks / ReferenceSampleSize, and every error of the
 * core (K >= M, NaN/Inf features, ...). The core's warnings are forwarded as VTK warnings.
 *
 * Device (vtkMultichannelAlgorithm): where the out-of-sample step and UMAP's layout run;
 * GetDeviceUsed says where the out-of-sample step ran (a UMAP layout that fell back to the
 * CPU says so in a warning).
 *
 * Parallel runs (mpiexec pvbatch --mpi, pvserver): each process holds a piece; the
 * column statistics and the reference sample are drawn across all processes and shared
 * (the same sample, hence the same embedding, as one process for the same seed), the fit
 * is shared, and each process places its own voxels. Only piece 0 emits the spectrum
 * table.
 */

#ifndef vtkDimensionReduction_h
#define vtkDimensionReduction_h

#include "mcvEnumPropertyMacro.h"      // for mcvEnumPropertyMacro
#include "mcvFiltersReductionModule.h" // for export macro
#include "vtkMultichannelFeatureAlgorithm.h"

#include <array>   // for std::array
#include <cstddef> // for std::size_t
#include <cstdint> // for std::uint64_t
#include <string>  // for std::string
#include <memory>  // for std::unique_ptr

class vtkDataArray;
class vtkDoubleArray;
class vtkPointData;
class vtkTable;
class vtkUnsignedCharArray;

#include "vtkSmartPointer.h" // for vtkSmartPointer
#include <vector>            // for std::vector

#ifndef __VTK_WRAP__
namespace mcv
{
class FeatureRows;
struct GridPiece;
struct ReductionModel;
struct ReductionOptions;
struct ReductionResult;
struct ImageGrid;
namespace vtkhelpers
{
struct FeatureRecipe;
struct ModelFile;
}
}
#endif

class MCVFILTERSREDUCTION_EXPORT vtkDimensionReduction : public vtkMultichannelFeatureAlgorithm
{
public:
  static vtkDimensionReduction* New();
  vtkTypeMacro(vtkDimensionReduction, vtkMultichannelFeatureAlgorithm);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  /** The sources of the feature vectors beyond the base's computed sets. */
  enum FeatureSourceType
  {
    FEATURES_INPUT_ARRAY = 3,
    FEATURES_AUTOMATIC = 4
  };

  ///@{
  /**
   * Where the feature vectors come from: FEATURES_AUTOMATIC (default: the `Features` array
   * when the input has one, else FEATURES_24D), FEATURES_INPUT_ARRAY (the selected array),
   * or a set computed from the channels (FEATURES_6D, FEATURES_24D, FEATURES_CUSTOM, with
   * the base's toggles, Normalization and background mask, as in MultichannelFeatures).
   */
  mcvEnumPropertyMacro(FeatureSet, FEATURES_6D, FEATURES_AUTOMATIC);
  ///@}

  enum MethodType
  {
    PCA = 0,
    ISOMAP = 1,
    LLE = 2,
    UMAP = 3
  };

  ///@{
  /** PCA (default), ISOMAP (landmark Isomap), LLE or UMAP. */
  mcvEnumPropertyMacro(Method, PCA, UMAP);
  ///@}

  enum CoordinatePrecisionType
  {
    FLOAT32 = 0,
    FLOAT16 = 1
  };

  ///@{
  /**
   * How ReducedCoordinates is stored: FLOAT32 (default, a vtkFloatArray) or FLOAT16 (a
   * vtkTypeUInt16Array of IEEE binary16 bits: half the memory, ~1/2048 relative precision;
   * the suite reads an unsigned-short coordinate array as float16). A coordinate beyond
   * float16's range (|x| > 65504) is an error. With FLOAT16 the output's field data also
   * has `ReducedCoordinatesRange` (OutputDimension components; tuple 0 the minima, tuple 1
   * the maxima of the decoded values of this piece), since the array's own range is that
   * of the bits.
   */
  mcvEnumPropertyMacro(CoordinatePrecision, FLOAT32, FLOAT16);
  ///@}

  ///@{
  /**
   * Dimension of the reduced domain: 2 or 3 (default 3). Any other value is refused at
   * execution time with an error (not clamped silently).
   */
  vtkSetMacro(OutputDimension, int);
  vtkGetMacro(OutputDimension, int);
  ///@}

  ///@{
  /** K of the Isomap / LLE neighbourhood graph (default 50; must be < the sample size). */
  vtkSetMacro(NumberOfNeighbors, int);
  vtkGetMacro(NumberOfNeighbors, int);
  ///@}

  ///@{
  /**
   * L, the landmarks of landmark Isomap and of locally linear landmarks (LLE), default 500;
   * L >= the reference sample size: exact Isomap / exact LLE.
   */
  vtkSetMacro(NumberOfLandmarks, int);
  vtkGetMacro(NumberOfLandmarks, int);
  ///@}

  ///@{
  /** UMAP: minimum distance of the layout (umap-learn's min_dist), in [0, 1]; default 0.1. */
  vtkSetMacro(MinimumDistance, double);
  vtkGetMacro(MinimumDistance, double);
  ///@}

  ///@{
  /** UMAP: SGD epochs; 0 (default): 500 up to 10000 reference points, 200 beyond. */
  vtkSetMacro(NumberOfEpochs, int);
  vtkGetMacro(NumberOfEpochs, int);
  ///@}

  ///@{
  /** M, the reference sample the embedding is fitted on (default 10000; >= voxels: all). */
  vtkSetMacro(ReferenceSampleSize, vtkIdType);
  vtkGetMacro(ReferenceSampleSize, vtkIdType);
  ///@}

  ///@{
  /** Seed of the reference sample and landmarks: same seed, same result (default 0). */
  vtkSetMacro(RandomSeed, int);
  vtkGetMacro(RandomSeed, int);
  ///@}

  ///@{
  /**
   * A reduction model file (`.mcvmodel`, written by ParaView's Save Data on this filter's
   * Spectrum output, or mx.save_model): empty (default) fits here; a path applies that
   * model instead: no fit, the features are computed from the channels the model names
   * (matched by name, any order; a missing one is an error naming it) with the model's
   * feature set and the normalisation offsets and scales of its fit volume, and every voxel
   * is placed with the model's references. FeatureSet, Normalization, Method and the fit's
   * properties are then the model's. A spacing other than the fit volume's is a warning.
   * The output gains the point array `ModelDistance` (distance to the nearest reference over
   * the model's reference radius; above 1.5 a voxel is outside the model and counted).
   */
  vtkSetStringMacro(ModelFile);
  vtkGetStringMacro(ModelFile);
  ///@}

  enum FitTimeType
  {
    FIT_EACH_STEP = 0,
    FIT_ONE_STEP = 1,
    FIT_ALL_STEPS = 2
  };

  ///@{
  /**
   * With time steps: FIT_EACH_STEP (default) fits every step on its own; FIT_ONE_STEP fits
   * once, on step FitTimeStep (an index, clamped to the steps; -1, the default: the step
   * current at the first update after FitTime or FitTimeStep was set), and places every
   * step with that fit, so that unchanged voxels keep their coordinates across steps;
   * FIT_ALL_STEPS fits once on all steps: the normalisation from the statistics of every
   * step, the reference sample drawn across them (while it fits, the filter holds a copy of
   * every step's channels). Ignored with a ModelFile.
   */
  virtual void SetFitTime(int fitTime);
  vtkGetMacro(FitTime, int);
  virtual void SetFitTimeStep(int step);
  vtkGetMacro(FitTimeStep, int);
  ///@}

  /**
   * The time step (index) the one-step fit used, once it ran; -1 before, with FIT_EACH_STEP
   * or FIT_ALL_STEPS.
   */
  vtkGetMacro(FittedTimeStep, int);

  /** Voxels of the last execution outside the applied model (0 when fitting). */
  vtkGetMacro(NumberOfOutOfModelVoxels, vtkIdType);

  ///@{
  /** Results of the last execution (empty / zero before the first or after a failure). */
  /** Eigenvalue spectrum as returned by the core (PCA, Isomap: descending). */
  vtkDoubleArray* GetEigenvalueSpectrum();
  /**
   * True when the spectrum's eigenvalues are variances (PCA, Isomap: ReductionMethods.h),
   * so that their shares and VarianceRetained mean what they say.
   */
  vtkGetMacro(VarianceSpectrum, bool);
  /** Fraction of the spectrum kept by the OutputDimension leading values (PCA, Isomap). */
  vtkGetMacro(VarianceRetained, double);
  /**
   * Trustworthiness (k = 10) of the embedding on a sample of the reference points; NaN
   * when it could not be measured (a sample of no more than 2k points).
   */
  vtkGetMacro(Trustworthiness, double);
  /** Number of feature components used (zero-variance ones are dropped by the core). */
  vtkGetMacro(NumberOfFeaturesUsed, int);
  /** Milliseconds: fit, out-of-sample placement, total (core timings). */
  vtkGetVector3Macro(StageTimings, double);
  /** Voxels the reference sample was drawn from (the foreground ones with a mask). */
  vtkGetMacro(NumberOfSampledVoxels, vtkIdType);
  ///@}

protected:
  vtkDimensionReduction();
  ~vtkDimensionReduction() override;

  int FillOutputPortInformation(int port, vtkInformation* info) override;
  int RequestInformation(vtkInformation*, vtkInformationVector**, vtkInformationVector*) override;
  int RequestMultichannelData(
    vtkInformation*, vtkInformationVector**, vtkInformationVector*) override;
  // FIT_ONE_STEP: asks the input for the fit step first, then for the step asked of us;
  // FIT_ALL_STEPS: for every step in turn, then for the step asked of us.
  int RequestUpdateExtent(vtkInformation*, vtkInformationVector**, vtkInformationVector*) override;
  // Split runs: one ghost layer, the reach of the features computed from the channels (a
  // Features array needs none; its ghost voxels are placed and cropped away).
  int GetSplitGhostLayers() override { return 1; }
  // Every numeric point array but the suite's outputs and ParaView's own.
  std::vector<vtkDataArray*> GetDefaultChannels(vtkPointData* pd) override;

  void ResetResults();

  int FeatureSet = FEATURES_AUTOMATIC;

  // The method and its parameters (into the core's options by MethodOptions).
  int Method = PCA;
  int OutputDimension = 3;
  int NumberOfNeighbors = 50;
  int NumberOfLandmarks = 500;
  double MinimumDistance = 0.1;
  int NumberOfEpochs = 0;
  // The reference sample it is fitted on.
  vtkIdType ReferenceSampleSize = 10000;
  int RandomSeed = 0;
  // Which fit the volume is placed with: a saved model, or the steps of a series it uses.
  char* ModelFile = nullptr;
  int FitTime = FIT_EACH_STEP;
  int FitTimeStep = -1;
  // The output: precision of the coordinates, the spectrum beside them.
  int CoordinatePrecision = FLOAT32;
  bool VarianceSpectrum = false;

  // Results of the last update (information properties).
  int FittedTimeStep = -1;
  vtkIdType NumberOfOutOfModelVoxels = 0;
  double VarianceRetained = 0.0;
  double Trustworthiness = 0.0;
  int NumberOfFeaturesUsed = 0;
  double StageTimings[3] = { 0, 0, 0 };
  vtkIdType NumberOfSampledVoxels = 0;

private:
  vtkDimensionReduction(const vtkDimensionReduction&) = delete;
  void operator=(const vtkDimensionReduction&) = delete;

  // The input's `Foreground` mask (uint8, one per voxel) as the core reads it; nullptr when
  // there is none or it is not such a mask (warning).
  const unsigned char* ForegroundMask(vtkPointData* pd, std::size_t count);

#ifndef __VTK_WRAP__
  // FIT_ALL_STEPS, one pass per step (vtkDimensionReductionSeries.cxx): keeps the step's
  // channels and feature statistics; after the last step, fits on all of them and asks for
  // one more pass, which places the step asked of us with that fit. 0 on an error.
  int CollectSeriesStep(vtkInformation* request, vtkImageData* image, const mcv::ImageGrid& grid,
    const mcv::GridPiece& piece, vtkImageData* output);
  int FitSeries(const mcv::ImageGrid& grid, const mcv::GridPiece& piece);
  // The core's options of the method and its sample, from the properties.
  mcv::ReductionOptions MethodOptions();
  // The model file of a fit: its features, its reduction and the fit's settings.
  std::shared_ptr<mcv::vtkhelpers::ModelFile> NewModelFile(mcv::vtkhelpers::FeatureRecipe recipe,
    mcv::ReductionModel fitted, const mcv::ReductionResult& result, std::uint64_t seed,
    const std::array<int, 3>& volumeDimensions, const std::string& fittedOn);
  // The rows the core reads: the selected feature array (nullptr after an error), or, on
  // the fused path, the features computed from the channels a slab at a time (prepared:
  // their statistics are known) with the Foreground mask in `foreground` (MaskBackground).
  // Collective in a split run from AllProcessesReady() on, which they call.
  std::unique_ptr<mcv::FeatureRows> InputArrayRows(vtkImageData* image, std::size_t count, const char*& name);
  // With `model`, the channels, features and normalisation are the model's; `recipe`
  // (optional) receives how the rows were made, for the model a fit writes.
  std::unique_ptr<mcv::FeatureRows> ChannelRows(vtkImageData* image, mcv::ImageGrid grid, const mcv::GridPiece& piece,
    vtkSmartPointer<vtkUnsignedCharArray>& foreground, const mcv::vtkhelpers::ModelFile* model,
    mcv::vtkhelpers::FeatureRecipe* recipe);
  // ModelFile read (again only when the file changed); false after an error (reported).
  bool ReadModelFile();
  // The modification time of the filter and everything upstream (not the data: a new time
  // step re-executes the input without changing it).
  vtkMTimeType PipelineKey();
  // True when this run computes the features from the channels.
  bool UsesChannels(vtkPointData* pd);

  // The steps of RequestMultichannelData, in order; Run holds what one execution has found
  // so far (vtkDimensionReductionInternals.h). Each returns false after an error (reported).
  struct Run;
  bool CheckArguments();
  bool ChooseModel(vtkImageData* image, Run& run);
  bool ReduceRows(vtkImageData* image, Run& run);
  mcv::ReductionOptions RunOptions(vtkPointData* pd, Run& run, mcv::ReductionModel& fittedModel);
  void NewCoordinates(Run& run, mcv::ReductionOptions& options);
  void KeepModel(Run& run, mcv::vtkhelpers::FeatureRecipe recipe, mcv::ReductionModel fittedModel,
    const mcv::ReductionResult& result, const mcv::ReductionOptions& options);
  bool StoreResults(const Run& run);
  void WriteImageOutput(vtkImageData* image, Run& run, vtkImageData* output);
  void WriteSpectrumTable(const Run& run, vtkTable* spectrumTable);
#endif

  struct vtkInternals;
  std::unique_ptr<vtkInternals> Internals;
};

#endif
