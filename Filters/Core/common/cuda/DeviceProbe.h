// Whether this process can use a GPU: the probe behind common/Device.cpp's gpuUsable. Plain
// C++ interface (no CUDA types), so the CPU code of the core can call it; built only when
// MCV_ENABLE_CUDA is on (the core then defines MCV_HAS_CUDA).
#pragma once

#include <cstddef>
#include <string>

namespace mcv
{
namespace cuda
{

// True when a CUDA device can be used and this build holds code it can run; else `reason`
// says why. Never reads the device count after an error: without a driver (or with one too
// old) the count is undefined.
bool deviceUsable(std::string* reason = nullptr);

// True once a sticky CUDA error (illegal address, launch failure, ...) has left this
// process's GPU context unusable; `reason` says which. Every later CUDA call would fail.
bool contextLost(std::string* reason = nullptr);

// The shared memory one block may opt in to on the current device, in bytes (what kernels
// that keep a whole row or graph in shared memory are sized by); 0 where there is no usable
// device.
std::size_t sharedMemoryPerBlockOptin();

} // namespace cuda
} // namespace mcv
