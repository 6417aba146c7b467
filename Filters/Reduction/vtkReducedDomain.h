/**
 * @class   vtkReducedDomain
 * @brief   the reduced domain of a volume as a point cloud, beside the volume.
 *
 * Input: a vtkImageData (or any dataset) whose point data holds the reduced coordinates
 * (the input array to process, default `ReducedCoordinates`, 2 or 3 components) of
 * DimensionReduction. A seeded uniform sample of SampleSize points (all of them when
 * SampleSize >= the number of points; points with non-finite coordinates are left out)
 * is output as (by piece 0 alone when the output is asked for in pieces, as on an MPI
 * pvserver: the sample is drawn once over the whole volume, the same points for a seed
 * whatever the number of processes; the other pieces are empty):
 *
 * - port 0 `Domain`: vtkPolyData, one vertex per sampled voxel at its reduced
 *   coordinates (z = 0 for 2D), with point arrays `RGBA` (uint8, the colour and opacity
 *   the Gaussian widgets give it: the "Gaussian TF Volume" representation's formula),
 *   `WidgetOpacity` (float), `DisplayColor` (uint8 RGB: the widget colour over light
 *   grey by how strongly the shown widgets select the point, the opacity it would have
 *   if each shown widget's peak opacity were 1), `VoxelId` (the voxel's point id) and
 *   copies of the input's other point arrays (the channel intensities; the coordinates
 *   and `Features` arrays are not copied); and the field array `FocusBounds` (xmin, xmax,
 *   ymin, ymax, zmin, zmax: per axis the sample without the points cut off from the rest
 *   by a gap wider than 5 % of its 5th-95th percentile range, widened to each shown
 *   widget's centre +- sigma), which show_dual_domain frames the view on.
 * - port 1 `Widgets`: vtkPolyData, one vertex per Gaussian widget at its centre, with
 *   `Sigma`, `Diameter` (2 sigma, to scale sphere glyphs; 0 for a hidden widget, peak
 *   opacity 0, whose sphere is then not drawn), `Opacity`, `Color` (RGB float)
 *   and `WidgetIndex`.
 *
 * Automatic widgets: with SeedWidgetCount = n > 0 the filter also clusters the sample's
 * distinct coordinates with k-means (mcv::seedGaussianWidgets; each weighted by the sampled
 * voxels at it in the cluster sizes) and reports n widgets in
 * SeededWidgets (8 values each, the GaussianWidgets layout); the Python helper
 * auto_widgets() copies them to the representation. Distinct coordinates only: voxels with
 * the same feature vector (a uniform background) share one point in the domain and would
 * otherwise pull widgets onto it.
 *
 * Background: when the input has the uint8 point array `Foreground` (MultichannelFeatures'
 * MaskBackground, passed on by DimensionReduction), points whose Foreground is 0 are left
 * out of the sample, hence out of the domain cloud and of the k-means: no widget is seeded
 * on the background. SkipLargestCluster applies only when the input has no Foreground
 * array (the mask already removed the background; the largest foreground cluster is a
 * structure). A Foreground array that marks no point is ignored (warning). Seeded widgets
 * take the suite's palette (mcv::widgetColor: ColorBrewer Set1), sigmas that overlap
 * little, and peak opacities derived from the voxels each selects and the mean length of
 * a ray through the foreground, so that no widget hides what is behind it; a widget that
 * selects more than half of the voxels is flagged to start hidden (GetSeededWidgetDetails;
 * WidgetSeeding.h). With seeding, port 0 also has `SeededWidget` (int): the seeded widget
 * of each sampled point (-1: none).
 */

#ifndef vtkReducedDomain_h
#define vtkReducedDomain_h

#include "mcvFiltersReductionModule.h" // for export macro
#include "mcvPolyDataOutputMacro.h" // for mcvPolyDataOutputMacro
#include "vtkGaussianWidgetsAlgorithm.h"

#include <memory> // for std::unique_ptr
#include <vector> // for std::vector

class vtkDataArray;
class vtkDataSet;
class vtkDoubleArray;
class vtkPointData;

#ifndef __VTK_WRAP__
namespace mcv
{
struct GaussianWidget;
struct WidgetList;
}
#endif

class MCVFILTERSREDUCTION_EXPORT vtkReducedDomain : public vtkGaussianWidgetsAlgorithm
{
public:
  static vtkReducedDomain* New();
  vtkTypeMacro(vtkReducedDomain, vtkGaussianWidgetsAlgorithm);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  /** The output is polydata (mcvPolyDataOutputMacro.h). */
  mcvPolyDataOutputMacro();

  ///@{
  /**
   * Number of sampled voxels (default 20000; >= the number of points: all of them). Below
   * 1 is an error at the next update.
   */
  vtkSetMacro(SampleSize, vtkIdType);
  vtkGetMacro(SampleSize, vtkIdType);
  ///@}

  ///@{
  /** Seed of the sample and of the k-means (same seed, same output). */
  vtkSetMacro(RandomSeed, int);
  vtkGetMacro(RandomSeed, int);
  ///@}

  ///@{
  /**
   * Number of widgets to seed by k-means (0, the default: none). Negative or above 64 is
   * an error at the next update; more than the distinct sampled points seeds one widget
   * per point, with a warning.
   */
  vtkSetMacro(SeedWidgetCount, int);
  vtkGetMacro(SeedWidgetCount, int);
  ///@}

  ///@{
  /**
   * Highest peak opacity of the seeded widgets (default 0.5); each gets less when a ray
   * through the volume crosses many of its voxels (WidgetSeeding.h). NaN is an error, a
   * value outside [0, 1] is clamped with a warning.
   */
  vtkSetMacro(SeedWidgetOpacity, double);
  vtkGetMacro(SeedWidgetOpacity, double);
  ///@}

  ///@{
  /**
   * Leave the largest cluster out of the seeded widgets (default on): count + 1 clusters
   * are made and the largest, almost always the background of a volume, gets no widget.
   * Applies only when the input has no Foreground array (with one, the background is
   * already out of the sample).
   */
  vtkSetMacro(SkipLargestCluster, bool);
  vtkGetMacro(SkipLargestCluster, bool);
  vtkBooleanMacro(SkipLargestCluster, bool);
  ///@}

  /** The seeded widgets of the last execution (8 values each; empty when none). */
  vtkDoubleArray* GetSeededWidgets();

  /**
   * 3 values per seeded widget: its share of the voxels of all seeded widgets' clusters,
   * 1 when it should start hidden (its share exceeds 1/2: the background-sized class
   * around the others), and its mean Gaussian weight over its cluster (WidgetSeeding.h).
   */
  vtkDoubleArray* GetSeededWidgetDetails();

  /**
   * Mean length of a ray through the drawn voxels (the foreground, or every voxel with
   * finite coordinates without a Foreground array) taken as a ball, in ParaView's default
   * Scalar Opacity Unit Distance, from the last update (0 for input that is no image):
   * the L of the seeded opacities (WidgetSeeding.h).
   */
  vtkGetMacro(LastForegroundRayLength, double);

protected:
  vtkReducedDomain();
  ~vtkReducedDomain() override;

  // Not split (GetSplitGhostLayers): every process takes the whole volume, and piece 0
  // alone outputs the sample, drawn over the whole volume (global VoxelIds).
  int RequestMultichannelData(
    vtkInformation*, vtkInformationVector**, vtkInformationVector*) override;

  vtkIdType SampleSize = 20000;
  int RandomSeed = 0;
  int SeedWidgetCount = 0;
  double SeedWidgetOpacity = 0.5;
  bool SkipLargestCluster = true;
  double LastForegroundRayLength = 0;

  // Mean length of a ray through the foreground (`foregroundPoints` voxels taken as a
  // ball) in ParaView's default opacity unit distances; 0 for input that is no image.
  static double ForegroundRayLength(vtkDataSet* input, double foregroundPoints);

private:
  vtkReducedDomain(const vtkReducedDomain&) = delete;
  void operator=(const vtkReducedDomain&) = delete;

#ifndef __VTK_WRAP__
  // The steps of RequestMultichannelData; each returns false (nullptr) after an error,
  // reported. Sample holds what one execution samples (vtkReducedDomain.cxx).
  struct Sample;
  vtkDataArray* FindCoordinates(vtkInformationVector** inputVector, vtkDataSet* input);
  bool DrawSample(vtkDataSet* input, Sample& sample);
  bool MarkEligible(vtkDataSet* input, Sample& sample);
  bool WriteDomain(vtkDataSet* input, const Sample& sample, const mcv::WidgetList& widgets, vtkPolyData* domain);
  bool SeedWidgets(const Sample& sample, const mcv::WidgetList& widgets, vtkPointData* outPD,
    std::vector<mcv::GaussianWidget>& shown);
#endif

  struct vtkInternals;
  std::unique_ptr<vtkInternals> Internals;
};

#endif
