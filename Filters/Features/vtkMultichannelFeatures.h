/**
 * @class   vtkMultichannelFeatures
 * @brief   per-voxel feature vectors of a multichannel volume (input of DimensionReduction).
 *
 * Input: a vtkImageData whose point data holds one or more numeric arrays. Every component
 * of every selected array is a channel (several scalar arrays or one multi-component
 * array). Output: the input (shallow copy) plus a float32 point array `Features` with one
 * component per feature, each named "<channel>.<feature>", e.g. "T1.gradMag". A channel is
 * named after its array ("<array>_<component name or index>" for multi-component arrays).
 *
 * Per channel (see Filters/Core/features/FeatureVectors.h for the exact formulas):
 * intensity; gradient vector gradX/gradY/gradZ (central differences in world units, border
 * replicated); gradient magnitude gradMag; laplacian (6-neighbour Laplacian / 6 in index
 * units: mean of the 6 face neighbours minus the voxel); mean and variance of the 3x3x3
 * neighbourhood (border replicated).
 * FeatureSet: FEATURES_6D = intensity + gradMag per channel (6 for 3 channels),
 * FEATURES_24D = all 8 per channel (24 for 3 channels), FEATURES_CUSTOM = the toggles.
 * Normalization (per column, over voxels finite in every channel): ZSCORE (default),
 * MINMAX (to [0,1]), NONE. Constant columns are left at 0 under ZSCORE/MINMAX (warning);
 * voxels with NaN/Inf in any channel get a feature row of zeros (warning with the count).
 *
 * Background (MaskBackground, default on): a voxel is background when EVERY selected
 * channel is <= min + BackgroundThreshold * (max - min) of that channel (min/max over the
 * whole volume; default threshold 0: the voxels at every channel's minimum, e.g. the zero
 * field of an MRI). The output then also holds the uint8 point array `Foreground`
 * (1 = foreground, 0 = background), which DimensionReduction, ReducedDomain and the
 * "Gaussian TF Volume" representation use to leave the background out. MaskBackground
 * off: no `Foreground` array (one from upstream is removed). A volume that is background
 * everywhere gets an all-0 mask and a warning. Core: Filters/Core/features/BackgroundMask.h.
 *
 * Channel selection (AddChannel/ClearChannels of vtkMultichannelAlgorithm, the `Channels`
 * property in ParaView): the named point arrays; none named: every numeric point array
 * except vtkGhostType, vtkValidPointMask and existing `Features` / `Foreground` arrays.
 *
 * Parallel runs (mpiexec pvbatch --mpi, pvserver): each process asks for its piece plus
 * one ghost layer (the neighbours of the gradient, Laplacian and 3x3x3 statistics),
 * computes its features, and the normalisation uses the column statistics of the whole
 * volume (each voxel counted once, combined across processes through
 * vtkMultiProcessController), so every process writes what one process would. The output
 * is the extent asked of the filter, without the ghost layers.
 */

#ifndef vtkMultichannelFeatures_h
#define vtkMultichannelFeatures_h

#include "mcvEnumPropertyMacro.h"      // for mcvEnumPropertyMacro
#include "mcvFiltersFeaturesModule.h" // for export macro
#include "vtkMultichannelFeatureAlgorithm.h"
#include "vtkSmartPointer.h" // for vtkSmartPointer

class vtkFloatArray;
class vtkUnsignedCharArray;

class MCVFILTERSFEATURES_EXPORT vtkMultichannelFeatures : public vtkMultichannelFeatureAlgorithm
{
public:
  static vtkMultichannelFeatures* New();
  vtkTypeMacro(vtkMultichannelFeatures, vtkMultichannelFeatureAlgorithm);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  ///@{
  /** FEATURES_6D (default), FEATURES_24D or FEATURES_CUSTOM (the toggles of the base). */
  mcvEnumPropertyMacro(FeatureSet, FEATURES_6D, FEATURES_CUSTOM);
  ///@}

  ///@{
  /** Results of the last execution. */
  vtkGetMacro(NumberOfFeatures, int);
  vtkGetMacro(NumberOfNonFiniteVoxels, vtkIdType);
  vtkGetMacro(ComputeTime, double); // milliseconds, core only
  vtkGetMacro(NumberOfBackgroundVoxels, vtkIdType); // whole volume; 0 with MaskBackground off
  ///@}

protected:
  vtkMultichannelFeatures();
  ~vtkMultichannelFeatures() override;

  int RequestInformation(vtkInformation*, vtkInformationVector**, vtkInformationVector*) override;
  int RequestMultichannelData(
    vtkInformation*, vtkInformationVector**, vtkInformationVector*) override;
  // One ghost layer: the neighbours of the gradient, Laplacian and 3x3x3 statistics.
  int GetSplitGhostLayers() override { return 1; }
  // Every numeric point array but ParaView's own and an existing `Features`.
  std::vector<vtkDataArray*> GetDefaultChannels(vtkPointData* pd) override;

  int FeatureSet = FEATURES_6D;

  int NumberOfFeatures = 0;
  vtkIdType NumberOfNonFiniteVoxels = 0;
  double ComputeTime = 0.0;
  vtkIdType NumberOfBackgroundVoxels = 0;

private:
  vtkMultichannelFeatures(const vtkMultichannelFeatures&) = delete;
#ifndef __VTK_WRAP__
  // The steps of RequestMultichannelData: the block's Features array (nullptr after an
  // error, reported) and its Foreground mask (false after an error).
  vtkSmartPointer<vtkFloatArray> ComputeFeatureArray(
    const mcv::vtkhelpers::ChannelArrays& channels, const mcv::ImageGrid& grid, const mcv::GridPiece& piece);
  bool ComputeForegroundMask(const mcv::vtkhelpers::ChannelArrays& channels, const mcv::ImageGrid& grid,
    const mcv::GridPiece& piece, vtkSmartPointer<vtkUnsignedCharArray>& foreground);
#endif
  void operator=(const vtkMultichannelFeatures&) = delete;
};

#endif
