/**
 * @class   vtkBestViewpoint
 * @brief   best (and worst) view direction of a volume from 3D Harris interest points.
 *
 * Input: a vtkImageData whose point data holds one or more scalar arrays. Every component
 * of every selected array is a channel. Each channel is mapped through the opacity
 * function (OpacityFunction, in the channel's data values; when none is set, each
 * channel's own finite range maps linearly to 0..1) and the opacity volume is the maximum
 * over channels. NaN/Inf voxels get opacity 0 (with a warning giving their count).
 *
 * Channel selection (AddChannel/ClearChannels of vtkMultichannelAlgorithm, the `Channels`
 * property in ParaView): the named point arrays, all their components. With no name
 * given: the active point scalars (all components), or, when there are no active
 * scalars, every numeric point array.
 *
 * The work is done by mcv::computeBestViewpoint (Filters/Core, no VTK): Harris response
 * R = det(M) - k tr(M)^3 with M the Gaussian-smoothed gradient tensor, the
 * NumberOfInterestPoints strongest responses, PCA of their world positions. The camera
 * looks along BestViewDirection (v3, least variance); WorstViewDirection is v1; ViewUp is
 * v2 (so the widest spread runs horizontally). Eigenvalues are normalised to sum 1.
 * Method selects the baselines instead (area maximising, viewpoint entropy); they give
 * directions but no interest points.
 *
 * Output: the interest points as vtkPolyData (world positions, one vertex cell each) with
 * point arrays `HarrisScore` (float) and `VoxelIndex` (linear voxel index, x fastest),
 * and field-data copies of the directions. The directions are also available through
 * the getters below (information-only properties in ParaView).
 *
 * In parallel runs (mpiexec pvbatch --mpi, pvserver) with the HarrisPCA method, each
 * process asks for its piece plus 1 + KernelWidth/2 ghost layers (enough for the gradient
 * and the Gaussian), selects the top-N of the voxels it owns, and the lists are merged
 * into the global top-N (vtkMultiProcessController): the result, the same on every
 * process, equals the one-process result. Channel ranges (no OpacityFunction) are global.
 * The baselines (Method) take the whole extent on every process. Only piece 0 emits the
 * interest points.
 */

#ifndef vtkBestViewpoint_h
#define vtkBestViewpoint_h

#include "mcvEnumPropertyMacro.h"      // for mcvEnumPropertyMacro
#include "mcvFiltersViewpointModule.h" // for export macro
#include "mcvPolyDataOutputMacro.h" // for mcvPolyDataOutputMacro
#include "vtkDoubleArray.h" // for vtkDoubleArray ivar
#include "vtkGaussianWidgetsAlgorithm.h"
#include "vtkNew.h" // for vtkNew ivar

#include <string> // for std::string
#include <vector> // for std::vector

class vtkImageData;

class vtkPiecewiseFunction;
namespace mcv
{
struct BestViewpointResult;
struct GridPiece;
struct ImageGrid;
}

class MCVFILTERSVIEWPOINT_EXPORT vtkBestViewpoint : public vtkGaussianWidgetsAlgorithm
{
public:
  static vtkBestViewpoint* New();
  vtkTypeMacro(vtkBestViewpoint, vtkGaussianWidgetsAlgorithm);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  /** The output is polydata (mcvPolyDataOutputMacro.h). */
  mcvPolyDataOutputMacro();

  enum MethodType
  {
    HARRIS_PCA = 0,
    AREA_MAXIMIZING = 1,
    VIEWPOINT_ENTROPY = 2
  };

  enum OpacitySourceType
  {
    OPACITY_CHANNELS = 0,        // channels through OpacityFunction (or their ranges)
    OPACITY_GAUSSIAN_WIDGETS = 1 // the Gaussian TF representation's widget opacity
  };

  ///@{
  /**
   * Opacity transfer function applied to every channel, in data values. nullptr (the
   * default): each channel's own finite range mapped linearly to 0..1.
   */
  void SetOpacityFunction(vtkPiecewiseFunction* function);
  vtkGetObjectMacro(OpacityFunction, vtkPiecewiseFunction);
  ///@}

  ///@{
  /**
   * Where the opacity volume comes from: OPACITY_CHANNELS (default; Channels through
   * OpacityFunction) or OPACITY_GAUSSIAN_WIDGETS: the opacity
   * 1 - prod_i (1 - a_i exp(-|x - mu_i|^2 / (2 sigma_i^2))) of the Gaussian widgets at each
   * voxel's coordinates (the point array WidgetCoordinates, 2 or 3 components), the same
   * opacity the "Gaussian TF Volume" representation renders; 0 where the input's uint8
   * point array `Foreground` (MultichannelFeatures' background mask) is 0.
   */
  mcvEnumPropertyMacro(OpacitySource, OPACITY_CHANNELS, OPACITY_GAUSSIAN_WIDGETS);
  ///@}

  ///@{
  /** Point array with the widgets' coordinates (default "ReducedCoordinates"). */
  vtkSetStringMacro(WidgetCoordinates);
  vtkGetStringMacro(WidgetCoordinates);
  ///@}

  ///@{
  /** Number N of strongest Harris responses kept as interest points (> 0; default 2048). */
  vtkSetMacro(NumberOfInterestPoints, int);
  vtkGetMacro(NumberOfInterestPoints, int);
  ///@}

  ///@{
  /** Standard deviation of the Gaussian that smooths the gradient tensor, in voxels. */
  vtkSetMacro(GaussianSigma, double);
  vtkGetMacro(GaussianSigma, double);
  ///@}

  ///@{
  /** Taps per axis of the separable Gaussian (odd; default 5). */
  vtkSetMacro(KernelWidth, int);
  vtkGetMacro(KernelWidth, int);
  ///@}

  ///@{
  /** Harris sensitivity k in R = det(M) - k tr(M)^3 (default 0.004). */
  vtkSetMacro(HarrisK, double);
  vtkGetMacro(HarrisK, double);
  ///@}

  ///@{
  /** HARRIS_PCA (default), AREA_MAXIMIZING or VIEWPOINT_ENTROPY. */
  mcvEnumPropertyMacro(Method, HARRIS_PCA, VIEWPOINT_ENTROPY);
  ///@}

  ///@{
  /** Viewpoint entropy baseline: number of sphere samples (default 400). */
  vtkSetMacro(EntropySamples, int);
  vtkGetMacro(EntropySamples, int);
  ///@}

  ///@{
  /** Viewpoint entropy baseline: side of the square opacity images (default 128). */
  vtkSetMacro(EntropyImageSize, int);
  vtkGetMacro(EntropyImageSize, int);
  ///@}

  ///@{
  /** Results of the last execution (zeros when no direction could be found). */
  vtkGetVector3Macro(BestViewDirection, double);
  vtkGetVector3Macro(WorstViewDirection, double);
  vtkGetVector3Macro(ViewUp, double);
  vtkGetVector3Macro(EigenvalueSpectrum, double);
  /** Mean of the interest points (HarrisPCA) or centre of the method's estimate. */
  vtkGetVector3Macro(ViewCenter, double);
  /** Centre of the input's bounds (world coordinates). */
  vtkGetVector3Macro(DataCenter, double);
  /**
   * Bounds (xmin, xmax, ymin, ymax, zmin, zmax, world coordinates) of the voxels whose
   * opacity is at least kVisibleOpacity (1 %): what the picture shows, which the helpers
   * fit the camera to. The input's bounds when no voxel is that opaque.
   */
  vtkGetVector6Macro(VisibleBounds, double);
  /**
   * Support points of the same voxels (3 components): for each of 128 directions spread
   * over the sphere, the visible voxel furthest along it (world position). Their hull is
   * within ~1 % of the visible voxels' hull from any direction, so the helpers fit the
   * camera to the picture's silhouette, not to a box. Empty when no voxel is visible.
   */
  vtkDoubleArray* GetVisibleSupport() { return this->VisibleSupport; }
  static constexpr float kVisibleOpacity = 0.01f;
  /** 1 when the directions are meaningful, 0 (with a warning) otherwise. */
  vtkGetMacro(ViewValid, int);
  /** Number of interest points found (HarrisPCA). */
  vtkGetMacro(NumberOfPointsFound, int);
  /**
   * Voxels with a NaN or Inf value in a selected channel (opacity 0), in the whole volume:
   * a run split over processes counts each voxel once.
   */
  vtkGetMacro(NumberOfNonFiniteVoxels, vtkIdType);
  /** Milliseconds: Harris, top-N selection, PCA, total (core timings). */
  vtkGetVector4Macro(StageTimings, double);
  ///@}

  /** Includes the opacity function's modification time. */
  vtkMTimeType GetMTime() override;

protected:
  vtkBestViewpoint();
  ~vtkBestViewpoint() override;

  int RequestMultichannelData(
    vtkInformation*, vtkInformationVector**, vtkInformationVector*) override;
  // Only HarrisPCA runs split: ghost layers for the gradient (1) and the Gaussian
  // (KernelWidth/2). The baselines take the whole volume.
  int GetSplitGhostLayers() override;
  // The active point scalars, else every numeric point array.
  std::vector<vtkDataArray*> GetDefaultChannels(vtkPointData* pd) override;

  void ResetResults();

#ifndef __VTK_WRAP__
  // The steps of RequestMultichannelData. WorldFrame: the image's index frame -> world.
  struct WorldFrame;
  // The input image, its grid and the block of it this process holds, once the arguments
  // and the memory needed are checked; nullptr after an error was reported.
  vtkImageData* CheckArguments(
    vtkInformationVector** inputVector, mcv::ImageGrid& grid, mcv::GridPiece& block);
  // The grid's spacing and origin in the image's index frame (a negative spacing flips
  // that axis of the frame), the frame itself and DataCenter, the whole volume's centre.
  void PlaceGrid(
    vtkImageData* image, mcv::ImageGrid& grid, const mcv::GridPiece& block, WorldFrame& frame);
  // VisibleBounds and VisibleSupport from the opacity volume, over every process.
  void ComputeVisibleShape(const std::vector<float>& opacity, const mcv::ImageGrid& grid,
    const mcv::GridPiece& block, const WorldFrame& frame);
  // The core on the opacity volume; the view directions, centre and timings kept in world
  // coordinates. False after an error was reported.
  bool ComputeView(const std::vector<float>& opacity, const mcv::ImageGrid& grid,
    const mcv::GridPiece& block, const WorldFrame& frame, mcv::BestViewpointResult& result);
  // Output: the interest points (piece 0 only) and the view as field data.
  void WriteOutput(vtkInformationVector* outputVector, const mcv::BestViewpointResult& result,
    const WorldFrame& frame, vtkPolyData* output);
#endif
  // The opacity volume (count floats) from the channels or from the widgets; false after
  // an error was reported.
  bool ComputeChannelOpacity(vtkImageData* image, const mcv::ImageGrid& grid,
    const mcv::GridPiece& block, std::vector<float>& opacity);
  bool ComputeWidgetOpacity(vtkImageData* image, const mcv::ImageGrid& grid,
    const mcv::GridPiece& block, std::vector<float>& opacity);
  // A warning when fewer than 27 voxels of the volume get 1% opacity (lows/highs: the
  // channels' ranges that the default ramps span, when defaultRamps).
  void WarnIfFewVisibleVoxels(const mcv::ImageGrid& grid, const mcv::GridPiece& block,
    const std::vector<float>& opacity, bool defaultRamps,
    const std::vector<std::string>& channelNames, const std::vector<double>& lows,
    const std::vector<double>& highs);

  vtkPiecewiseFunction* OpacityFunction = nullptr;
  int NumberOfInterestPoints = 2048;
  double GaussianSigma = 1.5;
  int KernelWidth = 5;
  double HarrisK = 0.004;
  int Method = HARRIS_PCA;
  int EntropySamples = 400;
  int EntropyImageSize = 128;
  int OpacitySource = OPACITY_CHANNELS;
  char* WidgetCoordinates = nullptr;

  double BestViewDirection[3] = { 0, 0, 0 };
  double WorstViewDirection[3] = { 0, 0, 0 };
  double ViewUp[3] = { 0, 0, 0 };
  double EigenvalueSpectrum[3] = { 0, 0, 0 };
  double ViewCenter[3] = { 0, 0, 0 };
  double DataCenter[3] = { 0, 0, 0 };
  double VisibleBounds[6] = { 0, 0, 0, 0, 0, 0 };
  vtkNew<vtkDoubleArray> VisibleSupport;
  int ViewValid = 0;
  int NumberOfPointsFound = 0;
  vtkIdType NumberOfNonFiniteVoxels = 0;
  double StageTimings[4] = { 0, 0, 0, 0 };

private:
  vtkBestViewpoint(const vtkBestViewpoint&) = delete;
  void operator=(const vtkBestViewpoint&) = delete;
};

#endif
