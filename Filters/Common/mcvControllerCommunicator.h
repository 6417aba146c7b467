// mcv::Communicator (Filters/Core/common/Communicator.h) over a vtkMultiProcessController: how the
// VTK filters hand ParaView's MPI processes to the VTK-free core. Header-only, like
// mcvChannelArrays.h; the modules that include it depend on VTK::ParallelCore.
#pragma once

#include "Communicator.h"

#include "vtkCommunicator.h"
#include "vtkMultiProcessController.h"
#include "vtkType.h"

#include <vector>

namespace mcv
{
namespace vtkhelpers
{

class ControllerCommunicator : public mcv::Communicator
{
public:
  explicit ControllerCommunicator(vtkMultiProcessController* controller)
    : Controller(controller)
  {
  }
  int size() const override { return this->Controller->GetNumberOfProcesses(); }
  int rank() const override { return this->Controller->GetLocalProcessId(); }
  void sum(std::vector<double>& v) const override { this->Reduce(v, vtkCommunicator::SUM_OP); }
  void min(std::vector<double>& v) const override { this->Reduce(v, vtkCommunicator::MIN_OP); }
  void max(std::vector<double>& v) const override { this->Reduce(v, vtkCommunicator::MAX_OP); }

  std::vector<char> allGather(const std::vector<char>& local) const override
  {
    const int n = this->size();
    vtkIdType mine = static_cast<vtkIdType>(local.size());
    std::vector<vtkIdType> lengths(static_cast<std::size_t>(n), 0), offsets(static_cast<std::size_t>(n), 0);
    this->Controller->AllGather(&mine, lengths.data(), 1);
    vtkIdType total = 0;
    for (int r = 0; r < n; ++r)
    {
      offsets[static_cast<std::size_t>(r)] = total;
      total += lengths[static_cast<std::size_t>(r)];
    }
    // One spare byte keeps the buffers' data() valid when everything is empty.
    std::vector<char> all(static_cast<std::size_t>(total) + 1);
    std::vector<char> send(local);
    send.push_back(0);
    this->Controller->AllGatherV(send.data(), all.data(), mine, lengths.data(), offsets.data());
    all.pop_back();
    return all;
  }

private:
  void Reduce(std::vector<double>& v, int operation) const
  {
    if (v.empty())
    {
      return;
    }
    std::vector<double> in(v);
    this->Controller->AllReduce(in.data(), v.data(), static_cast<vtkIdType>(v.size()), operation);
  }

  vtkMultiProcessController* Controller;
};

} // namespace vtkhelpers
} // namespace mcv
