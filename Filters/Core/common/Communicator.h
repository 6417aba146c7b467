// The few collective operations the suite's global steps need when a volume is split into
// pieces over several processes (MPI ranks of pvbatch/pvserver): column statistics, a
// shared reference sample, a global top-N. The core stays free of MPI and VTK: the VTK
// filters wrap vtkMultiProcessController in this interface (Filters/Common/
// mcvControllerCommunicator.h); the core tests use threads. No communicator, or one of a
// single process, means the serial computation.
//
// Every call is collective: all processes make the same calls in the same order.
#pragma once

#include <cstddef>
#include <cstring>
#include <type_traits>
#include <vector>

namespace mcv
{

class Communicator
{
public:
  virtual ~Communicator() = default;
  virtual int size() const = 0;
  virtual int rank() const = 0;

  // Element-wise over the processes, in place; the result is on every process.
  virtual void sum(std::vector<double>& values) const = 0;
  virtual void min(std::vector<double>& values) const = 0;
  virtual void max(std::vector<double>& values) const = 0;

  // Every process's bytes, concatenated in rank order, on every process.
  virtual std::vector<char> allGather(const std::vector<char>& local) const = 0;
};

// True when a computation is split over more than one process.
inline bool isDistributed(const Communicator* comm)
{
  return comm != nullptr && comm->size() > 1;
}

// Every process's values of a trivially copyable type, concatenated in rank order.
template <class T>
std::vector<T> allGatherValues(const Communicator& comm, const std::vector<T>& local)
{
  static_assert(std::is_trivially_copyable<T>::value, "plain values only");
  std::vector<char> bytes(local.size() * sizeof(T));
  if (!bytes.empty())
  {
    std::memcpy(bytes.data(), local.data(), bytes.size());
  }
  const std::vector<char> all = comm.allGather(bytes);
  std::vector<T> out(all.size() / sizeof(T));
  if (!out.empty())
  {
    std::memcpy(out.data(), all.data(), out.size() * sizeof(T));
  }
  return out;
}

// One value per process: true on every process when `flag` is true on all of them. Used
// before a collective step so that an error on one process stops all of them together
// instead of leaving the others waiting.
inline bool allTrue(const Communicator* comm, bool flag)
{
  if (!isDistributed(comm))
  {
    return flag;
  }
  std::vector<double> v{ flag ? 1.0 : 0.0 };
  comm->min(v);
  return v[0] > 0.5;
}

} // namespace mcv
