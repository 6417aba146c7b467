// Where a computation runs. Every core entry point that has a GPU path takes a Device.
#pragma once

#include <string>

namespace mcv
{

enum class Device
{
  Auto = 0, // the GPU when one is usable, else the CPU (no warning: the expected case on a
            // machine without a GPU; the VTK layer logs why once, see gpuUsable)
  CPU = 1,
  GPU = 2 // the GPU; falls back to the CPU with a warning when none is usable
};

const char* deviceName(Device device);

// True when this build has CUDA and a CUDA GPU can be used now. On false, `reason`
// (if given) says why: built without CUDA, no driver, no device, or an earlier sticky CUDA
// error (illegal address, ...) that lost the GPU for the rest of the process...
bool gpuUsable(std::string* reason = nullptr);

// Resolves Auto/GPU to what will really run. `warning` receives a one-line message when
// the request cannot be honoured (GPU asked, none usable); Auto picking the CPU is not one.
Device resolveDevice(Device requested, std::string* warning = nullptr);

} // namespace mcv
