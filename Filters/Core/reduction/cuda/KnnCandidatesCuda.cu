// The reference graph's float candidates on the GPU (KnnCandidatesCuda.h): one block per row;
// its n squared distances go into shared memory as 64-bit keys (the float's bits above the
// point's index: non-negative floats order as their bits, so the keys order by (distance,
// index) and are all different), a radix select (eight 8-bit digits) finds the kp-th
// smallest key, and the kp keys at or below it are ranked. Written here because CUB's block
// radix sort would sort all n keys per row where only kp of them are wanted.
#include "KnnCandidatesCuda.h"

#include "cuda/CudaCheck.h"
#include "cuda/DeviceBuffer.cuh"
#include "cuda/DeviceProbe.h"

#include <vector>

namespace mcv
{
namespace cuda
{

namespace
{

constexpr int kThreads = 256;

__global__ void __launch_bounds__(kThreads) candidatesKernel(const float* data, unsigned n, int dim, int kp,
  unsigned* outIdx, float* outF)
{
  extern __shared__ unsigned long long keys[];
  __shared__ float query[kMaxKnnCandidateDimension];
  __shared__ unsigned histogram[256];
  __shared__ unsigned long long chosen[kMaxKnnCandidatesOnDevice];
  __shared__ unsigned long long prefix, mask;
  __shared__ unsigned wanted, found;
  const unsigned row = blockIdx.x, tid = threadIdx.x;
  for (int c = static_cast<int>(tid); c < dim; c += blockDim.x)
  {
    query[c] = data[static_cast<std::size_t>(row) * dim + c];
  }
  if (tid == 0)
  {
    prefix = 0;
    mask = 0;
    wanted = static_cast<unsigned>(kp);
    found = 0;
  }
  __syncthreads();
  for (unsigned r = tid; r < n; r += blockDim.x)
  {
    const float* p = data + static_cast<std::size_t>(r) * dim;
    float s = 0.f;
    for (int c = 0; c < dim; ++c)
    {
      const float diff = query[c] - p[c];
      s += diff * diff;
    }
    keys[r] = (static_cast<unsigned long long>(__float_as_uint(s)) << 32) | r;
  }
  // The kp-th smallest key, digit by digit from the top: the keys that share the digits
  // found so far are counted by their next digit.
  for (int shift = 56; shift >= 0; shift -= 8)
  {
    histogram[tid] = 0; // kThreads == 256 bins
    __syncthreads();
    const unsigned long long m = mask, pre = prefix;
    for (unsigned r = tid; r < n; r += blockDim.x)
    {
      const unsigned long long key = keys[r];
      if ((key & m) == pre)
      {
        atomicAdd(&histogram[(key >> shift) & 255u], 1u);
      }
    }
    __syncthreads();
    if (tid == 0)
    {
      unsigned below = 0, digit = 0;
      while (below + histogram[digit] < wanted)
      {
        below += histogram[digit++];
      }
      wanted -= below;
      prefix |= static_cast<unsigned long long>(digit) << shift;
      mask |= 255ull << shift;
    }
    __syncthreads();
  }
  const unsigned long long last = prefix; // the kp-th smallest key itself
  for (unsigned r = tid; r < n; r += blockDim.x)
  {
    if (keys[r] <= last)
    {
      chosen[atomicAdd(&found, 1u)] = keys[r];
    }
  }
  __syncthreads();
  if (tid < static_cast<unsigned>(kp))
  {
    const unsigned long long mine = chosen[tid];
    int rank = 0;
    for (int j = 0; j < kp; ++j)
    {
      rank += chosen[j] < mine;
    }
    const std::size_t at = static_cast<std::size_t>(row) * kp + rank;
    outIdx[at] = static_cast<unsigned>(mine & 0xFFFFFFFFu);
    outF[at] = __uint_as_float(static_cast<unsigned>(mine >> 32));
  }
}

} // namespace

std::size_t knnCandidatesMaxPoints()
{
  // The kernel's static shared variables: the query, the histogram, the chosen keys.
  const std::size_t optin = sharedMemoryPerBlockOptin();
  const std::size_t fixed = kMaxKnnCandidateDimension * 4 + 256 * 4 + kMaxKnnCandidatesOnDevice * 8 + 64;
  return optin > fixed ? (optin - fixed) / 8 : 0;
}

bool knnCandidates(const float* data, std::size_t n, int dim, int kp, std::uint32_t* idx, float* f, std::string* error)
{
  FaultStage stage("isomapfit");
  if (n == 0)
  {
    return true;
  }
  if (kp <= 0 || kp > kMaxKnnCandidatesOnDevice || static_cast<std::size_t>(kp) > n || dim <= 0 ||
    dim > kMaxKnnCandidateDimension || n > knnCandidatesMaxPoints() || n > 0xFFFFFFFFull)
  {
    return detail::fail(error, "the GPU neighbour search takes up to " + std::to_string(knnCandidatesMaxPoints()) +
      " points of up to " + std::to_string(kMaxKnnCandidateDimension) + " dimensions and " +
      std::to_string(kMaxKnnCandidatesOnDevice) + " candidates (asked: " + std::to_string(n) + ", " +
      std::to_string(dim) + ", " + std::to_string(kp) + ")");
  }
  const std::size_t values = n * static_cast<std::size_t>(dim), out = n * static_cast<std::size_t>(kp);
  DeviceBuffer dData, dIdx, dF;
  MCV_CUDA_TRY(cudaMalloc(&dData.ptr, values * sizeof(float)));
  MCV_CUDA_TRY(cudaMalloc(&dIdx.ptr, out * sizeof(unsigned)));
  MCV_CUDA_TRY(cudaMalloc(&dF.ptr, out * sizeof(float)));
  MCV_CUDA_TRY(cudaMemcpy(dData.ptr, data, values * sizeof(float), cudaMemcpyHostToDevice));
  const std::size_t bytes = n * sizeof(unsigned long long);
  MCV_CUDA_TRY(cudaFuncSetAttribute(candidatesKernel, cudaFuncAttributeMaxDynamicSharedMemorySize, static_cast<int>(bytes)));
  candidatesKernel<<<static_cast<unsigned>(n), kThreads, bytes>>>(
    dData.as<float>(), static_cast<unsigned>(n), dim, kp, dIdx.as<unsigned>(), dF.as<float>());
  MCV_CUDA_TRY(cudaGetLastError());
  MCV_CUDA_TRY(cudaMemcpy(idx, dIdx.ptr, out * sizeof(unsigned), cudaMemcpyDeviceToHost));
  MCV_CUDA_TRY(cudaMemcpy(f, dF.ptr, out * sizeof(float), cudaMemcpyDeviceToHost));
  return true;
}

} // namespace cuda
} // namespace mcv
