/**
 * @class   vtkMergeChannels
 * @brief   Puts the point arrays of several volumes on one grid into one volume, or refuses.
 *
 * ParaView's AppendAttributes (vtkPMergeArrays) takes volumes on different grids without
 * a word about it: it crops a larger channel to the first one's extent, or fails with an
 * update-extent error and drops a channel, depending on the order. A multichannel volume
 * needs every channel on the same voxels, so this filter compares the inputs' grids (whole
 * extent, spacing, origin) first. Equal grids: the arrays are merged as AppendAttributes
 * does (a repeated name gets an "_input_N" suffix). Different grids: an error naming each
 * input that differs from the first (its arrays, voxels, spacing and origin) and what to
 * do, and an empty output.
 */
#ifndef vtkMergeChannels_h
#define vtkMergeChannels_h

#include "mcvFiltersFeaturesModule.h" // for export macro
#include "vtkPMergeArrays.h"

#include <string> // for std::string

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
  void operator=(const vtkMergeChannels&) = delete;

  // True when some input's grid differs from the first one's (set by RequestInformation).
  bool GridsDiffer = false;
  // The error last reported. An empty output never covers the extent asked of it, so the
  // pipeline executes the filter again on every update (the GUI asks 5 times after Apply);
  // the same error is reported once, again only after RequestInformation.
  std::string ReportedError;
};

#endif
