// The sticky-error record of CudaCheck.h and contextLost (DeviceProbe.h).
#include "CudaCheck.h"
#include "DeviceProbe.h"

#include <atomic>
#include <mutex>

namespace mcv
{
namespace cuda
{

namespace
{
std::atomic<bool> lost{ false };
std::mutex lostMutex;
std::string lostReason;
} // namespace

namespace detail
{

bool isStickyError(cudaError_t code)
{
  // The errors documented as "any further CUDA work will return the same error".
  switch (code)
  {
    case cudaErrorIllegalAddress:
    case cudaErrorLaunchTimeout:
    case cudaErrorAssert:
    case cudaErrorHardwareStackError:
    case cudaErrorIllegalInstruction:
    case cudaErrorMisalignedAddress:
    case cudaErrorInvalidAddressSpace:
    case cudaErrorInvalidPc:
    case cudaErrorLaunchFailure:
    case cudaErrorECCUncorrectable:
    case cudaErrorMpsClientTerminated:
      return true;
    default:
      return false;
  }
}

void noteStickyError(const std::string& message)
{
  std::lock_guard<std::mutex> lock(lostMutex);
  if (!lost.load())
  {
    lostReason = message;
    lost.store(true);
  }
}

} // namespace detail

bool contextLost(std::string* reason)
{
  if (!lost.load(std::memory_order_acquire))
  {
    return false;
  }
  if (reason)
  {
    std::lock_guard<std::mutex> lock(lostMutex);
    *reason = "an earlier CUDA failure left the GPU unusable until the process restarts (" +
      lostReason + ")";
  }
  return true;
}

} // namespace cuda
} // namespace mcv
