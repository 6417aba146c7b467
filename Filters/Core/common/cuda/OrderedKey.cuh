// An order-preserving float <-> int key (its own inverse), for integer atomicMin/atomicMax of
// floats on the device (the column statistics of FeaturesCuda.cu and FusedPassesCuda.cu);
// host and device alike.
#pragma once

#include <cstring>

namespace mcv
{
namespace cuda
{

__host__ __device__ inline int orderedKey(float f)
{
  int k;
  std::memcpy(&k, &f, sizeof k);
  return k >= 0 ? k : k ^ 0x7fffffff;
}

__host__ __device__ inline float fromOrderedKey(int k)
{
  const int bits = k >= 0 ? k : k ^ 0x7fffffff;
  float f;
  std::memcpy(&f, &bits, sizeof f);
  return f;
}

} // namespace cuda
} // namespace mcv
