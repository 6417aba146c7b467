/**
 * @class   vtkDimensionReduction
 * @brief   reduces per-voxel feature vectors to a 2D/3D domain (PCA, Isomap, LLE, UMAP).
 *
 * Input: a vtkImageData whose point data holds a multi-component array of feature
 * vectors, one tuple per voxel (the `Features` array of MultichannelFeatures by default;
 * select another with SetInputArrayToProcess(0, 0, 0, POINTS, name), the `Features`
 * property in ParaView). A contiguous float32 array is handed to the core without a copy;
 * any other numeric type is converted to float32 once.
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
 * (float32, OutputDimension components named dim1, dim2[, dim3]) and field-data arrays
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
 * Device (vtkMultichannelAlgorithm): where the out-of-sample step runs; GetDeviceUsed says
 * where it ran.
 *
 * Parallel runs (mpiexec pvbatch --mpi, pvserver): each process holds a piece; the
 * column statistics and the reference sample are drawn across all processes and shared
 * (the same sample, hence the same embedding, as one process for the same seed), the fit
 * is shared, and each process places its own voxels. Only piece 0 emits the spectrum
 * table.
 */

#ifndef vtkDimensionReduction_h
#define vtkDimensionReduction_h

#include "mcvFiltersReductionModule.h" // for export macro
#include "vtkMultichannelAlgorithm.h"

#include <cstddef> // for std::size_t
#include <memory>  // for std::unique_ptr

class vtkDoubleArray;
class vtkPointData;

class MCVFILTERSREDUCTION_EXPORT vtkDimensionReduction : public vtkMultichannelAlgorithm
{
public:
  static vtkDimensionReduction* New();
  vtkTypeMacro(vtkDimensionReduction, vtkMultichannelAlgorithm);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  enum MethodType
  {
    PCA = 0,
    ISOMAP = 1,
    LLE = 2,
    UMAP = 3
  };

  ///@{
  /** PCA (default), ISOMAP (landmark Isomap), LLE or UMAP. */
  vtkSetClampMacro(Method, int, PCA, UMAP);
  vtkGetMacro(Method, int);
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
  /** Results of the last execution (empty / zero before the first or after a failure). */
  /** Eigenvalue spectrum as returned by the core (PCA, Isomap: descending). */
  vtkDoubleArray* GetEigenvalueSpectrum();
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
  // Split runs: no ghost layers, every voxel is placed on its own.
  int GetSplitGhostLayers() override { return 0; }

  void ResetResults();

  int Method = PCA;
  int OutputDimension = 3;
  int NumberOfNeighbors = 50;
  int NumberOfLandmarks = 500;
  double MinimumDistance = 0.1;
  int NumberOfEpochs = 0;
  vtkIdType ReferenceSampleSize = 10000;
  int RandomSeed = 0;

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

  struct vtkInternals;
  std::unique_ptr<vtkInternals> Internals;
};

#endif
