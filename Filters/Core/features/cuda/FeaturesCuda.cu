// GPU path of the multichannel feature vectors: one thread per voxel for the stencil
// features (the same float expressions as the CPU path in Filters/Core/features/FeatureVectors.cpp),
// per-column statistics by per-thread accumulation + shared-memory combination + per-block
// partials summed on the host in double, and an elementwise normalisation.
#include "FeaturesCuda.h"

#include "cuda/CudaCheck.h"
#include "FeatureKernels.cuh"
#include "cuda/OrderedKey.cuh"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <vector>

namespace mcv
{
namespace cuda
{

namespace
{

constexpr int kThreads = 256;
static_assert(kThreads == kFeatureThreads, "the feature kernel's blocks are counted in kThreads");
constexpr int kStatBlocks = 1024;
constexpr int kMaxStatColumns = 1024; // 5 doubles per column in shared memory (40 KiB)

// Thread t of the grid handles elements t, t + S, t + 2S, ... with S a multiple of cols:
// always the same column (t % cols). Per-block partials: [block][col] for count, sum, min,
// max (pass 1) or sqdev (pass 2, about `mean`).
__global__ void columnStatsKernel(const float* __restrict__ out, const unsigned char* __restrict__ mask,
  std::int64_t elements, int cols, std::int64_t stride, int deviation, const double* __restrict__ mean,
  double* partialCount, double* partialSum, double* partialMin, double* partialMax,
  double* partialSqdev)
{
  extern __shared__ double shared[];
  double* sCount = shared;
  double* sSum = sCount + cols;
  double* sSqdev = sSum + cols;
  int* sMin = reinterpret_cast<int*>(sSqdev + cols);
  int* sMax = sMin + cols;
  for (int c = threadIdx.x; c < cols; c += blockDim.x)
  {
    sCount[c] = 0.0;
    sSum[c] = 0.0;
    sSqdev[c] = 0.0;
    sMin[c] = orderedKey(INFINITY);
    sMax[c] = orderedKey(-INFINITY);
  }
  __syncthreads();
  const std::int64_t t = blockIdx.x * static_cast<std::int64_t>(blockDim.x) + threadIdx.x;
  if (t < stride)
  {
    const int col = static_cast<int>(t % cols);
    const double m = deviation ? mean[col] : 0.0;
    double count = 0.0, sum = 0.0, sq = 0.0;
    float lo = INFINITY, hi = -INFINITY;
    for (std::int64_t e = t; e < elements; e += stride)
    {
      if (mask && mask[e / cols])
      {
        continue;
      }
      const float x = out[e];
      if (!isfinite(x))
      {
        continue;
      }
      if (deviation)
      {
        const double d = static_cast<double>(x) - m;
        sq += d * d;
      }
      else
      {
        count += 1.0;
        sum += x;
        lo = fminf(lo, x);
        hi = fmaxf(hi, x);
      }
    }
    if (deviation)
    {
      atomicAdd(&sSqdev[col], sq);
    }
    else
    {
      atomicAdd(&sCount[col], count);
      atomicAdd(&sSum[col], sum);
      atomicMin(&sMin[col], orderedKey(lo));
      atomicMax(&sMax[col], orderedKey(hi));
    }
  }
  __syncthreads();
  for (int c = threadIdx.x; c < cols; c += blockDim.x)
  {
    const std::int64_t at = static_cast<std::int64_t>(blockIdx.x) * cols + c;
    if (deviation)
    {
      partialSqdev[at] = sSqdev[c];
    }
    else
    {
      partialCount[at] = sCount[c];
      partialSum[at] = sSum[c];
      partialMin[at] = fromOrderedKey(sMin[c]);
      partialMax[at] = fromOrderedKey(sMax[c]);
    }
  }
}

__global__ void normalizeKernel(float* out, const unsigned char* __restrict__ mask,
  std::int64_t elements, int cols, const double* __restrict__ offset,
  const double* __restrict__ scale)
{
  for (std::int64_t e = blockIdx.x * static_cast<std::int64_t>(blockDim.x) + threadIdx.x;
       e < elements; e += static_cast<std::int64_t>(gridDim.x) * blockDim.x)
  {
    const std::int64_t row = e / cols;
    const int col = static_cast<int>(e - row * cols);
    if (mask && mask[row])
    {
      out[e] = 0.0f;
      continue;
    }
    const double sc = scale[col];
    const float y = static_cast<float>((static_cast<double>(out[e]) - offset[col]) * sc);
    out[e] = (sc != 0.0 && isfinite(y)) ? y : 0.0f;
  }
}

int blocksFor(std::int64_t work)
{
  const std::int64_t b = (work + kThreads - 1) / kThreads;
  return static_cast<int>(std::max<std::int64_t>(1, std::min<std::int64_t>(b, 65535 * 16)));
}

} // namespace

struct FeatureMatrixGpu::Impl
{
  std::size_t rows = 0;
  int cols = 0;
  float* out = nullptr;
  float* channel = nullptr;
  unsigned char* mask = nullptr;
  double* partials = nullptr; // 5 x kStatBlocks x cols
  double* columnParams = nullptr; // 2 x cols (mean or offset, scale)

  void release()
  {
    cudaFree(out);
    cudaFree(channel);
    cudaFree(mask);
    cudaFree(partials);
    cudaFree(columnParams);
    out = channel = nullptr;
    mask = nullptr;
    partials = columnParams = nullptr;
  }
};

FeatureMatrixGpu::FeatureMatrixGpu()
  : P(new Impl)
{
}

FeatureMatrixGpu::~FeatureMatrixGpu()
{
  P->release();
}

bool FeatureMatrixGpu::allocate(std::size_t rows, int cols, std::string* error)
{
  FaultStage stage("features");
  P->release();
  if (cols <= 0 || rows == 0)
  {
    return detail::fail(error, "empty feature matrix");
  }
  if (cols > kMaxStatColumns)
  {
    return detail::fail(error, "more than " + std::to_string(kMaxStatColumns) +
        " feature columns (the GPU statistics keep them in shared memory)");
  }
  P->rows = rows;
  P->cols = cols;
  const std::size_t elements = rows * static_cast<std::size_t>(cols);
  MCV_CUDA_TRY(cudaMalloc(&P->out, elements * sizeof(float)));
  MCV_CUDA_TRY(cudaMalloc(&P->channel, rows * sizeof(float)));
  MCV_CUDA_TRY(cudaMalloc(&P->partials, 5 * sizeof(double) * kStatBlocks * cols));
  MCV_CUDA_TRY(cudaMalloc(&P->columnParams, 2 * sizeof(double) * cols));
  return true;
}

bool FeatureMatrixGpu::addChannel(const float* hostValues, bool hasNonFinite,
  const ImageGrid& grid, const FeatureSelection& sel, int firstColumn, std::string* error)
{
  FaultStage stage("features");
  if (!P->out || grid.voxelCount() != P->rows ||
    firstColumn + sel.perChannel() > P->cols)
  {
    return detail::fail(error, "feature matrix not allocated for this channel");
  }
  MCV_CUDA_TRY(cudaMemcpy(P->channel, hostValues, P->rows * sizeof(float), cudaMemcpyHostToDevice));
  const ChannelParams p = channelParams(grid, sel, P->cols, firstColumn);
  const int blocks = blocksFor(static_cast<std::int64_t>(P->rows));
  if (hasNonFinite)
  {
    channelFeaturesKernel<true><<<blocks, kFeatureThreads>>>(P->channel, P->out, p);
  }
  else
  {
    channelFeaturesKernel<false><<<blocks, kFeatureThreads>>>(P->channel, P->out, p);
  }
  MCV_CUDA_TRY(cudaGetLastError());
  return true;
}

bool FeatureMatrixGpu::setMask(const unsigned char* hostMask, std::string* error)
{
  FaultStage stage("features");
  if (!hostMask)
  {
    cudaFree(P->mask);
    P->mask = nullptr;
    return true;
  }
  if (!P->mask)
  {
    MCV_CUDA_TRY(cudaMalloc(&P->mask, P->rows));
  }
  MCV_CUDA_TRY(cudaMemcpy(P->mask, hostMask, P->rows, cudaMemcpyHostToDevice));
  return true;
}

bool FeatureMatrixGpu::columnStats(bool deviation, mcv::detail::ColumnStats& stats, std::string* error)
{
  FaultStage stage("features");
  const int F = P->cols;
  const std::int64_t elements = static_cast<std::int64_t>(P->rows) * F;
  const std::int64_t threads = static_cast<std::int64_t>(kStatBlocks) * kThreads;
  if (threads < F)
  {
    return detail::fail(error, "too many feature columns for the GPU statistics");
  }
  const std::int64_t stride = (threads / F) * F;
  const std::size_t block = static_cast<std::size_t>(kStatBlocks) * F;
  double* pCount = P->partials;
  double* pSum = pCount + block;
  double* pMin = pSum + block;
  double* pMax = pMin + block;
  double* pSq = pMax + block;
  const std::size_t sharedBytes = static_cast<std::size_t>(F) * (3 * sizeof(double) + 2 * sizeof(int));
  stats.reset(F);
  std::vector<double> host(block);
  auto pass = [&](bool dev) -> bool {
    columnStatsKernel<<<kStatBlocks, kThreads, sharedBytes>>>(P->out, P->mask, elements, F, stride,
      dev ? 1 : 0, P->columnParams, pCount, pSum, pMin, pMax, pSq);
    MCV_CUDA_TRY(cudaGetLastError());
    if (dev)
    {
      MCV_CUDA_TRY(cudaMemcpy(host.data(), pSq, block * sizeof(double), cudaMemcpyDeviceToHost));
      for (std::size_t b = 0; b < static_cast<std::size_t>(kStatBlocks); ++b)
        for (int c = 0; c < F; ++c)
          stats.sqdev[c] += host[b * F + c];
      return true;
    }
    double* parts[4] = { pCount, pSum, pMin, pMax };
    for (int q = 0; q < 4; ++q)
    {
      MCV_CUDA_TRY(cudaMemcpy(host.data(), parts[q], block * sizeof(double), cudaMemcpyDeviceToHost));
      for (std::size_t b = 0; b < static_cast<std::size_t>(kStatBlocks); ++b)
      {
        for (int c = 0; c < F; ++c)
        {
          const double x = host[b * F + c];
          if (q == 0)
            stats.count[c] += x;
          else if (q == 1)
            stats.sum[c] += x;
          else if (q == 2)
            stats.min[c] = std::min(stats.min[c], x);
          else
            stats.max[c] = std::max(stats.max[c], x);
        }
      }
    }
    return true;
  };
  if (!pass(false))
  {
    return false;
  }
  if (deviation)
  {
    std::vector<double> mean(F);
    for (int c = 0; c < F; ++c)
    {
      mean[c] = stats.count[c] > 0 ? stats.sum[c] / stats.count[c] : 0.0;
    }
    MCV_CUDA_TRY(cudaMemcpy(P->columnParams, mean.data(), F * sizeof(double), cudaMemcpyHostToDevice));
    if (!pass(true))
    {
      return false;
    }
  }
  return true;
}

bool FeatureMatrixGpu::applyNormalization(
  const std::vector<double>& offset, const std::vector<double>& scale, std::string* error)
{
  FaultStage stage("features");
  const int F = P->cols;
  if (offset.size() != static_cast<std::size_t>(F) || scale.size() != static_cast<std::size_t>(F))
  {
    return detail::fail(error, "normalisation parameters do not match the columns");
  }
  MCV_CUDA_TRY(cudaMemcpy(P->columnParams, offset.data(), F * sizeof(double), cudaMemcpyHostToDevice));
  MCV_CUDA_TRY(cudaMemcpy(P->columnParams + F, scale.data(), F * sizeof(double), cudaMemcpyHostToDevice));
  const std::int64_t elements = static_cast<std::int64_t>(P->rows) * F;
  normalizeKernel<<<blocksFor(elements), kThreads>>>(
    P->out, P->mask, elements, F, P->columnParams, P->columnParams + F);
  MCV_CUDA_TRY(cudaGetLastError());
  return true;
}

bool FeatureMatrixGpu::download(float* hostOut, std::string* error)
{
  FaultStage stage("features");
  MCV_CUDA_TRY(cudaMemcpy(hostOut, P->out, P->rows * static_cast<std::size_t>(P->cols) * sizeof(float),
    cudaMemcpyDeviceToHost));
  return true;
}

} // namespace cuda
} // namespace mcv
