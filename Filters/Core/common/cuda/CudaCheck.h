// Error handling of the CUDA path: every CUDA call is checked; a failure becomes `false`
// with a message (file, line, call, CUDA's own words) so the core can fall back to the CPU.
// A sticky error (the context is lost until the process ends) is also recorded, so that
// later GPU requests go to the CPU at once (contextLost in DeviceProbe.h). Checked calls
// are the injection points of FaultInjection.h.
#pragma once

#include "FaultInjection.h"

#include <cuda_runtime.h>

#include <string>

namespace mcv
{
namespace cuda
{
namespace detail
{

inline bool fail(std::string* error, const std::string& message)
{
  if (error)
  {
    *error = message;
  }
  return false;
}

// True for the errors after which every further CUDA call of the process fails too.
bool isStickyError(cudaError_t code);
// Remembers the first sticky error (see contextLost).
void noteStickyError(const std::string& message);

inline bool fail(std::string* error, cudaError_t code, const char* call, const char* file, int line,
  bool injected = false)
{
  (void)cudaGetLastError(); // clear a non-sticky error so later calls start clean
  std::string where = file;
  const auto slash = where.find_last_of('/');
  if (slash != std::string::npos)
  {
    where = where.substr(slash + 1);
  }
  std::string message = std::string("CUDA error ") + cudaGetErrorName(code) + " (" +
    cudaGetErrorString(code) + ") in " + call + " at " + where + ":" + std::to_string(line);
  if (injected)
  {
    message += " [injected failure]";
  }
  else if (isStickyError(code))
  {
    message += "; the GPU is unusable until the process restarts";
    noteStickyError(message);
  }
  return fail(error, message);
}

} // namespace detail
} // namespace cuda
} // namespace mcv

// Evaluates a cudaError_t expression; on failure sets *error (a std::string*) and returns
// false. With an injection armed (FaultInjection.h) the chosen call reports
// cudaErrorMemoryAllocation instead of running.
#define MCV_CUDA_TRY(expr)                                                                        \
  do                                                                                              \
  {                                                                                               \
    constexpr ::mcv::cuda::CudaCall mcvCudaKind_ = ::mcv::cuda::detail::classifyCudaCall(#expr);  \
    const bool mcvCudaInjected_ =                                                                 \
      ::mcv::cuda::detail::faultHooksOn() && ::mcv::cuda::detail::takeInjectedFault(mcvCudaKind_); \
    const cudaError_t mcvCudaErr_ = mcvCudaInjected_ ? cudaErrorMemoryAllocation : (expr);        \
    if (mcvCudaErr_ != cudaSuccess)                                                               \
    {                                                                                             \
      return ::mcv::cuda::detail::fail(                                                           \
        error, mcvCudaErr_, #expr, __FILE__, __LINE__, mcvCudaInjected_);                         \
    }                                                                                             \
  } while (0)
