// Shortest paths from the landmarks and the MDS spectrum on the GPU (GeodesicsCuda.h).
//
// Shortest paths: one block per source, its distances and frontier flags in shared memory
// (10 B per vertex: the 10000-reference graph takes 100 KB). Rounds of Bellman-Ford over the
// frontier: every vertex whose distance dropped in the last round relaxes its edges (a warp
// per vertex, a lane per edge), a lower distance goes in with a 64-bit atomicMin on the
// double's bits (non-negative doubles order as their bit patterns), and the block stops
// after a round that changed nothing. Written here because neither CUB nor Thrust has a
// shortest-path routine, and a graph library on the device (Gunrock) is not a dependency
// of this project.
//
// Why the same bits as Dijkstra: a path's length is summed from the source edge by edge in
// double (d[u] + w), and rounding is monotone, so Dijkstra's answer for a vertex is the
// smallest such sum over all paths. The rounds stop only when no edge lowers its head, and
// every value they hold is the sum of some path; following the shortest path from the
// source, monotonicity gives each of its vertices at most that path's sum. So both are the
// same minimum, whatever order the relaxations ran in.
#include "GeodesicsCuda.h"

#include "cuda/CudaCheck.h"
#include "cuda/DeviceBuffer.cuh"
#include "cuda/DeviceProbe.h"

#ifdef MCV_HAS_CUSOLVER
#include <cusolverDn.h>
#endif

#include <vector>

namespace mcv
{
namespace cuda
{

namespace
{

constexpr int kThreads = 1024;
constexpr int kBytesPerVertex = 8 + 2;
constexpr unsigned long long kInfinityBits = 0x7FF0000000000000ull; // +inf as a double

__global__ void __launch_bounds__(kThreads, 2) geodesicsKernel(unsigned n, const unsigned long long* start,
  const std::uint32_t* to, const float* weight, const std::uint32_t* sources, double* out)
{
  extern __shared__ unsigned long long shared[];
  volatile unsigned long long* dist = shared;
  unsigned char* flagsA = reinterpret_cast<unsigned char*>(shared + n);
  unsigned char* flagsB = flagsA + n;
  // One "changed" flag per round, three in turn: round r clears round r + 1's, which was
  // last read before the barrier that closed round r - 1.
  __shared__ int changed[3];
  const unsigned tid = threadIdx.x;
  for (unsigned v = tid; v < n; v += blockDim.x)
  {
    dist[v] = kInfinityBits;
    flagsA[v] = 0;
    flagsB[v] = 0;
  }
  if (tid < 3)
  {
    changed[tid] = 0;
  }
  __syncthreads();
  const unsigned source = sources[blockIdx.x];
  if (tid == 0)
  {
    dist[source] = 0ull; // +0.0
    flagsA[source] = 1;
  }
  __syncthreads();

  unsigned char* current = flagsA;
  unsigned char* next = flagsB;
  const unsigned lane = tid & 31u, warp = tid >> 5, warps = blockDim.x >> 5;
  for (int round = 0;; ++round)
  {
    if (tid == 0)
    {
      changed[(round + 1) % 3] = 0;
    }
    for (unsigned base = warp * 32u; base < n; base += warps * 32u)
    {
      const unsigned v = base + lane;
      const bool active = v < n && current[v];
      if (active)
      {
        current[v] = 0;
      }
      unsigned mask = __ballot_sync(0xFFFFFFFFu, active);
      while (mask)
      {
        const unsigned u = base + static_cast<unsigned>(__ffs(static_cast<int>(mask)) - 1);
        mask &= mask - 1;
        const double du = __longlong_as_double(static_cast<long long>(dist[u]));
        const unsigned long long end = start[u + 1];
        for (unsigned long long e = start[u] + lane; e < end; e += 32u)
        {
          const std::uint32_t t = to[e];
          const double candidate = du + static_cast<double>(weight[e]);
          const unsigned long long bits = static_cast<unsigned long long>(__double_as_longlong(candidate));
          if (bits < dist[t] &&
            atomicMin(const_cast<unsigned long long*>(dist + t), bits) > bits)
          {
            next[t] = 1;
            changed[round % 3] = 1;
          }
        }
      }
    }
    __syncthreads();
    if (!changed[round % 3])
    {
      break;
    }
    unsigned char* swap = current;
    current = next;
    next = swap;
  }
  double* row = out + static_cast<std::size_t>(blockIdx.x) * n;
  for (unsigned v = tid; v < n; v += blockDim.x)
  {
    row[v] = __longlong_as_double(static_cast<long long>(dist[v]));
  }
}

} // namespace

std::size_t geodesicMaxVertices()
{
  const std::size_t optin = sharedMemoryPerBlockOptin();
  const std::size_t fixed = 64; // the kernel's own shared variables, with room
  return optin > fixed ? (optin - fixed) / kBytesPerVertex : 0;
}

bool geodesicDistances(std::size_t n, const std::size_t* start, const std::uint32_t* to, const float* weight,
  const std::uint32_t* sources, int count, double* dist, std::string* error)
{
  FaultStage stage("isomapfit");
  if (count <= 0 || n == 0)
  {
    return true;
  }
  if (n > geodesicMaxVertices())
  {
    return detail::fail(error, "the graph has " + std::to_string(n) + " vertices, more than one block's shared memory holds (" +
      std::to_string(geodesicMaxVertices()) + ")");
  }
  const std::size_t edges = start[n];
  std::vector<unsigned long long> offsets(start, start + n + 1);
  DeviceBuffer dStart, dTo, dWeight, dSources, dOut;
  MCV_CUDA_TRY(cudaMalloc(&dStart.ptr, offsets.size() * sizeof(unsigned long long)));
  MCV_CUDA_TRY(cudaMalloc(&dTo.ptr, std::max<std::size_t>(1, edges) * sizeof(std::uint32_t)));
  MCV_CUDA_TRY(cudaMalloc(&dWeight.ptr, std::max<std::size_t>(1, edges) * sizeof(float)));
  MCV_CUDA_TRY(cudaMalloc(&dSources.ptr, static_cast<std::size_t>(count) * sizeof(std::uint32_t)));
  MCV_CUDA_TRY(cudaMalloc(&dOut.ptr, static_cast<std::size_t>(count) * n * sizeof(double)));
  MCV_CUDA_TRY(cudaMemcpy(dStart.ptr, offsets.data(), offsets.size() * sizeof(unsigned long long), cudaMemcpyHostToDevice));
  if (edges > 0)
  {
    MCV_CUDA_TRY(cudaMemcpy(dTo.ptr, to, edges * sizeof(std::uint32_t), cudaMemcpyHostToDevice));
    MCV_CUDA_TRY(cudaMemcpy(dWeight.ptr, weight, edges * sizeof(float), cudaMemcpyHostToDevice));
  }
  MCV_CUDA_TRY(cudaMemcpy(dSources.ptr, sources, static_cast<std::size_t>(count) * sizeof(std::uint32_t), cudaMemcpyHostToDevice));
  const std::size_t bytes = n * kBytesPerVertex;
  MCV_CUDA_TRY(cudaFuncSetAttribute(geodesicsKernel, cudaFuncAttributeMaxDynamicSharedMemorySize, static_cast<int>(bytes)));
  geodesicsKernel<<<count, kThreads, bytes>>>(static_cast<unsigned>(n), dStart.as<unsigned long long>(),
    dTo.as<std::uint32_t>(), dWeight.as<float>(), dSources.as<std::uint32_t>(), dOut.as<double>());
  MCV_CUDA_TRY(cudaGetLastError());
  MCV_CUDA_TRY(cudaMemcpy(dist, dOut.ptr, static_cast<std::size_t>(count) * n * sizeof(double), cudaMemcpyDeviceToHost));
  return true;
}

bool symmetricEigenvalues(const double* A, int L, double* values, std::string* error)
{
#ifdef MCV_HAS_CUSOLVER
  FaultStage stage("isomapfit");
  if (L <= 0)
  {
    return true;
  }
  struct Handle
  {
    cusolverDnHandle_t h = nullptr;
    ~Handle()
    {
      if (h)
      {
        cusolverDnDestroy(h);
      }
    }
  } solver;
  auto solverFailed = [&](const char* call, cusolverStatus_t status) {
    return detail::fail(error, std::string("cuSOLVER ") + call + " failed (status " + std::to_string(static_cast<int>(status)) + ")");
  };
  cusolverStatus_t status = cusolverDnCreate(&solver.h);
  if (status != CUSOLVER_STATUS_SUCCESS)
  {
    solver.h = nullptr;
    return solverFailed("cusolverDnCreate", status);
  }
  const std::size_t elements = static_cast<std::size_t>(L) * static_cast<std::size_t>(L);
  DeviceBuffer dA, dW, dInfo, dWork;
  MCV_CUDA_TRY(cudaMalloc(&dA.ptr, elements * sizeof(double)));
  MCV_CUDA_TRY(cudaMalloc(&dW.ptr, static_cast<std::size_t>(L) * sizeof(double)));
  MCV_CUDA_TRY(cudaMalloc(&dInfo.ptr, sizeof(int)));
  MCV_CUDA_TRY(cudaMemcpy(dA.ptr, A, elements * sizeof(double), cudaMemcpyHostToDevice));
  int lwork = 0;
  status = cusolverDnDsyevd_bufferSize(
    solver.h, CUSOLVER_EIG_MODE_NOVECTOR, CUBLAS_FILL_MODE_LOWER, L, dA.as<double>(), L, dW.as<double>(), &lwork);
  if (status != CUSOLVER_STATUS_SUCCESS)
  {
    return solverFailed("cusolverDnDsyevd_bufferSize", status);
  }
  MCV_CUDA_TRY(cudaMalloc(&dWork.ptr, std::max(1, lwork) * sizeof(double)));
  status = cusolverDnDsyevd(solver.h, CUSOLVER_EIG_MODE_NOVECTOR, CUBLAS_FILL_MODE_LOWER, L, dA.as<double>(), L,
    dW.as<double>(), dWork.as<double>(), lwork, dInfo.as<int>());
  if (status != CUSOLVER_STATUS_SUCCESS)
  {
    return solverFailed("cusolverDnDsyevd", status);
  }
  int info = 0;
  MCV_CUDA_TRY(cudaMemcpy(&info, dInfo.ptr, sizeof info, cudaMemcpyDeviceToHost));
  if (info != 0)
  {
    return detail::fail(error, "cuSOLVER syevd did not converge (info " + std::to_string(info) + ")");
  }
  MCV_CUDA_TRY(cudaMemcpy(values, dW.ptr, static_cast<std::size_t>(L) * sizeof(double), cudaMemcpyDeviceToHost));
  return true;
#else
  (void)A;
  (void)L;
  (void)values;
  return detail::fail(error, "this build has no cuSOLVER");
#endif
}

} // namespace cuda
} // namespace mcv
