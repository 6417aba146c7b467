/**
 * @class   vtkMultichannelFeatureAlgorithm
 * @brief   base of the filters that compute per-voxel feature vectors from channels.
 *
 * MultichannelFeatures computes the feature vectors; DimensionReduction computes the same
 * vectors itself when its input has none. Both offer the same feature settings, defined
 * here once:
 *
 * - the custom feature toggles (Intensity, Gradient, GradientMagnitude, Laplacian,
 *   LocalMean, LocalVariance), used when FeatureSet is FEATURES_CUSTOM,
 * - Normalization (ZSCORE, MINMAX, NONE),
 * - MaskBackground and BackgroundThreshold (the `Foreground` array).
 *
 * FeatureSet itself stays with each filter: DimensionReduction adds two sources of its
 * own (an input array, or the automatic choice) and has another default. The filters'
 * ServerManager XML shares these properties the same way (FeatureSettings.xml).
 */

#ifndef vtkMultichannelFeatureAlgorithm_h
#define vtkMultichannelFeatureAlgorithm_h

#include "mcvEnumPropertyMacro.h"   // for mcvEnumPropertyMacro
#include "mcvFiltersCommonModule.h" // for export macro
#include "vtkMultichannelAlgorithm.h"

#ifndef __VTK_WRAP__
namespace mcv
{
struct FeatureOptions;
}
#endif

class MCVFILTERSCOMMON_EXPORT vtkMultichannelFeatureAlgorithm : public vtkMultichannelAlgorithm
{
public:
  vtkTypeMacro(vtkMultichannelFeatureAlgorithm, vtkMultichannelAlgorithm);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  /** The feature sets computed from the channels (the core's FeaturePreset). */
  enum FeatureSetType
  {
    FEATURES_6D = 0,
    FEATURES_24D = 1,
    FEATURES_CUSTOM = 2
  };

  ///@{
  /** Features of FEATURES_CUSTOM (defaults: intensity and gradient magnitude). */
  vtkSetMacro(Intensity, bool);
  vtkGetMacro(Intensity, bool);
  vtkSetMacro(Gradient, bool);
  vtkGetMacro(Gradient, bool);
  vtkSetMacro(GradientMagnitude, bool);
  vtkGetMacro(GradientMagnitude, bool);
  vtkSetMacro(Laplacian, bool);
  vtkGetMacro(Laplacian, bool);
  vtkSetMacro(LocalMean, bool);
  vtkGetMacro(LocalMean, bool);
  vtkSetMacro(LocalVariance, bool);
  vtkGetMacro(LocalVariance, bool);
  ///@}

  ///@{
  /** Normalisation of the computed features: ZSCORE (default), MINMAX or NONE. */
  enum NormalizationType
  {
    ZSCORE = 0,
    MINMAX = 1,
    NONE = 2
  };
  mcvEnumPropertyMacro(Normalization, ZSCORE, NONE);
  ///@}

  ///@{
  /**
   * Mark the background (voxels empty in every channel) in the `Foreground` array
   * (default on); DimensionReduction also draws its reference sample from the foreground.
   */
  vtkSetMacro(MaskBackground, bool);
  vtkGetMacro(MaskBackground, bool);
  vtkBooleanMacro(MaskBackground, bool);
  ///@}

  ///@{
  /**
   * A channel is empty at a voxel when its value is <= min + BackgroundThreshold *
   * (max - min) of the channel (default 0: exactly the minimum). In [0, 1].
   */
  vtkSetClampMacro(BackgroundThreshold, double, 0.0, 1.0);
  vtkGetMacro(BackgroundThreshold, double);
  ///@}

protected:
  vtkMultichannelFeatureAlgorithm();
  ~vtkMultichannelFeatureAlgorithm() override;

#ifndef __VTK_WRAP__
  // The toggles and Normalization into the core's options; `preset` is a FeatureSetType.
  void SetFeatureOptions(int preset, mcv::FeatureOptions& options) const;
  // An error naming the toggles when `featureCount` (the core's count) is not positive.
  bool CheckFeatureCount(int featureCount);
  // The image's spacing into `grid`: gradients in world units along the image's own axes
  // (an oriented image's direction matrix rotates them; the features are per axis of the
  // grid, like vtkImageGradient).
  static void SetGridSpacing(vtkImageData* image, mcv::ImageGrid& grid);
#endif

  bool Intensity = true;
  bool Gradient = false;
  bool GradientMagnitude = true;
  bool Laplacian = false;
  bool LocalMean = false;
  bool LocalVariance = false;
  int Normalization = ZSCORE;
  bool MaskBackground = true;
  double BackgroundThreshold = 0.0;

private:
  vtkMultichannelFeatureAlgorithm(const vtkMultichannelFeatureAlgorithm&) = delete;
  void operator=(const vtkMultichannelFeatureAlgorithm&) = delete;
};

#endif
