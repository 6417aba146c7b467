// The block a process of a split run asked its input for, assembled from the pieces the
// processes hold, when the input delivered another decomposition. Header-only, like
// mcvPieces.h.
//
// Why: a filter of the suite asks its input for its piece plus ghost layers
// (mcvPieces.h), but some of ParaView's parallel sources ignore the request and deliver
// their own split: ResampleToImage (vtkPResampleToImage) hands out DIY blocks, along y for
// the brain, whatever extent was asked. Without this step the run stops with "the input
// delivered extent ... does not hold this process's piece". VTK 9.2 has no image
// redistribution filter (vtkRedistributeDataSetFilter makes unstructured grids), so the
// exchange is written here: every process tells the others which extent it holds and
// which it needs (one AllGather), then each pair of processes whose boxes meet trades the
// intersection, point array by point array, as raw bytes.
#pragma once

#include "vtkDataArray.h"
#include "vtkImageData.h"
#include "vtkMultiProcessController.h"
#include "vtkPointData.h"
#include "vtkSmartPointer.h"

#include <algorithm>
#include <cstdint>
#include <cstring>
#include <sstream>
#include <string>
#include <vector>

namespace mcv
{
namespace vtkhelpers
{

struct Box
{
  int e[6] = { 0, -1, 0, -1, 0, -1 };
  bool Empty() const { return e[1] < e[0] || e[3] < e[2] || e[5] < e[4]; }
  std::int64_t Dim(int a) const { return Empty() ? 0 : e[2 * a + 1] - e[2 * a] + 1; }
  std::int64_t Count() const { return Dim(0) * Dim(1) * Dim(2); }
  bool Contains(const Box& o) const
  {
    if (o.Empty())
    {
      return true;
    }
    for (int a = 0; a < 3; ++a)
    {
      if (Empty() || o.e[2 * a] < e[2 * a] || o.e[2 * a + 1] > e[2 * a + 1])
      {
        return false;
      }
    }
    return true;
  }
  Box Intersect(const Box& o) const
  {
    Box r;
    for (int a = 0; a < 3; ++a)
    {
      r.e[2 * a] = std::max(e[2 * a], o.e[2 * a]);
      r.e[2 * a + 1] = std::min(e[2 * a + 1], o.e[2 * a + 1]);
    }
    return r;
  }
};

namespace gather_detail
{
constexpr int kHeaderTag = 73310;
constexpr int kDataTag = 73311;

// Calls f(rowInFrom, rowInTo, tuples) for every x-run of `part`, where `from` and `to` are
// the boxes two arrays cover (x fastest).
template <typename F>
void forEachRun(const Box& part, const Box& from, const Box& to, F f)
{
  const std::int64_t n = part.Dim(0);
  for (int k = part.e[4]; k <= part.e[5]; ++k)
  {
    for (int j = part.e[2]; j <= part.e[3]; ++j)
    {
      const std::int64_t a = (part.e[0] - from.e[0]) + from.Dim(0) * ((j - from.e[2]) + from.Dim(1) * (k - from.e[4]));
      const std::int64_t b = (part.e[0] - to.e[0]) + to.Dim(0) * ((j - to.e[2]) + to.Dim(1) * (k - to.e[4]));
      f(a, b, n);
    }
  }
}

inline std::size_t tupleBytes(vtkDataArray* a)
{
  return static_cast<std::size_t>(a->GetDataTypeSize()) * static_cast<std::size_t>(a->GetNumberOfComponents());
}

// The arrays that travel: every point data array but the producer's ghost marks, which
// describe its own split, not the block's.
inline vtkDataArray* travelling(vtkPointData* pd, int i)
{
  vtkDataArray* a = pd->GetArray(i);
  return a && !(a->GetName() && std::strcmp(a->GetName(), "vtkGhostType") == 0) ? a : nullptr;
}

// "name\ttype\tcomponents\n" per travelling array: what a receiver allocates.
inline std::string describeArrays(vtkPointData* pd)
{
  std::ostringstream os;
  for (int i = 0; i < pd->GetNumberOfArrays(); ++i)
  {
    if (vtkDataArray* a = travelling(pd, i))
    {
      os << (a->GetName() ? a->GetName() : "") << '\t' << a->GetDataType() << '\t' << a->GetNumberOfComponents() << '\n';
    }
  }
  return os.str();
}
} // namespace gather_detail

// Collective over `controller`. `local` holds box `have` (its extent), this process needs
// `need`. Returns `local` itself when every process holds what it needs; else a new image
// of extent `need` (origin and spacing of `local`) with every point array, filled from the
// processes' pieces. On failure (the pieces do not cover a needed voxel) returns nullptr
// and sets `error` on the process that misses it.
inline vtkSmartPointer<vtkImageData> gatherBlock(vtkImageData* local, const Box& need,
  vtkMultiProcessController* controller, std::string& error)
{
  using namespace gather_detail;
  Box have;
  local->GetExtent(have.e);
  if (local->GetNumberOfPoints() == 0)
  {
    have = Box();
  }
  const int R = controller->GetNumberOfProcesses(), me = controller->GetLocalProcessId();
  int mine[13];
  std::copy(have.e, have.e + 6, mine);
  std::copy(need.e, need.e + 6, mine + 6);
  mine[12] = have.Contains(need) ? 1 : 0;
  std::vector<int> all(static_cast<std::size_t>(13 * R));
  controller->AllGather(mine, all.data(), 13);
  bool everyoneHasIt = true;
  std::vector<Box> haves(R), needs(R);
  for (int r = 0; r < R; ++r)
  {
    std::copy(&all[13 * r], &all[13 * r] + 6, haves[r].e);
    std::copy(&all[13 * r + 6], &all[13 * r] + 12, needs[r].e);
    everyoneHasIt = everyoneHasIt && all[13 * r + 12] == 1;
  }
  if (everyoneHasIt)
  {
    return local;
  }

  auto block = vtkSmartPointer<vtkImageData>::New();
  block->SetExtent(const_cast<int*>(need.e));
  block->SetOrigin(local->GetOrigin());
  block->SetSpacing(local->GetSpacing());
  block->SetDirectionMatrix(local->GetDirectionMatrix());
  std::vector<unsigned char> covered(static_cast<std::size_t>(need.Count()), 0);
  bool allocated = false;

  // The arrays of `block`, made on the first piece that arrives (this process's own one
  // when it holds any), from a description.
  auto allocate = [&](const std::string& description) {
    if (allocated || description.empty())
    {
      return;
    }
    std::istringstream is(description);
    std::string line;
    while (std::getline(is, line))
    {
      std::istringstream fields(line);
      std::string name, type, components;
      std::getline(fields, name, '\t');
      std::getline(fields, type, '\t');
      std::getline(fields, components, '\t');
      vtkSmartPointer<vtkDataArray> a;
      a.TakeReference(vtkDataArray::CreateDataArray(std::stoi(type)));
      a->SetName(name.c_str());
      a->SetNumberOfComponents(std::stoi(components));
      a->SetNumberOfTuples(need.Count());
      block->GetPointData()->AddArray(a);
    }
    allocated = true;
  };
  // Copies the part of box `from` held in the arrays `source` (or raw `bytes`) into block.
  auto place = [&](const Box& part, const Box& from, vtkPointData* source, const char* bytes) {
    vtkPointData* to = block->GetPointData();
    std::size_t offset = 0; // into bytes
    for (int i = 0; i < to->GetNumberOfArrays(); ++i)
    {
      vtkDataArray* out = to->GetArray(i);
      const std::size_t tb = tupleBytes(out);
      const char* in = nullptr;
      if (source)
      {
        vtkDataArray* s = source->GetArray(out->GetName());
        if (!s || tupleBytes(s) != tb)
        {
          continue;
        }
        in = static_cast<const char*>(s->GetVoidPointer(0));
      }
      char* dst = static_cast<char*>(out->GetVoidPointer(0));
      if (bytes)
      {
        forEachRun(part, part, need, [&](std::int64_t a, std::int64_t b, std::int64_t n) {
          std::memcpy(dst + b * tb, bytes + offset + a * tb, n * tb);
        });
        offset += static_cast<std::size_t>(part.Count()) * tb;
      }
      else
      {
        forEachRun(part, from, need, [&](std::int64_t a, std::int64_t b, std::int64_t n) {
          std::memcpy(dst + b * tb, in + a * tb, n * tb);
        });
      }
    }
    forEachRun(part, part, need, [&](std::int64_t, std::int64_t b, std::int64_t n) {
      std::fill(covered.begin() + b, covered.begin() + b + n, 1);
    });
  };

  // This process's own share first.
  const Box own = have.Intersect(need);
  if (!own.Empty())
  {
    allocate(describeArrays(local->GetPointData()));
    place(own, have, local->GetPointData(), nullptr);
  }

  // Pairs in one global order (i < j, lexicographic): the lower rank sends, then receives;
  // every pair a process takes part in comes in the same order on both sides, so the
  // blocking sends and receives cannot wait on each other in a cycle.
  auto send = [&](int to) {
    const Box part = have.Intersect(needs[to]);
    if (part.Empty())
    {
      return;
    }
    const std::string description = describeArrays(local->GetPointData());
    const int length = static_cast<int>(description.size());
    controller->Send(&length, 1, to, kHeaderTag);
    controller->Send(description.data(), length, to, kHeaderTag);
    std::vector<char> bytes;
    vtkPointData* pd = local->GetPointData();
    for (int i = 0; i < pd->GetNumberOfArrays(); ++i)
    {
      vtkDataArray* a = travelling(pd, i);
      if (!a)
      {
        continue;
      }
      const std::size_t tb = tupleBytes(a);
      const std::size_t start = bytes.size();
      bytes.resize(start + static_cast<std::size_t>(part.Count()) * tb);
      const char* in = static_cast<const char*>(a->GetVoidPointer(0));
      forEachRun(part, have, part, [&](std::int64_t s, std::int64_t d, std::int64_t n) {
        std::memcpy(bytes.data() + start + d * tb, in + s * tb, n * tb);
      });
    }
    controller->Send(bytes.data(), static_cast<vtkIdType>(bytes.size()), to, kDataTag);
  };
  auto receive = [&](int from) {
    const Box part = haves[from].Intersect(need);
    if (part.Empty())
    {
      return;
    }
    int length = 0;
    controller->Receive(&length, 1, from, kHeaderTag);
    std::string description(static_cast<std::size_t>(length), '\0');
    controller->Receive(&description[0], length, from, kHeaderTag);
    allocate(description);
    std::size_t total = 0;
    vtkPointData* to = block->GetPointData();
    for (int i = 0; i < to->GetNumberOfArrays(); ++i)
    {
      total += static_cast<std::size_t>(part.Count()) * tupleBytes(to->GetArray(i));
    }
    std::vector<char> bytes(total);
    controller->Receive(bytes.data(), static_cast<vtkIdType>(total), from, kDataTag);
    place(part, part, nullptr, bytes.data());
  };
  for (int i = 0; i < R; ++i)
  {
    for (int j = i + 1; j < R; ++j)
    {
      if (me == i)
      {
        send(j);
        receive(j);
      }
      else if (me == j)
      {
        receive(i);
        send(i);
      }
    }
  }

  const auto missing = std::count(covered.begin(), covered.end(), 0);
  if (missing > 0)
  {
    std::ostringstream os;
    os << "The input's pieces do not cover the block this process needs (" << missing
       << " voxels of extent " << need.e[0] << " " << need.e[1] << " " << need.e[2] << " " << need.e[3] << " "
       << need.e[4] << " " << need.e[5] << " are held by no process).";
    error = os.str();
    return nullptr;
  }
  return block;
}

} // namespace vtkhelpers
} // namespace mcv
