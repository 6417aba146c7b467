// The fused reduction's GPU placement: the slab stream (SlabStream.cuh: channels up, features
// and normalisation on the device) with the placement of each slab there and its
// coordinates down.
#include "FusedPlacementCuda.h"

#include "cuda/CudaCheck.h"
#include "SlabStream.cuh"
#include "cuda/StagingCopy.h"

#include <cstring>

namespace mcv
{
namespace cuda
{

namespace
{
// The placement's part of the slab stream: its references, scratch and coordinates.
SlabStreamSetup streamSetup(const FusedPlacementSetup& s)
{
  SlabStreamSetup st = slabStreamSetup(s);
  const PlacementInput& r = s.references;
  st.pass.fixedDevice = PlacementOnDevice::referenceBytes(r.M, r.D, r.d);
  // Coordinates on the device and in pinned memory, per row; the placement's scratch per slot.
  // With distances to a model, one float more per row.
  const std::size_t perRow = (static_cast<std::size_t>(r.d) + (s.writeDistances ? 1 : 0)) * sizeof(float);
  st.pass.perRowDevice = perRow;
  st.pass.perSlotDevice = [](std::size_t rows) { return PlacementOnDevice::scratchBytesPerSlot(rows); };
  st.pass.perRowPinned = perRow;
  return st;
}

// Device coordinates of each slot, given back however the placement ends.
struct Coordinates
{
  float* slot[kSlabSlots] = { nullptr, nullptr };
  ~Coordinates()
  {
    for (float* p : slot)
    {
      cudaFree(p);
    }
  }
};
} // namespace

std::size_t fusedPlacementBytes(const FusedPlacementSetup& setup, int slices)
{
  return SlabStream::bytesFor(streamSetup(setup), slices);
}

bool placeFused(const FusedPlacementSetup& setup, const FusedChannelFill& fill, float* out,
  const std::function<void(double)>& progress, FusedPlacementStats* statsOut, std::size_t* rowsDone,
  std::string* error)
{
  FaultStage stage("fused");
  FusedPlacementStats local;
  FusedPlacementStats& st = statsOut ? *statsOut : local;
  st = FusedPlacementStats{};
  std::size_t doneLocal = 0;
  std::size_t& done = rowsDone ? *rowsDone : doneLocal;
  done = 0;

  const int d = setup.references.d;
  const std::size_t total = setup.grid.voxelCount();
  if (setup.offset.size() != static_cast<std::size_t>(setup.cols) || setup.references.dim != setup.cols || !fill ||
    (!out && !setup.writeCoordinates))
  {
    return detail::fail(error, "invalid arguments of the GPU fused placement");
  }
  if (total == 0)
  {
    return true;
  }
  // Declared before the stream, so that the stream's destructor (which waits for the
  // device) runs before these buffers are freed.
  PlacementOnDevice placement;
  Coordinates coords;
  SlabStream stream;
  if (!stream.open(streamSetup(setup), error))
  {
    return false;
  }
  const std::size_t slabRows = stream.slabRows();
  if (!placement.upload(setup.references, stream.slotsUsed(), slabRows, error))
  {
    return false;
  }
  // Per slot: the coordinates, then (with writeDistances) one distance per row.
  const bool distances = static_cast<bool>(setup.writeDistances);
  const std::size_t perRow = static_cast<std::size_t>(d) + (distances ? 1 : 0);
  for (int i = 0; i < stream.slotsUsed(); ++i)
  {
    MCV_CUDA_TRY(cudaMalloc(&coords.slot[i], slabRows * perRow * sizeof(float)));
  }
  SlabStreamStats& ss = stream.stats();
  const PlacementInput& r = setup.references;
  ss.bytesToDevice += PlacementOnDevice::referenceBytes(r.M, r.D, r.d);

  const auto launch = [&](Slab& s) -> bool {
    float* slot = coords.slot[s.slot];
    float* distance = distances ? slot + s.rows * static_cast<std::size_t>(d) : nullptr;
    if (!placement.place(s.features, s.rows, slot, nullptr, s.slot, s.stream, setup.mergeEqualRows, error, distance,
          setup.modelRadius))
    {
      return false;
    }
    // Coordinates and distances lie one after the other: one copy down.
    MCV_CUDA_TRY(cudaMemcpyAsync(s.pinned, slot, s.rows * perRow * sizeof(float), cudaMemcpyDeviceToHost, s.stream));
    ss.bytesFromDevice += s.rows * perRow * sizeof(float);
    return true;
  };
  const auto finished = [&](const Slab& s) -> bool {
    const float* values = reinterpret_cast<const float*>(s.pinned);
    if (setup.writeCoordinates)
    {
      setup.writeCoordinates(s.firstRow, s.rows, values);
    }
    else
    {
      detail::stagingCopy(out + s.firstRow * static_cast<std::size_t>(d), values, s.rows * static_cast<std::size_t>(d) * sizeof(float));
    }
    if (distances)
    {
      setup.writeDistances(s.firstRow, s.rows, values + s.rows * static_cast<std::size_t>(d));
    }
    done = s.firstRow + s.rows;
    if (progress)
    {
      progress(static_cast<double>(done) / static_cast<double>(total));
    }
    return true;
  };
  const bool ok = stream.run(fill, launch, finished, error) && placement.radiusScans(&st.radiusScans, error);
  st.slabSlices = ss.slabSlices;
  st.slabs = ss.slabs;
  st.bytesToDevice = ss.bytesToDevice;
  st.bytesFromDevice = ss.bytesFromDevice;
  st.deviceBytes = ss.deviceBytes;
  st.deviceUsedPeak = ss.deviceUsedPeak;
  st.pinnedBytes = ss.pinnedBytes;
  st.setupMs = ss.setupMs;
  st.fillMs = ss.fillMs;
  st.waitMs = ss.waitMs;
  st.totalMs = ss.totalMs;
  return ok;
}

} // namespace cuda
} // namespace mcv
