// How the suite's filters take part in a run split over processes (mpiexec pvbatch --mpi,
// pvserver): which voxels this process owns, which block (owned voxels, the extent asked
// of its output, ghost layers) it asks its input for, and where the block lies for the
// core (mcv::GridPiece). Header-only, like mcvChannelArrays.h; the modules that include it
// depend on VTK::ParallelCore.
//
// A run is split when ParaView asks this process for piece p of P > 1 and P processes run
// the pipeline (vtkMultiProcessController::GetGlobalController()). Any other request (a
// serial session, streaming pieces in one process) takes the whole volume.
// Ownership follows vtkExtentTranslator's block split of the whole extent: each piece
// without its upper boundary layer (which the next piece shares), unless that layer is the
// volume's last, so every voxel is owned exactly once.
#pragma once

#include "Communicator.h"
#include "GridPiece.h"
#include "mcvWholeExtent.h"

#include "vtkAlgorithm.h"
#include "vtkExecutive.h"
#include "vtkInformationExecutivePortKey.h"
#include "vtkExtentTranslator.h"
#include "vtkImageData.h"
#include "vtkInformation.h"
#include "vtkInformationVector.h"
#include "vtkMultiProcessController.h"
#include "vtkNew.h"
#include "vtkStreamingDemandDrivenPipeline.h"

#include <algorithm>
#include <sstream>
#include <string>

namespace mcv
{
namespace vtkhelpers
{

struct PieceLayout
{
  vtkMultiProcessController* Controller = nullptr; // set only when the run is split
  int Piece = 0;
  int NumberOfPieces = 1;
  int Whole[6] = { 0, -1, 0, -1, 0, -1 };
  int Owned[6] = { 0, -1, 0, -1, 0, -1 }; // whole-volume indices, inclusive
  int Extent[6] = { 0, -1, 0, -1, 0, -1 }; // the piece's extent: Owned + the shared layer
  bool IsSplit() const { return this->Controller != nullptr; }
};

// The layout of this process for the request in outInfo on an input whose information
// (WHOLE_EXTENT) is inInfo.
inline PieceLayout pieceLayout(vtkInformation* outInfo, vtkInformation* inInfo)
{
  PieceLayout layout;
  if (!inInfo->Has(vtkStreamingDemandDrivenPipeline::WHOLE_EXTENT()))
  {
    return layout;
  }
  inInfo->Get(vtkStreamingDemandDrivenPipeline::WHOLE_EXTENT(), layout.Whole);
  std::copy(layout.Whole, layout.Whole + 6, layout.Owned);
  const int pieces = outInfo->Has(vtkStreamingDemandDrivenPipeline::UPDATE_NUMBER_OF_PIECES())
    ? outInfo->Get(vtkStreamingDemandDrivenPipeline::UPDATE_NUMBER_OF_PIECES())
    : 1;
  const int piece = outInfo->Has(vtkStreamingDemandDrivenPipeline::UPDATE_PIECE_NUMBER())
    ? outInfo->Get(vtkStreamingDemandDrivenPipeline::UPDATE_PIECE_NUMBER())
    : 0;
  vtkMultiProcessController* controller = vtkMultiProcessController::GetGlobalController();
  if (pieces <= 1 || !controller || controller->GetNumberOfProcesses() != pieces ||
    controller->GetLocalProcessId() != piece)
  {
    return layout;
  }
  layout.Controller = controller;
  layout.Piece = piece;
  layout.NumberOfPieces = pieces;
  vtkNew<vtkExtentTranslator> translator;
  translator->PieceToExtentThreadSafe(piece, pieces, 0, layout.Whole, layout.Owned,
    vtkExtentTranslator::BLOCK_MODE, 0);
  std::copy(layout.Owned, layout.Owned + 6, layout.Extent);
  for (int a = 0; a < 3; ++a)
  {
    if (layout.Owned[2 * a + 1] < layout.Whole[2 * a + 1])
    {
      --layout.Owned[2 * a + 1];
    }
  }
  return layout;
}

// The output information of the algorithm that really makes the input: ParaView puts a
// vtkPVPostFilter (array conversions on demand, a pass-through that forwards the requests)
// after every source and filter, and that one hides the real producer (a filter of the
// suite) and its keys (CAN_PRODUCE_SUB_EXTENT of the XML image reader).
inline vtkInformation* pastPostFilter(vtkInformation* inInfo)
{
  vtkExecutive* executive = vtkExecutive::PRODUCER()->GetExecutive(inInfo);
  vtkAlgorithm* producer = executive ? executive->GetAlgorithm() : nullptr;
  if (producer && producer->IsA("vtkPVPostFilter") &&
    producer->GetNumberOfInputConnections(0) == 1)
  {
    return producer->GetInputInformation(0, 0);
  }
  return inInfo;
}

// True when the input comes straight from another filter of the suite that can run split.
inline bool fromSplitFilter(vtkInformation* inInfo)
{
  vtkExecutive* executive = vtkExecutive::PRODUCER()->GetExecutive(pastPostFilter(inInfo));
  vtkAlgorithm* producer = executive ? executive->GetAlgorithm() : nullptr;
  return producer &&
    (producer->IsA("vtkMultichannelFeatures") || producer->IsA("vtkDimensionReduction"));
}

// True when the input produces whatever sub-extent it is asked for on its own
// (CAN_PRODUCE_SUB_EXTENT, set by the XML image readers, the Wavelet source...).
inline bool producesSubExtents(vtkInformation* inInfo)
{
  vtkInformation* info = pastPostFilter(inInfo);
  return info->Has(vtkAlgorithm::CAN_PRODUCE_SUB_EXTENT()) &&
    info->Get(vtkAlgorithm::CAN_PRODUCE_SUB_EXTENT()) != 0;
}

// RequestUpdateExtent of a filter that can run split: asks the input for this process's
// owned voxels, plus the extent asked of an image output (`requested`, may be null),
// padded by `ghostLayers` and clipped to the volume; the whole volume when not split.
// The piece numbers go upstream to the suite's own filters, so that they split the same
// way. A source that produces sub-extents (producesSubExtents: the XML image readers read
// just the block) is asked for piece 0 of 1 with the block. Any other input is asked for
// piece 0 of 1 with the WHOLE extent, the same request on every process: most of
// ParaView's image readers (NIfTI, raw, DEN) produce data for piece 0 only and read the
// whole volume anyway, and a parallel filter may need one request everywhere:
// vtkPResampleToImage (ResampleToImage) splits the UPDATE_EXTENT it is asked for into DIY
// blocks and sends each process the points of its block as computed from the SENDER's
// request; asked a different extent on each process, it writes those points outside its
// output's arrays (ParaView 5.11: heap corruption in vtkPResampleToImage::RequestData,
// "free(): invalid next size"). Such an input delivers its own split, which gatherBlock
// (mcvGatherBlock.h) reassembles.
inline int requestPieceWithGhosts(vtkInformationVector** inputVector,
  vtkInformationVector* outputVector, int ghostLayers, const int* requested = nullptr)
{
  vtkInformation* inInfo = inputVector[0]->GetInformationObject(0);
  vtkInformation* outInfo = outputVector->GetInformationObject(0);
  const PieceLayout layout = pieceLayout(outInfo, inInfo);
  if (!layout.IsSplit())
  {
    return requestWholeExtent(inputVector);
  }
  // A piece request (ParaView's UpdatePipeline, representations) leaves the output's
  // UPDATE_EXTENT at the whole extent: taken as an extent request it would make every
  // process ask its input for the whole volume. The output then holds the piece's extent
  // (shared upper layer included, which the next process owns), so that is what is asked.
  if (requested && std::equal(requested, requested + 6, layout.Whole))
  {
    requested = layout.Extent;
  }
  int block[6];
  for (int a = 0; a < 3; ++a)
  {
    int lo = layout.Owned[2 * a], hi = layout.Owned[2 * a + 1];
    if (requested && requested[2 * a] <= requested[2 * a + 1])
    {
      lo = std::min(lo, requested[2 * a]);
      hi = std::max(hi, requested[2 * a + 1]);
    }
    block[2 * a] = std::max(layout.Whole[2 * a], lo - ghostLayers);
    block[2 * a + 1] = std::min(layout.Whole[2 * a + 1], hi + ghostLayers);
    // A process that owns no voxel (more processes than the volume splits in) still asks
    // for one: a split filter of the suite upstream crops its output to what is asked,
    // and an empty block would stop this one ("empty extent") instead of letting it take
    // part with nothing.
    if (block[2 * a] > block[2 * a + 1])
    {
      block[2 * a] = block[2 * a + 1] = layout.Whole[2 * a];
    }
  }
  const bool split = fromSplitFilter(inInfo);
  if (!split && !producesSubExtents(inInfo))
  {
    std::copy(layout.Whole, layout.Whole + 6, block);
  }
  inInfo->Set(vtkStreamingDemandDrivenPipeline::UPDATE_EXTENT(), block, 6);
  inInfo->Set(vtkStreamingDemandDrivenPipeline::UPDATE_PIECE_NUMBER(), split ? layout.Piece : 0);
  inInfo->Set(
    vtkStreamingDemandDrivenPipeline::UPDATE_NUMBER_OF_PIECES(), split ? layout.NumberOfPieces : 1);
  inInfo->Set(vtkStreamingDemandDrivenPipeline::UPDATE_NUMBER_OF_GHOST_LEVELS(), 0);
  return 1;
}

// requestPieceWithGhosts for an image-to-image filter: the extent asked of output port 0
// is kept, plus `ghostLayers`.
inline int requestOutputExtentWithGhosts(
  vtkInformationVector** inputVector, vtkInformationVector* outputVector, int ghostLayers)
{
  vtkInformation* outInfo = outputVector->GetInformationObject(0);
  int requested[6] = { 0, -1, 0, -1, 0, -1 };
  if (outInfo->Has(vtkStreamingDemandDrivenPipeline::UPDATE_EXTENT()))
  {
    outInfo->Get(vtkStreamingDemandDrivenPipeline::UPDATE_EXTENT(), requested);
  }
  return requestPieceWithGhosts(inputVector, outputVector, ghostLayers, requested);
}

// Where `image` (the block the input delivered) lies in the whole volume and which of its
// voxels this process owns. "" or, when the block does not hold every owned voxel (an
// input that ignored the extent request with a smaller one), the error message.
inline std::string gridPiece(vtkImageData* image, const PieceLayout& layout, mcv::GridPiece& piece)
{
  int extent[6];
  image->GetExtent(extent);
  for (int a = 0; a < 3; ++a)
  {
    const int dims = extent[2 * a + 1] - extent[2 * a] + 1;
    if (!layout.IsSplit())
    {
      piece.wholeDims[a] = dims;
      piece.offset[a] = 0;
      piece.ownedLo[a] = 0;
      piece.ownedHi[a] = dims - 1;
      continue;
    }
    if (extent[2 * a] > layout.Owned[2 * a] || extent[2 * a + 1] < layout.Owned[2 * a + 1])
    {
      std::ostringstream os;
      os << "The input delivered extent " << extent[0] << " " << extent[1] << " " << extent[2]
         << " " << extent[3] << " " << extent[4] << " " << extent[5]
         << ", which does not hold this process's piece of the volume.";
      return os.str();
    }
    piece.wholeDims[a] = layout.Whole[2 * a + 1] - layout.Whole[2 * a] + 1;
    piece.offset[a] = extent[2 * a] - layout.Whole[2 * a];
    piece.ownedLo[a] = layout.Owned[2 * a] - extent[2 * a];
    piece.ownedHi[a] = layout.Owned[2 * a + 1] - extent[2 * a];
  }
  return "";
}

// Keeps the processes of a split run together on errors. Every process must make the same
// collective calls, so one that fails its local checks (an array missing, a bad property)
// still votes in the check the others make before their first collective step, and all
// of them stop with an error instead of waiting for it. Serial (no communicator): no-op.
class CollectiveCheck
{
public:
  explicit CollectiveCheck(const mcv::Communicator* comm)
    : Comm(comm)
  {
  }
  ~CollectiveCheck()
  {
    if (this->Pending)
    {
      mcv::allTrue(this->Comm, false);
    }
  }
  CollectiveCheck(const CollectiveCheck&) = delete;
  CollectiveCheck& operator=(const CollectiveCheck&) = delete;

  // Called once, where every process has passed its local checks: true when all have.
  bool AllPassed()
  {
    this->Pending = false;
    return mcv::allTrue(this->Comm, true);
  }

private:
  const mcv::Communicator* Comm;
  bool Pending = true;
};

} // namespace vtkhelpers
} // namespace mcv
