/**
 * @class   vtkMultichannelAlgorithm
 * @brief   base of the suite's filters: channels, Device, split runs, progress.
 *
 * The filters of the suite (MultichannelFeatures, DimensionReduction, BestViewpoint,
 * ReducedDomain) read image data and hand it to the VTK-free core (Filters/Core). What
 * they share lives here, once:
 *
 * - the `Channels` property (AddChannel/ClearChannels) and its resolution into the core's
 *   channels (SelectChannels; GetDefaultChannels when no array is named),
 * - the `Device` property (DEVICE_AUTO, DEVICE_CPU, DEVICE_GPU) and the device the last
 *   execution ran on (GetDeviceUsed),
 * - runs split over processes (mpiexec pvbatch --mpi, pvserver): the piece each process
 *   asks of its input, with GetSplitGhostLayers() ghost layers (mcvPieces.h), the
 *   communicator of the core, and AllProcessesReady(), the vote that keeps the processes
 *   together when one of them fails its checks,
 * - the checks of the input image, progress callbacks for the core (which also carry an
 *   abort requested through AbortExecute into the core), and the reporting of the core's
 *   messages (memory checks, errors, warnings).
 *
 * The input port takes any vtkDataSet, so that other data gets the filter's own error
 * message rather than the pipeline's. The output is image data unless a filter says
 * otherwise in FillOutputPortInformation: BestViewpoint and ReducedDomain make polydata
 * but derive from here too, so that ParaView's wrapping inherits the shared property
 * methods from one class. Filters implement RequestMultichannelData in place of
 * RequestData. Which properties a filter offers is up to its ServerManager XML.
 */

#ifndef vtkMultichannelAlgorithm_h
#define vtkMultichannelAlgorithm_h

#include "mcvEnumPropertyMacro.h"   // for mcvEnumPropertyMacro
#include "mcvFiltersCommonModule.h" // for export macro
#include "vtkImageAlgorithm.h"
#include "vtkSmartPointer.h" // for vtkSmartPointer

#include <cstddef>    // for std::size_t
#include <functional> // for std::function
#include <memory>     // for std::unique_ptr
#include <string>     // for std::string
#include <vector>     // for std::vector

class vtkDataArray;
class vtkImageData;
class vtkPointData;

#ifndef __VTK_WRAP__
namespace mcv
{
class Communicator;
enum class Device;
struct GridPiece;
struct ImageGrid;
namespace vtkhelpers
{
struct ChannelArrays;
struct PieceLayout;
}
}
#endif

class MCVFILTERSCOMMON_EXPORT vtkMultichannelAlgorithm : public vtkImageAlgorithm
{
public:
  vtkTypeMacro(vtkMultichannelAlgorithm, vtkImageAlgorithm);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  ///@{
  /**
   * Point arrays used as channels, in order (all components of each). None named: what
   * GetDefaultChannels picks.
   */
  void AddChannel(const char* arrayName);
  void ClearChannels();
  int GetNumberOfChannels();
  const char* GetChannel(int index);
  ///@}

  ///@{
  /** DEVICE_AUTO (default), DEVICE_CPU or DEVICE_GPU (falls back to the CPU, warning). */
  enum DeviceType
  {
    DEVICE_AUTO = 0,
    DEVICE_CPU = 1,
    DEVICE_GPU = 2
  };
  mcvEnumPropertyMacro(Device, DEVICE_AUTO, DEVICE_GPU);
  ///@}

  /** "CPU" or "GPU": where the last execution ran ("CPU" before the first one). */
  const char* GetDeviceUsed();

protected:
  vtkMultichannelAlgorithm();
  ~vtkMultichannelAlgorithm() override;

  int FillInputPortInformation(int port, vtkInformation* info) override;
  int RequestInformation(vtkInformation*, vtkInformationVector**, vtkInformationVector*) override;
  int RequestUpdateExtent(vtkInformation*, vtkInformationVector**, vtkInformationVector*) override;
  // Sets up the run (its piece, communicator and vote), then RequestMultichannelData.
  int RequestData(vtkInformation*, vtkInformationVector**, vtkInformationVector*) override;
  // The active-scalar information describes image outputs only.
  void CopyInputArrayAttributesToOutput(
    vtkInformation*, vtkInformationVector**, vtkInformationVector*) override;

  // The filter's RequestData. Every return before AllProcessesReady() votes "failed".
  virtual int RequestMultichannelData(
    vtkInformation*, vtkInformationVector**, vtkInformationVector*) = 0;

  // Ghost layers a split run asks of the input around this process's piece. Negative (the
  // default): the filter is not split; every process takes the whole volume.
  virtual int GetSplitGhostLayers() { return -1; }

  // The channels when none is named: every numeric point array but ParaView's own.
  virtual std::vector<vtkDataArray*> GetDefaultChannels(vtkPointData* pd);

  // Reports a non-empty message as the filter's error; returns whether it did.
  bool ReportError(const std::string& message);
  // Reports each non-empty message as a warning of the filter.
  void ReportWarnings(const std::vector<std::string>& warnings);

  // In RequestMultichannelData, where every process has passed its local checks: true
  // when all have (always in a serial run); false, reported, otherwise. Call it once.
  bool AllProcessesReady();

  // The input as image data, or nullptr after an error that ends "<label> needs a
  // vtkImageData <requirement>".
  vtkImageData* GetInputImage(vtkInformationVector** inputVector, const char* requirement);

  // The extent the image output holds: in a split run the extent asked of it, within the
  // block the input delivered (as vtkImageData::Crop clips it), so not the ghost layers;
  // otherwise the block's own extent.
  void GetOutputExtent(vtkImageData* block, vtkInformationVector* outputVector, int extent[6]);

  // `output` := `input` at `extent` (within the input's extent): geometry, field data, point
  // and cell arrays, but for the point arrays named in `leaveOut`. Shared when the extents
  // are equal; otherwise copies of the extent, made while the input keeps its own. The
  // filter's own block-sized arrays go through CropPointArray one at a time instead, so no
  // moment holds every array twice (ShallowCopy then Crop did: docs/benchmarks.md §7.2).
  void PassInputAtExtent(vtkImageData* input, const int extent[6], vtkImageData* output,
    const std::vector<std::string>& leaveOut);

  // `array` (one tuple per voxel of extent `from`) cut to `to` (within `from`): a new array
  // of `to`'s voxels, or `array` itself when the extents are equal.
  static vtkSmartPointer<vtkDataArray> CropPointArray(
    vtkDataArray* array, const int from[6], const int to[6]);

// The core's types stay out of the wrappers' view.
#ifndef __VTK_WRAP__
  // This process's piece of a split run (IsSplit() false otherwise) and its communicator
  // (nullptr unless split); valid in RequestMultichannelData.
  const mcv::vtkhelpers::PieceLayout& GetPieceLayout() const;
  const mcv::Communicator* GetCommunicator() const;

  // The voxel counts of `image` (grid.dims; spacing and origin are the filter's) and where
  // the block lies in the whole volume; false after an error (empty extent, a block that
  // misses voxels of this process).
  bool GetImageBlock(vtkImageData* image, mcv::ImageGrid& grid, mcv::GridPiece& piece);

  // The selected channels of `image` (count voxels) as the core reads them; false after
  // an error (no such array, not numeric, wrong length, nothing to select).
  bool SelectChannels(
    vtkImageData* image, std::size_t count, mcv::vtkhelpers::ChannelArrays& channels);

  mcv::Device GetRequestedDevice() const;
  void SetDeviceUsed(mcv::Device device);

public:
  /**
   * Logs once per process, at INFO level, that Device Auto runs on the CPU and why (no
   * warning: that is the expected case without a GPU). Called by the filters and the
   * Gaussian TF Volume representation.
   */
  static void NoteAutoDeviceOnCPU();

protected:

  // Progress for the core, mapped to [from, to]. UpdateProgress fires VTK events: only
  // calls from the pipeline's thread are passed on. The staged form also sets the text.
  // Abort: when AbortExecute is set (a ProgressEvent observer may set it), the next report
  // stops the core and RequestData leaves the outputs empty, without an error. Honoured in
  // runs on one process; a run split over processes goes on (they must stay together).
  std::function<void(double)> ProgressCallback(double from = 0.0, double to = 1.0);
  std::function<void(const char*, double)> StageProgressCallback();
#endif

  int Device = DEVICE_AUTO;

private:
  void StopIfAborted();

  vtkMultichannelAlgorithm(const vtkMultichannelAlgorithm&) = delete;
  void operator=(const vtkMultichannelAlgorithm&) = delete;

  struct vtkInternals;
  std::unique_ptr<vtkInternals> Internals;
};

#endif
