#include "vtkMultichannelAlgorithm.h"

#include "vtkDataArray.h"
#include "vtkDataObject.h"
#include "vtkImageData.h"
#include "vtkInformation.h"
#include "vtkInformationVector.h"
#include "vtkLogger.h"
#include "vtkNew.h"
#include "vtkPointData.h"
#include "vtkStreamingDemandDrivenPipeline.h"

// The VTK-free core (Filters/Core).
#include "Device.h"

#include "mcvChannelArrays.h"
#include "mcvControllerCommunicator.h"
#include "mcvGatherBlock.h"
#include "mcvPieces.h"

#include <omp.h>

#include <algorithm>
#include <new>
#include <cstring>
#include <thread>

struct vtkMultichannelAlgorithm::vtkInternals
{
  mcv::vtkhelpers::ChannelSelection Channels;
  std::string DeviceUsed = "CPU";
  // Set during RequestData.
  mcv::vtkhelpers::PieceLayout Layout;
  const mcv::Communicator* Communicator = nullptr;
  mcv::vtkhelpers::CollectiveCheck* Check = nullptr;
  // The block a split run assembled when the input delivered another split (GetInputImage).
  vtkSmartPointer<vtkImageData> GatheredInput;
};

namespace
{
// Thrown by the progress callbacks when AbortExecute is set (by a ProgressEvent observer,
// the VTK way), caught in RequestData. An exception because the core's progress callbacks
// return nothing: it unwinds the core (RAII throughout) from the next progress report.
// Not derived from std::exception, so the core's own handlers let it pass.
struct AbortRequested
{
};

bool makesImageData(vtkAlgorithm* algorithm, int port)
{
  vtkInformation* info = algorithm->GetOutputPortInformation(port);
  const char* type = info ? info->Get(vtkDataObject::DATA_TYPE_NAME()) : nullptr;
  return type && std::strcmp(type, "vtkImageData") == 0;
}
} // namespace

//------------------------------------------------------------------------------
vtkMultichannelAlgorithm::vtkMultichannelAlgorithm()
  : Internals(new vtkInternals)
{
  this->SetNumberOfInputPorts(1);
  this->SetNumberOfOutputPorts(1);
}

//------------------------------------------------------------------------------
vtkMultichannelAlgorithm::~vtkMultichannelAlgorithm() = default;

//------------------------------------------------------------------------------
void vtkMultichannelAlgorithm::AddChannel(const char* arrayName)
{
  if (this->Internals->Channels.Add(arrayName))
  {
    this->Modified();
  }
}

//------------------------------------------------------------------------------
void vtkMultichannelAlgorithm::ClearChannels()
{
  if (this->Internals->Channels.Clear())
  {
    this->Modified();
  }
}

//------------------------------------------------------------------------------
int vtkMultichannelAlgorithm::GetNumberOfChannels()
{
  return this->Internals->Channels.Size();
}

//------------------------------------------------------------------------------
const char* vtkMultichannelAlgorithm::GetChannel(int index)
{
  return this->Internals->Channels.Get(index);
}

//------------------------------------------------------------------------------
const char* vtkMultichannelAlgorithm::GetDeviceUsed()
{
  return this->Internals->DeviceUsed.c_str();
}

//------------------------------------------------------------------------------
mcv::Device vtkMultichannelAlgorithm::GetRequestedDevice() const
{
  return static_cast<mcv::Device>(this->Device);
}

//------------------------------------------------------------------------------
void vtkMultichannelAlgorithm::SetDeviceUsed(mcv::Device device)
{
  this->Internals->DeviceUsed = mcv::deviceName(device);
  if (this->GetRequestedDevice() == mcv::Device::Auto && device == mcv::Device::CPU)
  {
    NoteAutoDeviceOnCPU();
  }
}

//------------------------------------------------------------------------------
void vtkMultichannelAlgorithm::NoteAutoDeviceOnCPU()
{
  // Device Auto without a usable GPU is the expected case on most desktops: one line at
  // INFO level per process, not a warning that opens ParaView's Output Messages window.
  static bool noted = false;
  if (!noted)
  {
    noted = true;
    std::string why;
    mcv::gpuUsable(&why);
    vtkLog(INFO, "Multichannel Explorer: Device Auto runs on the CPU (no usable GPU: " << why << ").");
  }
}

//------------------------------------------------------------------------------
int vtkMultichannelAlgorithm::FillInputPortInformation(int, vtkInformation* info)
{
  // vtkDataSet rather than vtkImageData so that other inputs get the filter's own,
  // explicit error message (ParaView's XML restricts the input to image data anyway).
  info->Set(vtkAlgorithm::INPUT_REQUIRED_DATA_TYPE(), "vtkDataSet");
  return 1;
}

//------------------------------------------------------------------------------
void vtkMultichannelAlgorithm::CopyInputArrayAttributesToOutput(
  vtkInformation* request, vtkInformationVector** inputVector, vtkInformationVector* outputVector)
{
  if (makesImageData(this, 0))
  {
    this->Superclass::CopyInputArrayAttributesToOutput(request, inputVector, outputVector);
  }
}

//------------------------------------------------------------------------------
int vtkMultichannelAlgorithm::RequestInformation(
  vtkInformation* request, vtkInformationVector** inputVector, vtkInformationVector* outputVector)
{
  if (!this->Superclass::RequestInformation(request, inputVector, outputVector))
  {
    return 0;
  }
  // Piece requests become extents (vtkExtentTranslator), so a split run computes pieces.
  if (this->GetSplitGhostLayers() >= 0 && makesImageData(this, 0))
  {
    outputVector->GetInformationObject(0)->Set(vtkAlgorithm::CAN_PRODUCE_SUB_EXTENT(), 1);
  }
  return 1;
}

//------------------------------------------------------------------------------
int vtkMultichannelAlgorithm::RequestUpdateExtent(
  vtkInformation*, vtkInformationVector** inputVector, vtkInformationVector* outputVector)
{
  const int ghostLayers = this->GetSplitGhostLayers();
  if (ghostLayers < 0)
  {
    return mcv::vtkhelpers::requestWholeExtent(inputVector);
  }
  // An image output keeps the extent asked of it; other outputs come in pieces.
  return makesImageData(this, 0)
    ? mcv::vtkhelpers::requestOutputExtentWithGhosts(inputVector, outputVector, ghostLayers)
    : mcv::vtkhelpers::requestPieceWithGhosts(inputVector, outputVector, ghostLayers);
}

//------------------------------------------------------------------------------
namespace
{
// No partial result is left behind after an abort or a failed allocation.
void emptyOutputs(vtkInformationVector* outputVector)
{
  for (int port = 0; port < outputVector->GetNumberOfInformationObjects(); ++port)
  {
    if (vtkDataObject* output =
          outputVector->GetInformationObject(port)->Get(vtkDataObject::DATA_OBJECT()))
    {
      output->Initialize();
    }
  }
}
} // namespace

//------------------------------------------------------------------------------
int vtkMultichannelAlgorithm::RequestData(
  vtkInformation* request, vtkInformationVector** inputVector, vtkInformationVector* outputVector)
{
  vtkInternals& internals = *this->Internals;
  internals.DeviceUsed = "CPU";
  internals.Layout = this->GetSplitGhostLayers() >= 0
    ? mcv::vtkhelpers::pieceLayout(
        outputVector->GetInformationObject(0), inputVector[0]->GetInformationObject(0))
    : mcv::vtkhelpers::PieceLayout();
  mcv::vtkhelpers::ControllerCommunicator communicator(internals.Layout.Controller);
  internals.Communicator = internals.Layout.IsSplit() ? &communicator : nullptr;
  // A process that returns before AllProcessesReady() votes "failed" as `check` goes.
  mcv::vtkhelpers::CollectiveCheck check(internals.Communicator);
  internals.Check = &check;
  int status = 1;
  try
  {
    status = this->RequestMultichannelData(request, inputVector, outputVector);
  }
  catch (const AbortRequested&)
  {
    // Aborted: no partial result is left behind (VTK's convention: no error either).
    emptyOutputs(outputVector);
    // VTK 9.2's executive does not clear the flag before the next run: clear it here, so
    // that the run after a modification starts afresh.
    this->SetAbortExecute(0);
    vtkDebugMacro("aborted");
  }
  catch (const std::bad_alloc&)
  {
    // An allocation the memory check could not foresee (another process took the memory,
    // fragmentation): an error and empty outputs rather than the process ending.
    emptyOutputs(outputVector);
    vtkErrorMacro(<< (this->GetClassName() + 3) << " ran out of memory (an allocation failed); "
                  << "crop or subsample the volume, close other programs, or run on more MPI "
                     "ranks (mpiexec -np R pvbatch --mpi) so that each holds a smaller piece.");
    status = 0;
  }
  internals.Check = nullptr;
  internals.Communicator = nullptr;
  internals.GatheredInput = nullptr;
  return status;
}

//------------------------------------------------------------------------------
const mcv::vtkhelpers::PieceLayout& vtkMultichannelAlgorithm::GetPieceLayout() const
{
  return this->Internals->Layout;
}

//------------------------------------------------------------------------------
const mcv::Communicator* vtkMultichannelAlgorithm::GetCommunicator() const
{
  return this->Internals->Communicator;
}

//------------------------------------------------------------------------------
bool vtkMultichannelAlgorithm::AllProcessesReady()
{
  if (this->Internals->Check && !this->Internals->Check->AllPassed())
  {
    vtkErrorMacro("Another process of the parallel run reported an error (see its output).");
    return false;
  }
  return true;
}

//------------------------------------------------------------------------------
bool vtkMultichannelAlgorithm::ReportError(const std::string& message)
{
  if (message.empty())
  {
    return false;
  }
  vtkErrorMacro(<< message);
  return true;
}

//------------------------------------------------------------------------------
void vtkMultichannelAlgorithm::ReportWarnings(const std::vector<std::string>& warnings)
{
  for (const std::string& warning : warnings)
  {
    if (!warning.empty())
    {
      vtkWarningMacro(<< warning);
    }
  }
}

//------------------------------------------------------------------------------
vtkImageData* vtkMultichannelAlgorithm::GetInputImage(
  vtkInformationVector** inputVector, const char* requirement)
{
  vtkDataObject* inputObject = vtkDataObject::GetData(inputVector[0], 0);
  vtkImageData* image = vtkImageData::SafeDownCast(inputObject);
  vtkInformation* inInfo = inputVector[0]->GetInformationObject(0);
  if (image && this->Internals->Layout.IsSplit() &&
    inInfo->Has(vtkStreamingDemandDrivenPipeline::UPDATE_EXTENT()))
  {
    // A source that ignored the extent asked of it (ResampleToImage splits its own way):
    // the block is assembled from the processes' pieces (collective).
    mcv::vtkhelpers::Box need;
    inInfo->Get(vtkStreamingDemandDrivenPipeline::UPDATE_EXTENT(), need.e);
    std::string error;
    this->Internals->GatheredInput =
      mcv::vtkhelpers::gatherBlock(image, need, this->Internals->Layout.Controller, error);
    if (this->ReportError(error))
    {
      return nullptr;
    }
    image = this->Internals->GatheredInput;
  }
  if (!image)
  {
    // "vtkBestViewpoint" -> "BestViewpoint", the filter's label in ParaView.
    vtkErrorMacro("Input is " << (inputObject ? inputObject->GetClassName() : "missing")
                              << ", not image data: " << (this->GetClassName() + 3)
                              << " needs a vtkImageData " << requirement);
  }
  return image;
}

//------------------------------------------------------------------------------
bool vtkMultichannelAlgorithm::GetImageBlock(
  vtkImageData* image, mcv::ImageGrid& grid, mcv::GridPiece& piece)
{
  int extent[6];
  image->GetExtent(extent);
  for (int a = 0; a < 3; ++a)
  {
    grid.dims[a] = extent[2 * a + 1] - extent[2 * a] + 1;
  }
  if (grid.dims[0] <= 0 || grid.dims[1] <= 0 || grid.dims[2] <= 0)
  {
    vtkErrorMacro("Input image has an empty extent (" << extent[0] << " " << extent[1] << " "
                                                      << extent[2] << " " << extent[3] << " "
                                                      << extent[4] << " " << extent[5] << ").");
    return false;
  }
  return !this->ReportError(mcv::vtkhelpers::gridPiece(image, this->Internals->Layout, piece));
}

//------------------------------------------------------------------------------
std::vector<vtkDataArray*> vtkMultichannelAlgorithm::GetDefaultChannels(vtkPointData* pd)
{
  std::vector<vtkDataArray*> picked;
  for (int i = 0; i < pd->GetNumberOfArrays(); ++i)
  {
    vtkDataArray* dataArray = pd->GetArray(i);
    if (dataArray && !mcv::vtkhelpers::isInternalArray(dataArray->GetName()))
    {
      picked.push_back(dataArray);
    }
  }
  return picked;
}

//------------------------------------------------------------------------------
bool vtkMultichannelAlgorithm::SelectChannels(
  vtkImageData* image, std::size_t count, mcv::vtkhelpers::ChannelArrays& channels)
{
  std::vector<vtkDataArray*> arrays;
  std::string error = mcv::vtkhelpers::selectChannelArrays(image,
    this->Internals->Channels.GetNames(),
    [this](vtkPointData* pd) { return this->GetDefaultChannels(pd); }, this->GetClassName() + 3,
    arrays);
  if (error.empty())
  {
    error = mcv::vtkhelpers::toChannels(arrays, count, channels);
  }
  return !this->ReportError(error);
}

//------------------------------------------------------------------------------
void vtkMultichannelAlgorithm::GetOutputExtent(
  vtkImageData* block, vtkInformationVector* outputVector, int extent[6])
{
  block->GetExtent(extent);
  vtkInformation* outInfo = outputVector->GetInformationObject(0);
  if (!this->Internals->Layout.IsSplit() ||
    !outInfo->Has(vtkStreamingDemandDrivenPipeline::UPDATE_EXTENT()))
  {
    return;
  }
  int requested[6];
  outInfo->Get(vtkStreamingDemandDrivenPipeline::UPDATE_EXTENT(), requested);
  // On a request of several pieces the executive replaces UPDATE_EXTENT, before this
  // filter runs, by this piece's part of it (vtkStreamingDemandDrivenPipeline::
  // ExecuteDataStart splits the extent asked with vtkExtentTranslator, as this output can
  // produce sub-extents) and keeps what was asked in ALL_PIECES_EXTENT. A consumer that
  // asked for an extent of its own (ExtractVoxels: the voxels its process owns) gets that
  // extent, not a piece of it cut along another axis; a request of the whole volume
  // (representations, UpdatePipeline) gets this process's piece.
  if (outInfo->Has(vtkDataObject::ALL_PIECES_EXTENT()))
  {
    int asked[6];
    outInfo->Get(vtkDataObject::ALL_PIECES_EXTENT(), asked);
    const int* whole = this->Internals->Layout.Whole;
    if (!std::equal(asked, asked + 6, whole))
    {
      std::copy(asked, asked + 6, requested);
    }
  }
  for (int a = 0; a < 3; ++a)
  {
    const int lo = std::max(extent[2 * a], requested[2 * a]);
    const int hi = std::min(extent[2 * a + 1], requested[2 * a + 1]);
    // vtkImageData::Crop leaves an axis it could not cut (an empty intersection) as it is.
    if (lo <= hi)
    {
      extent[2 * a] = lo;
      extent[2 * a + 1] = hi;
    }
  }
}

//------------------------------------------------------------------------------
void vtkMultichannelAlgorithm::PassInputAtExtent(vtkImageData* input, const int extent[6],
  vtkImageData* output, const std::vector<std::string>& leaveOut)
{
  vtkNew<vtkImageData> pass;
  pass->ShallowCopy(input);
  for (const std::string& name : leaveOut)
  {
    pass->GetPointData()->RemoveArray(name.c_str());
  }
  int inputExtent[6];
  input->GetExtent(inputExtent);
  if (!std::equal(inputExtent, inputExtent + 6, extent))
  {
    pass->Crop(extent);
  }
  output->ShallowCopy(pass);
}

//------------------------------------------------------------------------------
vtkSmartPointer<vtkDataArray> vtkMultichannelAlgorithm::CropPointArray(
  vtkDataArray* array, const int from[6], const int to[6])
{
  if (!array || std::equal(from, from + 6, to))
  {
    return array;
  }
  // vtkImageData::Crop on an image that holds this array alone.
  vtkNew<vtkImageData> one;
  one->SetExtent(const_cast<int*>(from));
  one->GetPointData()->AddArray(array);
  one->Crop(to);
  return one->GetPointData()->GetArray(0);
}

//------------------------------------------------------------------------------
std::function<void(double)> vtkMultichannelAlgorithm::ProgressCallback(double from, double to)
{
  const std::thread::id callingThread = std::this_thread::get_id();
  return [this, callingThread, from, to](double p) {
    if (std::this_thread::get_id() == callingThread)
    {
      this->UpdateProgress(from + (to - from) * std::min(1.0, std::max(0.0, p)));
      this->StopIfAborted();
    }
  };
}

//------------------------------------------------------------------------------
std::function<void(const char*, double)> vtkMultichannelAlgorithm::StageProgressCallback()
{
  const std::thread::id callingThread = std::this_thread::get_id();
  return [this, callingThread](const char* stage, double p) {
    if (std::this_thread::get_id() == callingThread)
    {
      this->SetProgressText(stage);
      this->UpdateProgress(std::min(1.0, std::max(0.0, p)));
      this->StopIfAborted();
    }
  };
}

//------------------------------------------------------------------------------
void vtkMultichannelAlgorithm::StopIfAborted()
{
  // Never inside an OpenMP region (an exception may not leave it), and only in a run that
  // is not split over processes (the others would wait for this one in a collective).
  if (this->GetAbortExecute() && !this->Internals->Communicator && !omp_in_parallel())
  {
    throw AbortRequested();
  }
}

//------------------------------------------------------------------------------
void vtkMultichannelAlgorithm::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "Channels:";
  for (const std::string& name : this->Internals->Channels.GetNames())
  {
    os << " " << name;
  }
  os << "\n";
  os << indent << "Device: " << this->Device << "\n";
  os << indent << "DeviceUsed: " << this->Internals->DeviceUsed << "\n";
}
