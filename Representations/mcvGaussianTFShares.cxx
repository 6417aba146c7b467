#include "mcvGaussianTFShares.h"

#include "../Filters/Common/mcvCoordinateArrays.h" // float32 or float16 coordinates

#include "vtkCommunicator.h"
#include "vtkDataArray.h"
#include "vtkImageData.h"
#include "vtkMultiProcessController.h"
#include "vtkPVSession.h"

#include <algorithm>
#include <cmath>

namespace mcv
{
namespace gaussiantf
{

ShareCounts countShares(
  const std::vector<SharePiece>& pieces, const int whole[6], const mcv::WidgetList& widgets)
{
  const size_t count = widgets.widgets.size();
  ShareCounts counts;
  counts.Values.assign(count + 1, 0.0);
  const bool haveWhole =
    whole[1] >= whole[0] && whole[3] >= whole[2] && whole[5] >= whole[4];
  vtkIdType total = 0; // points the sample is taken from
  if (haveWhole)
  {
    total = static_cast<vtkIdType>(whole[1] - whole[0] + 1) * (whole[3] - whole[2] + 1) *
      (whole[5] - whole[4] + 1);
  }
  else
  {
    for (const SharePiece& piece : pieces)
    {
      total += piece.Image->GetNumberOfPoints();
    }
  }
  const vtkIdType stride = std::max<vtkIdType>(1, total / MaximumShareSamples);
  std::vector<double> limit(count);
  for (size_t w = 0; w < count; ++w)
  {
    // Half maximum: exp(-d^2 / (2 sigma^2)) >= 1/2  <=>  d^2 <= 2 ln 2 sigma^2.
    limit[w] = 2.0 * std::log(2.0) * widgets.widgets[w].sigma * widgets.widgets[w].sigma;
  }
  for (const SharePiece& piece : pieces)
  {
    int extent[6];
    piece.Image->GetExtent(extent);
    // The voxels this piece owns: without an upper layer that is not the volume's last
    // (the next piece owns it; a piece of one such layer owns nothing).
    int owned[6];
    std::copy(extent, extent + 6, owned);
    if (haveWhole)
    {
      for (int a = 0; a < 3; ++a)
      {
        if (owned[2 * a + 1] < whole[2 * a + 1])
        {
          --owned[2 * a + 1];
        }
      }
    }
    const vtkIdType nx = extent[1] - extent[0] + 1;
    const vtkIdType ny = extent[3] - extent[2] + 1;
    const int dims = piece.Coordinates->GetNumberOfComponents();
    for (int k = owned[4]; k <= owned[5]; ++k)
    {
      for (int j = owned[2]; j <= owned[3]; ++j)
      {
        for (int i = owned[0]; i <= owned[1]; ++i)
        {
          const vtkIdType t = (i - extent[0]) + nx * ((j - extent[2]) + ny * (k - extent[4]));
          const vtkIdType g = haveWhole
            ? (i - whole[0]) +
              static_cast<vtkIdType>(whole[1] - whole[0] + 1) *
                ((j - whole[2]) + static_cast<vtkIdType>(whole[3] - whole[2] + 1) * (k - whole[4]))
            : t;
          if (g % stride != 0 || (piece.Mask && piece.Mask->GetComponent(t, 0) == 0))
          {
            continue;
          }
          double x[3] = { 0, 0, 0 };
          bool finite = true;
          for (int c = 0; c < dims; ++c)
          {
            x[c] = mcv::vtkhelpers::coordinateComponent(piece.Coordinates, t, c);
            finite = finite && std::isfinite(x[c]);
          }
          if (!finite)
          {
            continue;
          }
          counts.Values[0] += 1;
          for (size_t w = 0; w < count; ++w)
          {
            double d2 = 0;
            for (int c = 0; c < dims; ++c)
            {
              const double d = x[c] - widgets.widgets[w].center[c];
              d2 += d * d;
            }
            counts.Values[1 + w] += d2 <= limit[w] ? 1 : 0;
          }
        }
      }
    }
  }
  return counts;
}

void sumOverSession(vtkPVSession* session, std::vector<double>& values)
{
  // vtkPVView::AllReduce does this for one number and is protected: the same exchange for
  // a list, on tags ParaView's does not use.
  constexpr int toClient = 41290;
  constexpr int fromClient = 41291;
  if (values.empty())
  {
    return;
  }
  const vtkIdType n = static_cast<vtkIdType>(values.size());
  vtkMultiProcessController* parallel = vtkMultiProcessController::GetGlobalController();
  if (parallel && parallel->GetNumberOfProcesses() <= 1)
  {
    parallel = nullptr;
  }
  if (parallel)
  {
    std::vector<double> sum(values.size(), 0.0);
    parallel->Reduce(values.data(), sum.data(), n, vtkCommunicator::SUM_OP, 0);
    values = sum;
  }
  if (session)
  {
    // The first server process: sends its sum to the client and takes the total back.
    if (vtkMultiProcessController* client = session->GetController(vtkPVSession::CLIENT))
    {
      client->Send(values.data(), n, 1, toClient);
      client->Receive(values.data(), n, 1, fromClient);
    }
    // The client: adds the servers' sums (a render server apart from the data server
    // sends its own) and sends the total back.
    vtkMultiProcessController* render = session->GetController(vtkPVSession::RENDER_SERVER_ROOT);
    vtkMultiProcessController* data = session->GetController(vtkPVSession::DATA_SERVER_ROOT);
    if (data == render)
    {
      data = nullptr;
    }
    std::vector<double> part(values.size());
    for (vtkMultiProcessController* server : { render, data })
    {
      if (server)
      {
        server->Receive(part.data(), n, 1, toClient);
        for (size_t i = 0; i < values.size(); ++i)
        {
          values[i] += part[i];
        }
      }
    }
    for (vtkMultiProcessController* server : { render, data })
    {
      if (server)
      {
        server->Send(values.data(), n, 1, fromClient);
      }
    }
  }
  if (parallel)
  {
    parallel->Broadcast(values.data(), n, 0);
  }
}

std::vector<double> sharesOf(const ShareCounts& counts)
{
  std::vector<double> shares;
  if (counts.Values.empty() || !(counts.Values[0] > 0))
  {
    return shares;
  }
  for (size_t w = 1; w < counts.Values.size(); ++w)
  {
    shares.push_back(counts.Values[w] / counts.Values[0]);
  }
  return shares;
}

} // namespace gaussiantf
} // namespace mcv
