// deviceUsable (DeviceProbe.h): driver, device, context, and whether this build holds GPU
// code for the device. contextLost lives beside the sticky-error record (CudaCheck.cpp).
#include "DeviceProbe.h"

#include <cuda_runtime.h>

#include <string>

namespace mcv
{
namespace cuda
{

namespace
{

// Does nothing. Every GPU library of the build is compiled for the same architectures
// (CMAKE_CUDA_ARCHITECTURES), so whether the runtime finds code of this one for the device
// answers for all of them.
__global__ void probeKernel() {}

bool setReason(std::string* reason, const std::string& why)
{
  if (reason)
  {
    *reason = why;
  }
  return false;
}

} // namespace

bool deviceUsable(std::string* reason)
{
  std::string lost;
  if (contextLost(&lost))
  {
    return setReason(reason, lost);
  }
  int count = 0;
  cudaError_t err = cudaGetDeviceCount(&count);
  if (err != cudaSuccess)
  {
    // Without a driver (or with one too old) the count is undefined: never read it.
    (void)cudaGetLastError();
    return setReason(reason, std::string("no usable CUDA driver: ") + cudaGetErrorString(err));
  }
  if (count <= 0)
  {
    return setReason(reason, "no CUDA device");
  }
  int device = 0, major = 0, minor = 0;
  if ((err = cudaGetDevice(&device)) != cudaSuccess ||
    (err = cudaDeviceGetAttribute(&major, cudaDevAttrComputeCapabilityMajor, device)) != cudaSuccess ||
    (err = cudaDeviceGetAttribute(&minor, cudaDevAttrComputeCapabilityMinor, device)) != cudaSuccess)
  {
    (void)cudaGetLastError();
    return setReason(reason, std::string("cannot query the CUDA device: ") + cudaGetErrorString(err));
  }
  if ((err = cudaFree(nullptr)) != cudaSuccess) // creates the context: busy/unavailable devices
  {
    (void)cudaGetLastError();
    return setReason(reason, std::string("cannot use CUDA device ") + std::to_string(device) +
        ": " + cudaGetErrorString(err));
  }
  cudaFuncAttributes attributes;
  if ((err = cudaFuncGetAttributes(&attributes, probeKernel)) != cudaSuccess)
  {
    (void)cudaGetLastError();
    return setReason(reason, "this build has no GPU code for compute capability " +
        std::to_string(major) + "." + std::to_string(minor) + " (" + cudaGetErrorString(err) + ")");
  }
  return true;
}

std::size_t sharedMemoryPerBlockOptin()
{
  int device = 0, optin = 0;
  if (cudaGetDevice(&device) != cudaSuccess ||
    cudaDeviceGetAttribute(&optin, cudaDevAttrMaxSharedMemoryPerBlockOptin, device) != cudaSuccess)
  {
    (void)cudaGetLastError();
    return 0;
  }
  return optin > 0 ? static_cast<std::size_t>(optin) : 0;
}

} // namespace cuda
} // namespace mcv
