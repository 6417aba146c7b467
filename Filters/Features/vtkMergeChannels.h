/**
 * @class   vtkMergeChannels
 * @brief   Puts the point arrays of several volumes on one grid into one volume, or refuses.
 *
 * ParaView's AppendAttributes (vtkPMergeArrays) takes volumes on different grids without
 * a word about it: it crops a larger channel to the first one's extent, or fails with an
 * update-extent error and drops a channel, depending on the order. A multichannel volume
 * needs every channel on the same voxels, so this filter compares the inputs' grids (whole
 * extent, spacing, origin) first. Equal grids: the point arrays of all inputs, in input
 * order, each named after its channel: an array with a name its reader gives every file
 * ("NIFTI", "MetaImage", "Tiff Scalars", "ImageFile", ...; mcvFileNames.h) is named after
 * the file it was read from ("ch2" for ch2.nii.gz: the reader upstream of the input), any
 * other keeps its name (the plugin's readers already name their array after the file; a
 * multichannel file's arrays keep their channel labels). Names are made unique with "_2",
 * "_3", ... (two files ch2.nii.gz in two folders give "ch2" and "ch2_2"). vtkGhostType
 * and vtkValidPointMask are kept once, as they are. Different grids: an error naming each
 * input that differs from the first (its file, arrays, voxels, spacing and origin) and
 * what to do, and an empty output.
 */
#ifndef vtkMergeChannels_h
#define vtkMergeChannels_h

#include "mcvFiltersFeaturesModule.h" // for export macro
#include "vtkPMergeArrays.h"

#include <string> // for std::string

class vtkDataSet;

class MCVFILTERSFEATURES_EXPORT vtkMergeChannels : public vtkPMergeArrays
{
public:
  static vtkMergeChannels* New();
  vtkTypeMacro(vtkMergeChannels, vtkPMergeArrays);

protected:
  vtkMergeChannels() = default;
  ~vtkMergeChannels() override = default;

  int FillInputPortInformation(int port, vtkInformation* info) override;
  int RequestInformation(vtkInformation* request, vtkInformationVector** inputVector,
    vtkInformationVector* outputVector) override;
  int RequestUpdateExtent(vtkInformation* request, vtkInformationVector** inputVector,
    vtkInformationVector* outputVector) override;
  int RequestData(vtkInformation* request, vtkInformationVector** inputVector,
    vtkInformationVector* outputVector) override;

private:
  vtkMergeChannels(const vtkMergeChannels&) = delete;
  // Replaces the merged point arrays of `output` by those of every input, named after
  // their channels (see the class documentation).
  void NameChannels(vtkInformationVector* inputs, vtkDataSet* output);
  void operator=(const vtkMergeChannels&) = delete;

  // True when some input's grid differs from the first one's (set by RequestInformation).
  bool GridsDiffer = false;
  // The error last reported. An empty output never covers the extent asked of it, so the
  // pipeline executes the filter again on every update (the GUI asks 5 times after Apply);
  // the same error is reported once, again only after RequestInformation.
  std::string ReportedError;
};

#endif
