#include "GaussianTFCuda.h"

#include "cuda/CudaCheck.h"

#include <cuda_fp16.h>
#include <cuda_runtime.h>

#include <mutex>

namespace mcv
{
namespace cuda
{
namespace
{

using mcv::detail::PackedGaussianWidget;

__constant__ PackedGaussianWidget cWidgets[GaussianTFMaxWidgets];

constexpr float ExpFloor = -87.3f; // as the CPU path: NaN and lower arguments take the floor

// Log-weight of widget i; the _rn intrinsics are never fused into FMAs, so these are the
// bits the CPU path computes (it is built with -ffp-contract=off).
__device__ __forceinline__ float logWeight(const PackedGaussianWidget& w, float x, float y, float z)
{
  const float dx = __fsub_rn(x, w.cx), dy = __fsub_rn(y, w.cy), dz = __fsub_rn(z, w.cz);
  float d2 = __fadd_rn(__fmul_rn(dx, dx), __fmul_rn(dy, dy));
  d2 = __fadd_rn(d2, __fmul_rn(dz, dz));
  return __fsub_rn(w.logA, __fmul_rn(d2, w.k));
}

__device__ __forceinline__ float expClamped(float x)
{
  return expf(x >= ExpFloor ? x : ExpFloor);
}

__device__ __forceinline__ unsigned char toByte(float v)
{
  v = fminf(1.f, fmaxf(0.f, v));
  return static_cast<unsigned char>(255.0 * static_cast<double>(v) + 0.5);
}

template <int Components, GaussianTFOutput Kind>
__global__ void shadeKernel(const float* __restrict__ coords, std::size_t n, int widgetCount, void* out)
{
  for (std::size_t v = blockIdx.x * std::size_t(blockDim.x) + threadIdx.x; v < n;
       v += std::size_t(gridDim.x) * blockDim.x)
  {
    const float* p = coords + v * Components;
    const float x = p[0], y = p[1], z = Components == 3 ? p[2] : 0.f;
    float m = -INFINITY;
    for (int i = 0; i < widgetCount; ++i)
    {
      const float e = logWeight(cWidgets[i], x, y, z);
      m = e > m ? e : m;
    }
    const float scale = expClamped(m);
    float transmit = 1.f, sum = 0.f, r = 0.f, g = 0.f, b = 0.f;
    for (int i = 0; i < widgetCount; ++i)
    {
      const PackedGaussianWidget& w = cWidgets[i];
      const float weight = expClamped(logWeight(w, x, y, z) - m);
      transmit *= 1.f - weight * scale;
      if (Kind != GaussianTFOutput::Opacity)
      {
        sum += weight;
        r += weight * w.r;
        g += weight * w.g;
        b += weight * w.b;
      }
    }
    const bool valid = isfinite(x) && isfinite(y) && isfinite(z) && m > -INFINITY;
    const float alpha = valid ? 1.f - transmit : 0.f;
    if (Kind == GaussianTFOutput::Opacity)
    {
      static_cast<float*>(out)[v] = alpha;
      continue;
    }
    const float inv = valid ? 1.f / sum : 0.f;
    if (Kind == GaussianTFOutput::FloatRGBA)
    {
      static_cast<float4*>(out)[v] = make_float4(r * inv, g * inv, b * inv, alpha);
    }
    else
    {
      static_cast<uchar4*>(out)[v] =
        make_uchar4(toByte(r * inv), toByte(g * inv), toByte(b * inv), toByte(alpha));
    }
  }
}

std::size_t outputBytes(GaussianTFOutput kind, std::size_t n)
{
  switch (kind)
  {
    case GaussianTFOutput::FloatRGBA:
      return 16 * n;
    case GaussianTFOutput::ByteRGBA:
      return 4 * n;
    case GaussianTFOutput::Opacity:
      return 4 * n;
  }
  return 0;
}

template <int Components>
void launch(GaussianTFOutput kind, const float* coords, std::size_t n, int widgets, void* out)
{
  const int threads = 256;
  const std::size_t wanted = (n + threads - 1) / threads;
  const int blocks = static_cast<int>(wanted < 65535 * 8 ? wanted : 65535 * 8);
  switch (kind)
  {
    case GaussianTFOutput::FloatRGBA:
      shadeKernel<Components, GaussianTFOutput::FloatRGBA><<<blocks, threads>>>(coords, n, widgets, out);
      break;
    case GaussianTFOutput::ByteRGBA:
      shadeKernel<Components, GaussianTFOutput::ByteRGBA><<<blocks, threads>>>(coords, n, widgets, out);
      break;
    case GaussianTFOutput::Opacity:
      shadeKernel<Components, GaussianTFOutput::Opacity><<<blocks, threads>>>(coords, n, widgets, out);
      break;
  }
}

} // namespace

// float16 coordinates to float32, one value per thread (exact).
__global__ void widenHalves(const __half* in, float* out, std::size_t n)
{
  const std::size_t i = blockIdx.x * static_cast<std::size_t>(blockDim.x) + threadIdx.x;
  if (i < n)
  {
    out[i] = __half2float(in[i]);
  }
}

struct GaussianTFGpu::Impl
{
  float* coords = nullptr;
  std::size_t coordsCapacity = 0; // floats
  void* out = nullptr;
  std::size_t outCapacity = 0; // bytes
  std::size_t outBytes = 0;    // of the last shade()
  GaussianTFCoordinates resident; // data == nullptr: nothing resident
};

GaussianTFGpu::GaussianTFGpu()
  : P(new Impl)
{
}

GaussianTFGpu::~GaussianTFGpu()
{
  release();
}

void GaussianTFGpu::release()
{
  cudaFree(P->coords);
  cudaFree(P->out);
  *P = Impl();
}

bool GaussianTFGpu::setCoordinates(const GaussianTFCoordinates& c, std::string* error, bool* uploaded)
{
  FaultStage stage("gaussiantf");
  if (uploaded)
  {
    *uploaded = false;
  }
  const GaussianTFCoordinates& r = P->resident;
  if (c.version != 0 && r.data == c.data && r.halves == c.halves && r.count == c.count &&
    r.components == c.components && r.version == c.version)
  {
    return true;
  }
  P->resident = GaussianTFCoordinates();
  const std::size_t floats = c.count * c.components;
  if (floats > P->coordsCapacity)
  {
    cudaFree(P->coords);
    P->coords = nullptr;
    P->coordsCapacity = 0;
    MCV_CUDA_TRY(cudaMalloc(&P->coords, floats * sizeof(float)));
    P->coordsCapacity = floats;
  }
  if (floats > 0 && c.halves)
  {
    // The halves land in a scratch buffer freed again at once: the device keeps float32.
    __half* staged = nullptr;
    MCV_CUDA_TRY(cudaMalloc(&staged, floats * sizeof(__half)));
    cudaError_t status = cudaMemcpy(staged, c.halves, floats * sizeof(__half), cudaMemcpyHostToDevice);
    if (status == cudaSuccess)
    {
      constexpr unsigned threads = 256;
      widenHalves<<<static_cast<unsigned>((floats + threads - 1) / threads), threads>>>(staged, P->coords, floats);
      status = cudaGetLastError();
      if (status == cudaSuccess)
      {
        status = cudaDeviceSynchronize();
      }
    }
    cudaFree(staged);
    MCV_CUDA_TRY(status);
  }
  else if (floats > 0)
  {
    MCV_CUDA_TRY(cudaMemcpy(P->coords, c.data, floats * sizeof(float), cudaMemcpyHostToDevice));
  }
  P->resident = c;
  if (uploaded)
  {
    *uploaded = true;
  }
  return true;
}

bool GaussianTFGpu::shade(
  const std::vector<PackedGaussianWidget>& widgets, GaussianTFOutput kind, std::string* error)
{
  FaultStage stage("gaussiantf");
  const GaussianTFCoordinates& c = P->resident;
  if (c.count > 0 && !c.data && !c.halves)
  {
    return detail::fail(error, "GaussianTFGpu::shade before setCoordinates");
  }
  if (widgets.size() > GaussianTFMaxWidgets)
  {
    return detail::fail(error, std::to_string(widgets.size()) + " widgets, more than the " +
        std::to_string(GaussianTFMaxWidgets) + " the GPU path holds in constant memory");
  }
  const std::size_t bytes = outputBytes(kind, c.count);
  if (bytes > P->outCapacity)
  {
    cudaFree(P->out);
    P->out = nullptr;
    P->outCapacity = 0;
    MCV_CUDA_TRY(cudaMalloc(&P->out, bytes));
    P->outCapacity = bytes;
  }
  P->outBytes = bytes;
  if (c.count == 0)
  {
    return true;
  }
  if (!widgets.empty())
  {
    MCV_CUDA_TRY(cudaMemcpyToSymbol(cWidgets, widgets.data(), widgets.size() * sizeof(PackedGaussianWidget)));
  }
  const int count = static_cast<int>(widgets.size());
  if (c.components == 2)
  {
    launch<2>(kind, P->coords, c.count, count, P->out);
  }
  else
  {
    launch<3>(kind, P->coords, c.count, count, P->out);
  }
  MCV_CUDA_TRY(cudaGetLastError());
  MCV_CUDA_TRY(cudaDeviceSynchronize());
  return true;
}

bool GaussianTFGpu::download(void* hostOut, std::string* error)
{
  FaultStage stage("gaussiantf");
  if (P->outBytes > 0)
  {
    MCV_CUDA_TRY(cudaMemcpy(hostOut, P->out, P->outBytes, cudaMemcpyDeviceToHost));
  }
  return true;
}

namespace
{
std::mutex sharedMutex;
GaussianTFGpu& sharedInstance()
{
  static GaussianTFGpu instance; // at exit its cudaFree may find the runtime gone: ignored
  return instance;
}
} // namespace

bool shadeGaussianWidgetsCached(const GaussianTFCoordinates& coordinates,
  const std::vector<PackedGaussianWidget>& widgets, GaussianTFOutput kind, void* hostOut,
  std::string* error)
{
  std::lock_guard<std::mutex> lock(sharedMutex);
  GaussianTFGpu& gpu = sharedInstance();
  if (gpu.setCoordinates(coordinates, error) && gpu.shade(widgets, kind, error) &&
    gpu.download(hostOut, error))
  {
    return true;
  }
  gpu.release();
  return false;
}

void releaseGaussianTFCache()
{
  std::lock_guard<std::mutex> lock(sharedMutex);
  sharedInstance().release();
}

} // namespace cuda
} // namespace mcv
