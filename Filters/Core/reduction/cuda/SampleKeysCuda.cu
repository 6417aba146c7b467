// The sampler's key scan on the GPU: every voxel's key, the ones at or below the limit
// compacted (an atomic counter; put in order on the host, they are few).
#include "SampleKeysCuda.h"

#include "cuda/CudaCheck.h"
#include "cuda/DeviceBuffer.cuh"

#include <algorithm>

namespace mcv
{
namespace cuda
{

namespace
{

// Must equal Filters/Core/common/SeededRandom.h's mix64 and ReferenceSample.cpp's sampleKey
// (TestSampleKeysGPU compares them): integer arithmetic, so the same bits on any device.
__device__ __forceinline__ std::uint64_t mix64(std::uint64_t z)
{
  z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
  z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
  return z ^ (z >> 31);
}

__global__ void keysAtMostKernel(std::uint64_t seedMix, std::int64_t firstGlobal, std::uint64_t n,
  std::uint64_t limit, unsigned long long* rows, unsigned long long capacity, unsigned long long* count)
{
  for (std::uint64_t r = blockIdx.x * static_cast<std::uint64_t>(blockDim.x) + threadIdx.x; r < n;
       r += static_cast<std::uint64_t>(gridDim.x) * blockDim.x)
  {
    const std::uint64_t key = mix64(static_cast<std::uint64_t>(firstGlobal) + r + seedMix);
    if (key <= limit)
    {
      const unsigned long long at = atomicAdd(count, 1ull);
      if (at < capacity)
      {
        rows[at] = r;
      }
    }
  }
}

std::uint64_t hostMix64(std::uint64_t z)
{
  z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
  z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
  return z ^ (z >> 31);
}

// The distinct rows `found` (each below n), ascending. A sort of the 150 000 rows of the
// brain's largest scan (of 7.1 M) took milliseconds on the host; marking them in a bitmap
// of n bits and reading it in order is O(n / 64 + count). Few rows: the sort is cheaper.
void ascendingRows(const std::vector<unsigned long long>& found, std::size_t n, std::vector<std::size_t>* rows)
{
  rows->assign(found.begin(), found.end());
  if (found.size() * 1024 < n)
  {
    std::sort(rows->begin(), rows->end());
    return;
  }
  std::vector<std::uint64_t> bits((n + 63) / 64, 0);
  for (const unsigned long long r : found)
  {
    bits[r >> 6] |= std::uint64_t(1) << (r & 63);
  }
  std::size_t at = 0;
  for (std::size_t w = 0; w < bits.size(); ++w)
  {
    for (std::uint64_t b = bits[w]; b != 0; b &= b - 1)
    {
      (*rows)[at++] = w * 64 + static_cast<std::size_t>(__builtin_ctzll(b));
    }
  }
}

} // namespace

bool rowsWithKeyAtMost(std::uint64_t seed, std::int64_t firstGlobal, std::size_t n, std::uint64_t limit,
  std::vector<std::size_t>* rows, std::string* error)
{
  FaultStage stage("samplekeys");
  rows->clear();
  if (n == 0)
  {
    return true;
  }
  // The expected count (keys are uniform over 64 bits) with a margin; a second launch with
  // the exact count when the margin was not enough.
  const double expected = static_cast<double>(n) * (static_cast<double>(limit) / 18446744073709551616.0);
  unsigned long long capacity =
    static_cast<unsigned long long>(std::min(static_cast<double>(n), 1.25 * expected + 4096.0));
  const std::uint64_t seedMix = hostMix64(seed + 0x9E3779B97F4A7C15ull);
  const int blocks = static_cast<int>(std::min<std::size_t>((n + 255) / 256, 132 * 64));
  for (int attempt = 0; attempt < 2; ++attempt)
  {
    DeviceBuffer found, count;
    MCV_CUDA_TRY(cudaMalloc(&found.ptr, std::max<unsigned long long>(1, capacity) * sizeof(unsigned long long)));
    MCV_CUDA_TRY(cudaMalloc(&count.ptr, sizeof(unsigned long long)));
    MCV_CUDA_TRY(cudaMemset(count.ptr, 0, sizeof(unsigned long long)));
    keysAtMostKernel<<<blocks, 256>>>(seedMix, firstGlobal, n, limit, found.as<unsigned long long>(), capacity,
      count.as<unsigned long long>());
    MCV_CUDA_TRY(cudaGetLastError());
    unsigned long long total = 0;
    MCV_CUDA_TRY(cudaMemcpy(&total, count.ptr, sizeof total, cudaMemcpyDeviceToHost));
    if (total <= capacity)
    {
      std::vector<unsigned long long> out(total);
      if (total > 0)
      {
        MCV_CUDA_TRY(cudaMemcpy(out.data(), found.ptr, total * sizeof(unsigned long long), cudaMemcpyDeviceToHost));
      }
      ascendingRows(out, n, rows);
      return true;
    }
    capacity = total;
  }
  return detail::fail(error, "the GPU key scan found more keys than it counted");
}

} // namespace cuda
} // namespace mcv
