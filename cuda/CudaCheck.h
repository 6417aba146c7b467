// Error handling of the CUDA path: every CUDA call is checked; a failure becomes `false`
// with a message (file, line, call, CUDA's own words) so the core can fall back to the CPU.
#pragma once

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

inline bool fail(std::string* error, cudaError_t code, const char* call, const char* file, int line)
{
  (void)cudaGetLastError(); // clear a non-sticky error so later calls start clean
  std::string where = file;
  const auto slash = where.find_last_of('/');
  if (slash != std::string::npos)
  {
    where = where.substr(slash + 1);
  }
  return fail(error,
    std::string("CUDA error ") + cudaGetErrorName(code) + " (" + cudaGetErrorString(code) +
      ") in " + call + " at " + where + ":" + std::to_string(line));
}

} // namespace detail
} // namespace cuda
} // namespace mcv

// Evaluates a cudaError_t expression; on failure sets *error (a std::string*) and returns false.
#define MCV_CUDA_TRY(expr)                                                                        \
  do                                                                                              \
  {                                                                                               \
    const cudaError_t mcvCudaErr_ = (expr);                                                       \
    if (mcvCudaErr_ != cudaSuccess)                                                               \
    {                                                                                             \
      return ::mcv::cuda::detail::fail(error, mcvCudaErr_, #expr, __FILE__, __LINE__);            \
    }                                                                                             \
  } while (0)
