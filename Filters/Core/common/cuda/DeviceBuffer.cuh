// One cudaMalloc'd allocation owned by a scope: freed when it ends, so every early return
// after a failed CUDA call leaves nothing allocated (the GPU paths fall back to the CPU and
// must not leak). Movable, not copyable.
#pragma once

#include "CudaCheck.h"

#include <cuda_runtime.h>

#include <cstddef>
#include <string>

namespace mcv
{
namespace cuda
{

struct DeviceBuffer
{
  void* ptr = nullptr;
  DeviceBuffer() = default;
  DeviceBuffer(const DeviceBuffer&) = delete;
  DeviceBuffer& operator=(const DeviceBuffer&) = delete;
  DeviceBuffer(DeviceBuffer&& o) noexcept
    : ptr(o.ptr)
  {
    o.ptr = nullptr;
  }
  ~DeviceBuffer()
  {
    if (ptr)
    {
      cudaFree(ptr);
    }
  }
  template <class T>
  T* as() const
  {
    return static_cast<T*>(ptr);
  }
};

// Keeps a reused device allocation `buffer` of `capacity` bytes at least `bytes` large:
// kept when it is, else freed and allocated anew (its contents are not kept). False with
// `error` set on a CUDA failure.
inline bool growDeviceBuffer(void*& buffer, std::size_t& capacity, std::size_t bytes, std::string* error)
{
  if (buffer && bytes <= capacity)
  {
    return true;
  }
  if (buffer)
  {
    MCV_CUDA_TRY(cudaFree(buffer));
    buffer = nullptr;
    capacity = 0;
  }
  MCV_CUDA_TRY(cudaMalloc(&buffer, bytes));
  capacity = bytes;
  return true;
}

} // namespace cuda
} // namespace mcv
