// The plain C++ entry points of the GPU path (HarrisCuda.h), on one shared device-resident
// pipeline: its buffers stay allocated between calls (the best viewpoint is recomputed at
// every transfer-function edit), and grow to the largest volume seen.
#include "HarrisCuda.h"

#include "cuda/CudaCheck.h"
#include "HarrisKernel.cuh"
#include "HarrisPipeline.h"
#include "HarrisSlabStream.h"

#include <mutex>

namespace mcv
{
namespace cuda
{

namespace
{

std::mutex& pipelineMutex()
{
  static std::mutex m;
  return m;
}

// Never destroyed: freeing device memory from a static destructor can run after the CUDA
// runtime has shut down; the driver reclaims everything at process exit.
HarrisPipeline& sharedPipeline()
{
  static HarrisPipeline* p = new HarrisPipeline;
  return *p;
}

HarrisSlabStream& sharedSlabStream() // never destroyed, as sharedPipeline()
{
  static HarrisSlabStream* s = new HarrisSlabStream;
  return *s;
}

std::size_t& budgetLimit() // guarded by pipelineMutex()
{
  static std::size_t bytes = 0;
  return bytes;
}

// After a failure at any step: the buffers may be half allocated or hold half a result, and
// after an out-of-memory the memory is better given back. release() waits for the stream
// (no copy into the caller's memory is left running) and frees everything; the next call
// allocates again. The caller gets no partial points.
void releaseAfterFailure(HarrisPipeline& pipeline, InterestPoints* out)
{
  pipeline.release();
  if (out)
  {
    out->indices.clear();
    out->scores.clear();
  }
}

} // namespace

bool harrisTopN(const float* hostOpacity, const ImageGrid& grid, const HarrisParameters& params,
  int N, InterestPoints& out, std::string* error, GpuStageTimings* timings)
{
  std::lock_guard<std::mutex> lock(pipelineMutex());
  FaultStage stage("harris");
  HarrisPipeline& pipeline = sharedPipeline();
  out = InterestPoints();
  const char* why = gpuUnsupportedReason(grid, params);
  if (*why)
  {
    return detail::fail(error, why);
  }
  HarrisSlabStream& slabs = sharedSlabStream();
  const std::size_t budget = deviceBudgetBytes(
    budgetLimit(), pipeline.deviceBytesHeld() + slabs.deviceBytesHeld());
  if (grid.extendedAxes() == 3 && wholeVolumeDeviceBytes(grid, sizeof(float)) > budget)
  {
    pipeline.release(); // its memory counts in the budget: give it to the slabs
    slabs.setBudgetBytes(budget);
    SlabTimings st;
    if (slabs.topN(hostOpacity, grid, params, N, out, error, &st))
    {
      if (timings)
      {
        *timings = GpuStageTimings();
        timings->uploadMs = st.uploadMs;
        timings->harrisMs = st.harrisMs;
        timings->selectMs = st.selectMs + st.mergeMs;
        timings->slabs = st.slabs;
      }
      return true;
    }
    out = InterestPoints(); // the slab stream has freed its buffers
    return false;
  }
  slabs.release(); // the whole volume fits: the slab buffers would only take room
  if (pipeline.uploadVolume(hostOpacity, grid, error) &&
    pipeline.topN(params, N, out, error, timings))
  {
    return true;
  }
  releaseAfterFailure(pipeline, &out);
  return false;
}

bool harrisResponse(const float* hostOpacity, const ImageGrid& grid,
  const HarrisParameters& params, float* hostResponse, std::string* error)
{
  std::lock_guard<std::mutex> lock(pipelineMutex());
  FaultStage stage("harris");
  HarrisPipeline& pipeline = sharedPipeline();
  const char* why = gpuUnsupportedReason(grid, params);
  if (*why)
  {
    return detail::fail(error, why);
  }
  if (pipeline.uploadVolume(hostOpacity, grid, error) &&
    pipeline.response(params, hostResponse, error))
  {
    return true;
  }
  releaseAfterFailure(pipeline, nullptr);
  return false;
}

void setHarrisDeviceBudget(std::size_t bytes)
{
  std::lock_guard<std::mutex> lock(pipelineMutex());
  budgetLimit() = bytes;
}

void releaseHarrisCache()
{
  std::lock_guard<std::mutex> lock(pipelineMutex());
  sharedPipeline().release();
  sharedSlabStream().release();
}

} // namespace cuda
} // namespace mcv
