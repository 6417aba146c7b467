#include "Device.h"
#include "EnumNames.h"

#ifdef MCV_HAS_CUDA
#include "cuda/DeviceProbe.h"
#endif

#include <mutex>

namespace mcv
{

const char* deviceName(Device device)
{
  static const EnumName<Device> names[] = { { Device::Auto, "Auto" }, { Device::CPU, "CPU" },
    { Device::GPU, "GPU" } };
  return nameOf(names, device, "unknown");
}

bool gpuUsable(std::string* reason)
{
  // Asking the driver once is enough: a GPU does not come while we run (it can be lost).
  static std::once_flag once;
  static bool usable = false;
  static std::string why;
  std::call_once(once, [] {
#ifdef MCV_HAS_CUDA
    usable = cuda::deviceUsable(&why);
#else
    why = "this build has no CUDA support";
#endif
  });
  if (!usable && reason)
  {
    *reason = why;
  }
#ifdef MCV_HAS_CUDA
  // A sticky CUDA error (illegal address, ...) loses the GPU for the rest of the process.
  if (usable && cuda::contextLost(reason))
  {
    return false;
  }
#endif
  return usable;
}

Device resolveDevice(Device requested, std::string* warning)
{
  if (requested == Device::CPU)
  {
    return Device::CPU;
  }
  std::string why;
  if (gpuUsable(&why))
  {
    return Device::GPU;
  }
  if (warning && requested == Device::GPU)
  {
    *warning = std::string("Device GPU: no usable GPU (") + why + "); running on the CPU.";
  }
  return Device::CPU;
}

} // namespace mcv
