/**
 * @class   vtkGaussianTFVolumeRepresentation
 * @brief   volume rendering of vtkImageData through Gaussian widgets in a reduced domain.
 *
 * The ParaView representation "Gaussian TF Volume" (dissertation chapter 5). Every voxel
 * has 2D or 3D coordinates in a reduced domain (the point array `ReducedCoordinates` of
 * DimensionReduction by default, see SetCoordinateArray). A list of Gaussian widgets,
 * each (centre, sigma, RGB colour, peak opacity), gives every voxel
 *   alpha_i(x) = a_i * exp(-|x - mu_i|^2 / (2 sigma_i^2))
 *   opacity(x) = 1 - prod_i (1 - alpha_i(x))
 *   colour(x)  = sum_i alpha_i(x) c_i / sum_i alpha_i(x)
 * Two ways to classify (property Classification):
 * - Per sample (default): the coordinates are uploaded once as a 16-bit RGBA texture
 *   (x, y, z, drawn; mcv::quantizeCoordinates) and the GPU ray caster's fragment shader
 *   classifies every interpolated ray sample (mcvGaussianTFShader.h): thin structures
 *   between voxels stay sharp and no colour bleeds across boundaries. The shader
 *   evaluates every widget at every sample (exact, one exp per widget, the default), or
 *   reads the widgets baked into a 3D table over the reduced domain (PerSampleEvaluation
 *   Baked table: one trilinear fetch per sample, the table re-baked on the CPU at each
 *   widget edit, mcvGaussianTFTable.h; exact where a widget is narrower than the largest
 *   table resolves). Opacity is per unit length (the volume's Scalar Opacity Unit Distance),
 *   corrected for the sample distance; rays are jittered (property Jittering).
 * - Per voxel: the VTK-free core (mcv::applyGaussianWidgets, CPU or CUDA) computes a uint8
 *   RGBA point array `GaussianTF_RGBA` that the ray caster interpolates as dependent
 *   components (pre-classification). Any number of widgets; colours on the CPU or CUDA.
 * Both need VTK's GPU ray caster (Volume Rendering Mode Smart or GPU Based): with another
 * mode the representation reports an error and draws nothing.
 * Voxels whose mask array (MaskArray, `Foreground` of MultichannelFeatures by default) is
 * 0, and voxels with non-finite coordinates, are transparent in both.
 *
 * Cheap widget edits: setting widgets, the coordinate array or the device does not mark
 * the representation modified (no re-execution, no re-delivery of the volume); the RGBA
 * array of the delivered volume is recomputed in place at the next render. New data (a
 * new delivered volume or a modified coordinate array) is recomputed too.
 *
 * Colours are not stretched: the ray caster maps each component's own data range onto
 * [0, 1] before using it as a colour (vtkVolumeTexture), so the cached range of every
 * RGBA component is anchored to the byte range [0, 255] after each computation.
 *
 * Errors (vtkErrorMacro, nothing is drawn): the coordinate array is missing, not numeric
 * or has a number of components other than 2 or 3; a widget list whose length is not a
 * multiple of 8, a non-finite value or sigma <= 0. Warnings (vtkWarningMacro, still
 * drawn): colours or opacity outside [0, 1] (clamped), a list emptied of its widgets (a
 * transparent volume; a representation that never had widgets says nothing),
 * a GPU request that falls back to the CPU. Each is reported once per change, not per
 * frame.
 */

#ifndef vtkGaussianTFVolumeRepresentation_h
#define vtkGaussianTFVolumeRepresentation_h

#include "mcvGaussianWidgetValuesMacro.h"       // for mcvGaussianWidgetValuesMacro
#include "mcvRepresentationsGaussianTFModule.h" // for export macro
#include "vtkImageVolumeRepresentation.h"
#include "vtkMultichannelAlgorithm.h" // for the DeviceType values the filters share

#include <memory> // for std::unique_ptr
#include <vector> // for the pieces whose shares are counted

class vtkImageData;
class vtkPVSession;
namespace mcv
{
struct WidgetList;
}

class MCVREPRESENTATIONSGAUSSIANTF_EXPORT vtkGaussianTFVolumeRepresentation
  : public vtkImageVolumeRepresentation
{
public:
  static vtkGaussianTFVolumeRepresentation* New();
  vtkTypeMacro(vtkGaussianTFVolumeRepresentation, vtkImageVolumeRepresentation);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  /**
   * The widgets, the ParaView property `GaussianWidgets` (mcvGaussianWidgetValuesMacro.h).
   * A change is seen at the next render, which checks the list; it does not re-execute.
   */
  mcvGaussianWidgetValuesMacro();

  ///@{
  /**
   * The widgets' names, one per widget in the order of the widget list (the ParaView
   * property `GaussianWidgetNames`, set by clearing then adding each name). A widget
   * without a name (the list is shorter) is "Widget N" in the legend.
   */
  void ClearGaussianWidgetNames();
  void AddGaussianWidgetName(const char* name);
  int GetNumberOfGaussianWidgetNames();
  const char* GetGaussianWidgetName(int index);
  ///@}

  ///@{
  /**
   * Show the widget legend in the view's top right corner (default on; hidden while the
   * volume is drawn as nothing after an error): one row per drawn widget
   * (peak opacity above 0): its colour, its name and the share of the voxels it
   * selects, i.e. of the drawn voxels (mask non-zero, finite coordinates) within its
   * half maximum (|x - mu| <= sigma sqrt(2 ln 2), where alpha_i >= a_i / 2), counted on
   * at most 10^6 voxels evenly spread over the volume. Each process counts its own piece
   * and the counts are summed over the session's processes (ProcessViewRequest), so a
   * split run and the client of a pvserver (which holds no voxels and draws the legend
   * over the server's image) show the whole volume's shares.
   */
  void SetShowWidgetLegend(bool show);
  vtkGetMacro(ShowWidgetLegend, bool);
  ///@}

  /**
   * The share of the voxels each widget selects (see SetShowWidgetLegend), from the last
   * view update that counted it; empty before it, or when no process holds a voxel.
   */
  int GetNumberOfWidgetShares();
  double GetWidgetShare(int index);

  /** The legend's rows as shown, one per line ("" when it shows none). */
  const char* GetWidgetLegendText();

  /** Hides the legend with the volume. */
  void SetVisibility(bool visible) override;

  ///@{
  /** Name of the point array of reduced coordinates (2 or 3 components). */
  void SetCoordinateArray(const char* name);
  const char* GetCoordinateArray();
  ///@}

  ///@{
  /**
   * PER_SAMPLE (default): the widgets are evaluated in the ray caster's shader at every
   * sample. PER_VOXEL: an RGBA array per voxel (CPU or CUDA, see Device).
   */
  enum ClassificationType
  {
    PER_SAMPLE = 0,
    PER_VOXEL = 1
  };
  void SetClassification(int mode);
  vtkGetMacro(Classification, int);
  ///@}

  ///@{
  /**
   * Per sample: start every ray a pseudo-random fraction of a sample step further in, so
   * that no wood-grain banding shows (default on).
   */
  void SetJittering(bool jittering);
  vtkGetMacro(Jittering, bool);
  ///@}

  ///@{
  /**
   * Per sample: split the volume into bricks of 8^3 voxels and list, for each, the widgets
   * that can reach the reduced coordinates of its voxels (mcvGaussianTFBricks.h); the
   * shader evaluates only those, and steps over a brick that none reaches (masked
   * background, or coordinates far from every widget) in whole sample steps. The widgets
   * left out add less than 1e-6 opacity per unit length to a sample (the picture is the
   * same within 1/255 on the brain). SKIPPING_OFF: every widget at every sample (the
   * un-culled loop). SKIPPING_ON: always the bricks. SKIPPING_AUTOMATIC (default): the
   * bricks only with the exact evaluation and where a sample of a reached brick evaluates
   * at most AutomaticSkippingShare of the widgets on average: on Mesa llvmpipe the brick
   * look-up at every sample costs more than it saves when every reached brick lists every
   * widget (1 and 8 widgets seeded on the brain), saves about a quarter of the frame where
   * the bricks list 59 % of 64 widgets (the 7.1 M-voxel brain) and is as likely to cost
   * as to save at 64 % (its 1 M-voxel block): docs/benchmarks.md section 20. Volumes of
   * one piece per process only.
   */
  enum EmptySpaceSkippingType
  {
    SKIPPING_OFF = 0,
    SKIPPING_ON = 1,
    SKIPPING_AUTOMATIC = 2
  };
  void SetEmptySpaceSkipping(int skipping);
  vtkGetMacro(EmptySpaceSkipping, int);
  ///@}

  /**
   * SKIPPING_AUTOMATIC uses the bricks when a sample of a reached brick evaluates at most
   * this share of the widgets on average (GetMeanWidgetsPerBrick over the widget count).
   */
  static constexpr double AutomaticSkippingShare = 0.6;

  /**
   * Whether the last render's shader used the widget table (EmptySpaceSkipping on, or
   * automatic and chosen).
   */
  vtkGetMacro(SkippingUsed, bool);

  ///@{
  /**
   * The bricks of the last widget table built (EmptySpaceSkipping on, or automatic: also
   * when it chose every widget instead): all of them, those no widget reaches, and the
   * mean number of widgets a sample of a reached brick evaluates (its list, or every
   * widget where most reach it); 0 without a table.
   */
  vtkGetMacro(NumberOfBricks, int);
  vtkGetMacro(NumberOfEmptyBricks, int);
  vtkGetMacro(MeanWidgetsPerBrick, double);
  ///@}

  ///@{
  /**
   * Per sample: EVALUATE_TABLE bakes the widgets into a 3D table over the
   * reduced domain (mcvGaussianTFTable.h: 3 intervals per sigma of the narrowest widget
   * on every axis, at most 512 nodes per axis and 2^23 in all) that the shader reads with one
   * trilinear fetch per sample; when a widget is too narrow for that table, every widget
   * is evaluated instead (GetEvaluationUsed says which). EVALUATE_EXACT (default): every
   * widget at every sample (one exp each), the formula itself. The table is not the
   * default: near a peak opacity of 1 its interpolation error changes the picture (up to
   * 37/255 on the brain), a widget edit bakes it (about 0.35 s for 6.6 M nodes), and with
   * one widget it is slower than the loop (docs/benchmarks.md section 20).
   */
  enum PerSampleEvaluationType
  {
    EVALUATE_TABLE = 0,
    EVALUATE_EXACT = 1
  };
  void SetPerSampleEvaluation(int evaluation);
  vtkGetMacro(PerSampleEvaluation, int);
  ///@}

  /**
   * How the last per-sample update classifies: "table NXxNYxNZ" (the baked table's node
   * counts), "exact" (requested), or "exact: " and why no table could be used; "" before
   * the first one.
   */
  const char* GetEvaluationUsed();

  ///@{
  /**
   * Point array whose zero values mark voxels that are never drawn (uint8 or any numeric
   * type; default `Foreground`, the background mask of MultichannelFeatures). A name that
   * is not an array of the input masks nothing.
   */
  void SetMaskArray(const char* name);
  const char* GetMaskArray();
  ///@}

  ///@{
  /**
   * Where the per-voxel RGBA computation runs: vtkMultichannelAlgorithm::DEVICE_AUTO (default),
   * DEVICE_CPU or DEVICE_GPU, as the filters' Device.
   */
  void SetDevice(int device);
  vtkGetMacro(Device, int);
  ///@}

  /**
   * ParaView's Volume Rendering Mode, forwarded to the volume mapper; remembered because
   * the representation needs the GPU ray caster (Default or GPU).
   */
  void SetRequestedRenderMode(int mode);

  ///@{
  /**
   * Blend mode of this representation, applied at every render in place of the volume
   * representation's BlendMode (whose ParaView 5.11 choices lack maximum intensity):
   * vtkVolumeMapper::COMPOSITE_BLEND (default) or MAXIMUM_INTENSITY_BLEND (colour of the
   * most opaque sample along each ray).
   */
  void SetGaussianBlendMode(int mode);
  vtkGetMacro(GaussianBlendMode, int);
  ///@}

  /**
   * Where the last classification ran: "CPU" or "GPU" (per voxel), "OpenGL" (per sample);
   * "" before the first one.
   */
  const char* GetDeviceUsed();

  /** True when the last computation succeeded (the volume is drawn). */
  int GetRGBAValid();

  /**
   * How many times the classification was updated: the RGBA array computed (per voxel) or
   * the widget uniforms set (per sample). Tests: a widget edit updates once.
   */
  vtkGetMacro(NumberOfComputations, int);

  /** How many times the data was (re-)executed and delivered (tests: widget edits do not). */
  vtkGetMacro(NumberOfDataUpdates, int);

  /** How many times the per-sample coordinate texture was built (data changes only). */
  vtkGetMacro(NumberOfTextureBuilds, int);

  /**
   * Seconds the last render that updated the classification spent preparing it in this
   * representation (building the texture or the RGBA array, setting uniforms): the work a
   * widget edit costs before the ray caster runs.
   */
  vtkGetMacro(LastPreparationSeconds, double);

  /** Name of the RGBA point array added to the delivered volume (per voxel). */
  static const char* GetRGBAArrayName() { return "GaussianTF_RGBA"; }

  /** Name of the 16-bit coordinate texture array added to the delivered volume (per sample). */
  static const char* GetTextureArrayName() { return "GaussianTF_Coordinates"; }

  /**
   * On REQUEST_UPDATE (every process of the view's session, also one without voxels),
   * counts the legend's shares on this process's piece and sums them over the session's
   * processes (those of a split run and a pvserver's client), so that every process,
   * the one that draws the legend included, holds the whole volume's shares.
   */
  int ProcessViewRequest(vtkInformationRequestKey* request, vtkInformation* inInfo,
    vtkInformation* outInfo) override;

  ///@{
  /** The legend goes into the view's non-composited (annotation) renderer. */
  bool AddToView(vtkView* view) override;
  bool RemoveFromView(vtkView* view) override;
  ///@}

protected:
  vtkGaussianTFVolumeRepresentation();
  ~vtkGaussianTFVolumeRepresentation() override;

  int FillInputPortInformation(int port, vtkInformation* info) override;
  int RequestData(vtkInformation*, vtkInformationVector**, vtkInformationVector*) override;

  // Recomputes RGBA when needed, then points the mapper at it as dependent components.
  void UpdateMapperParameters() override;

private:
  vtkGaussianTFVolumeRepresentation(const vtkGaussianTFVolumeRepresentation&) = delete;
  void operator=(const vtkGaussianTFVolumeRepresentation&) = delete;

  // Both return false (after an error) when nothing can be drawn.
  bool UpdateRGBA();
  bool UpdatePerSample();
  bool GPURayCasterRequested();
  void ReportWidgetWarnings(const mcv::WidgetList& widgets);
  // Each widget's share of the voxels of `pieces` (whole: the volume's whole extent, or
  // empty), summed over the processes of `session` (a collective call: every process of
  // it makes it; see mcv::gaussiantf::sumOverSession).
  void UpdateWidgetShares(
    const std::vector<vtkImageData*>& pieces, const int whole[6], vtkPVSession* session);
  void UpdateLegend();

  bool ShowWidgetLegend = true;

  int Classification = PER_SAMPLE;
  int RequestedRenderMode = 0;
  bool Jittering = true;
  int EmptySpaceSkipping = SKIPPING_AUTOMATIC;
  bool SkippingUsed = false;
  int PerSampleEvaluation = EVALUATE_EXACT;
  int NumberOfBricks = 0;
  int NumberOfEmptyBricks = 0;
  double MeanWidgetsPerBrick = 0;
  int NumberOfTextureBuilds = 0;
  double LastPreparationSeconds = 0;
  int Device = vtkMultichannelAlgorithm::DEVICE_AUTO;
  int GaussianBlendMode = 0;
  int NumberOfComputations = 0;
  int NumberOfDataUpdates = 0;

  struct vtkInternals;
  std::unique_ptr<vtkInternals> Internals;
};

#endif
