// GPU path of the Gaussian-widget transfer function (Filters/Core/transfer_function/GaussianTransferFunction.h).
// Plain C++ interface (no CUDA types), built only when MCV_ENABLE_CUDA is on. Every call
// returns false with `error` set on any CUDA failure (allocation included), so the core can
// fall back to the CPU.
//
// The widgets go to constant memory (at most GaussianTFMaxWidgets); the coordinates stay on
// the device between calls, uploaded again only when the host pointer, count, components or
// version change (version 0: always uploaded). One thread per voxel, the same float
// operations as the CPU path for the log-weights, expf for the exponentials.
#pragma once

#include "GaussianTransferFunction.h"
#include "NonCopyable.h"

#include <cstddef>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

namespace mcv
{
namespace cuda
{

constexpr std::size_t GaussianTFMaxWidgets = 1024; // 32 KB of constant memory

enum class GaussianTFOutput
{
  FloatRGBA, // 4 floats per voxel
  ByteRGBA,  // 4 bytes per voxel, round(255 v)
  Opacity    // 1 float per voxel
};

struct GaussianTFCoordinates
{
  const float* data = nullptr;
  std::size_t count = 0;
  int components = 3;
  std::uint64_t version = 0;
  // Instead of data: float16 coordinates (binary16 bits). They cross the bus as they are
  // (half the bytes) and are widened to float32 on the device, exactly (every binary16 is
  // a float32), so the kernel shades the same values as the CPU's decode.
  const std::uint16_t* halves = nullptr;
};

// Device-resident state: coordinates and one output buffer. The core uses one shared
// instance (shadeGaussianWidgetsCached); tests and benchmarks may hold their own to time
// the steps apart.
class GaussianTFGpu : NonCopyable
{
public:
  GaussianTFGpu();
  ~GaussianTFGpu();

  // Uploads the coordinates unless the same (data, count, components, non-zero version)
  // are already resident. `uploaded` (if given) says whether it copied.
  bool setCoordinates(const GaussianTFCoordinates& c, std::string* error, bool* uploaded = nullptr);

  // Runs the kernel into the device output buffer and waits for it.
  bool shade(const std::vector<mcv::detail::PackedGaussianWidget>& widgets, GaussianTFOutput kind,
    std::string* error);

  // The output of the last shade() into host memory (count x 4 floats/bytes, or count floats).
  bool download(void* hostOut, std::string* error);

  // Frees the device buffers.
  void release();

private:
  struct Impl;
  std::unique_ptr<Impl> P;
};

// setCoordinates + shade + download on the process-wide instance (serialised by a mutex).
// On a CUDA error the instance is released, so the next call starts clean.
bool shadeGaussianWidgetsCached(const GaussianTFCoordinates& coordinates,
  const std::vector<mcv::detail::PackedGaussianWidget>& widgets, GaussianTFOutput kind,
  void* hostOut, std::string* error);

void releaseGaussianTFCache();

} // namespace cuda
} // namespace mcv
