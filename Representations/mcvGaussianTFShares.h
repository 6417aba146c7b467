// The widget legend's shares: how many of the drawn voxels (mask non-zero, finite
// coordinates) lie within each Gaussian widget's half maximum. Counted on the pieces one
// process holds, as sums that add up over processes (a split run sums them across its
// processes before dividing), on the same voxels whatever the split: each voxel of the
// volume is counted by the one piece that owns it (pieces of a split image share their
// upper boundary layer of points, which the next piece owns), and the sample of at most
// 10^6 voxels is taken by the voxel's index in the whole volume.
#pragma once

#include "GaussianTransferFunction.h" // mcv core: mcv::WidgetList

#include "vtkType.h"

#include <vector>

class vtkDataArray;
class vtkImageData;
class vtkPVSession;

namespace mcv
{
namespace gaussiantf
{

// One piece to count: its image, coordinate array (2 or 3 components, one tuple per point)
// and mask (null: every voxel is drawn).
struct SharePiece
{
  vtkImageData* Image = nullptr;
  vtkDataArray* Coordinates = nullptr;
  vtkDataArray* Mask = nullptr;
};

// Sums over one process's pieces: Values[0] the drawn voxels counted, Values[1 + w] those
// within widget w's half maximum. Adding the Values of every process gives the whole
// volume's.
struct ShareCounts
{
  std::vector<double> Values;
};

// Most voxels counted: the share to a fraction of a percent in a few milliseconds per
// widget edit.
constexpr vtkIdType MaximumShareSamples = 1000000;

// Counts `pieces` for `widgets`. `whole` is the volume's whole extent (the pieces' union);
// when it is empty (whole[1] < whole[0]) each piece is counted whole, sampled by its own
// point index.
ShareCounts countShares(
  const std::vector<SharePiece>& pieces, const int whole[6], const mcv::WidgetList& widgets);

// Sums `values` (the same length on every process) over the processes of `session` in
// place: the processes of a split run (vtkMultiProcessController::GetGlobalController())
// and, in client-server, the client, through the session's client and server
// controllers, in the order ParaView's own vtkPVView::AllReduce uses (reduce to the
// first server process, which trades with the client, then broadcast), on tags of its
// own. A collective call: every process of the session makes it at the same point (a
// view update); null session: only the global controller's processes.
void sumOverSession(vtkPVSession* session, std::vector<double>& values);

// Shares from summed counts: one per widget, empty when no voxel was drawn.
std::vector<double> sharesOf(const ShareCounts& counts);

} // namespace gaussiantf
} // namespace mcv
