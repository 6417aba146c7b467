#include "GaussianTransferFunction.h"

#include "HalfCoordinates.h"

#ifdef MCV_HAS_CUDA
#include "cuda/GaussianTFCuda.h"
#endif

#include <omp.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <sstream>

namespace mcv
{

WidgetList parseGaussianWidgets(const double* values, std::size_t count)
{
  WidgetList list;
  if (count % GaussianWidgetStride != 0)
  {
    std::ostringstream msg;
    msg << "GaussianWidgets has " << count << " values, not a multiple of " << GaussianWidgetStride
        << " (cx, cy, cz, sigma, r, g, b, opacity per widget).";
    list.error = msg.str();
    return list;
  }
  const std::size_t n = count / GaussianWidgetStride;
  if (n == 0)
  {
    list.warnings.emplace_back("No Gaussian widgets: the volume is fully transparent.");
  }
  for (std::size_t i = 0; i < n; ++i)
  {
    const double* v = values + i * GaussianWidgetStride;
    for (int k = 0; k < GaussianWidgetStride; ++k)
    {
      if (!std::isfinite(v[k]))
      {
        std::ostringstream msg;
        static const char* const fields[GaussianWidgetStride] = { "cx", "cy", "cz", "sigma", "r",
          "g", "b", "opacity" };
        msg << "Gaussian widget " << i << ": " << fields[k] << " (number " << k + 1
            << " of its 8: cx, cy, cz, sigma, r, g, b, opacity) is not finite.";
        list.error = msg.str();
        return list;
      }
    }
    GaussianWidget w;
    std::copy(v, v + 3, w.center);
    w.sigma = v[3];
    if (!(w.sigma > 0))
    {
      std::ostringstream msg;
      msg << "Gaussian widget " << i << ": sigma " << w.sigma << " must be > 0.";
      list.error = msg.str();
      return list;
    }
    bool clamped = false;
    auto clamp01 = [&clamped](double x) {
      const double c = std::min(1.0, std::max(0.0, x));
      clamped = clamped || c != x;
      return c;
    };
    for (int k = 0; k < 3; ++k)
    {
      w.color[k] = clamp01(v[4 + k]);
    }
    w.opacity = clamp01(v[7]);
    if (clamped)
    {
      std::ostringstream msg;
      msg << "Gaussian widget " << i << ": colour or opacity outside [0, 1], clamped.";
      list.warnings.push_back(msg.str());
    }
    list.widgets.push_back(w);
  }
  return list;
}

std::vector<double> flattenGaussianWidgets(const std::vector<GaussianWidget>& widgets)
{
  std::vector<double> flat;
  flat.reserve(widgets.size() * GaussianWidgetStride);
  for (const GaussianWidget& w : widgets)
  {
    flat.insert(flat.end(), { w.center[0], w.center[1], w.center[2], w.sigma, w.color[0], w.color[1],
                              w.color[2], w.opacity });
  }
  return flat;
}

namespace
{

// The voxel loop is compiled for AVX-512F, AVX2 and baseline x86-64; the loader picks the
// best the CPU runs (GCC function multiversioning). All three do the same float operations
// (the file is built without FMA contraction).
// Everything the voxel loop calls is forced inline, so each clone compiles it for its ISA.
#if defined(__GNUC__) && !defined(__clang__) && defined(__x86_64__) && defined(__linux__)
#define MCV_CPU_CLONES __attribute__((target_clones("avx512f", "avx2", "default")))
#define MCV_LOOP_INLINE inline __attribute__((always_inline))
#else
#define MCV_CPU_CLONES
#define MCV_LOOP_INLINE inline
#endif

constexpr int Block = 64; // voxels per inner loop: coordinates as structure of arrays
constexpr float ExpFloor = -87.3f;       // exp(ExpFloor) ~ 1.2e-38, the smallest normal float

// See detail::expNonPositive. The magic-number rounding and the bit-level 2^n keep the loop
// free of calls and branches; the comparison is written so that NaN takes the floor.
MCV_LOOP_INLINE float expNonPositiveInline(float x)
{
  x = x >= ExpFloor ? x : ExpFloor;
  const float n = (x * 1.44269504f + 12582912.f) - 12582912.f; // round(x / ln 2)
  float r = x - n * 0.693359375f;                                // Cody-Waite: ln 2 in two parts
  r = r - n * -2.12194440e-4f;
  const float p = ((((1.9875691500e-4f * r + 1.3981999507e-3f) * r + 8.3334519073e-3f) * r +
                     4.1665795894e-2f) * r + 1.6666665459e-1f) * r + 5.0000001201e-1f;
  const float y = p * (r * r) + r + 1.f;
  const std::int32_t bits = (static_cast<std::int32_t>(n) + 127) << 23;
  float scale;
  std::memcpy(&scale, &bits, sizeof scale);
  return y * scale;
}

// std::isfinite, in a form that vectorises (false for NaN and +-inf).
MCV_LOOP_INLINE bool finite(float x)
{
  return std::fabs(x) <= std::numeric_limits<float>::max();
}

std::string checkCoordinates(const CoordinateView& c, const void* out)
{
  if (c.components != 2 && c.components != 3)
  {
    return "The coordinates must have 2 or 3 components, not " + std::to_string(c.components) + ".";
  }
  if ((c.count > 0 && !c.data && !c.halves) || (c.count > 0 && !out))
  {
    return "No coordinates or no output buffer.";
  }
  return {};
}

// Coordinates of voxels [first, first + count) as structure of arrays; the rest of the
// block (the volume's last, partial block) is zero. Constant strides, so the loops vectorise.
template <int Components>
MCV_LOOP_INLINE void loadBlockAs(const float* in, int count, float* x, float* y, float* z)
{
  if (count == Block)
  {
#pragma omp simd
    for (int v = 0; v < Block; ++v)
    {
      x[v] = in[Components * v];
      y[v] = in[Components * v + 1];
      z[v] = Components == 3 ? in[Components * v + 2] : 0.f;
    }
    return;
  }
  for (int v = 0; v < Block; ++v)
  {
    x[v] = v < count ? in[Components * v] : 0.f;
    y[v] = v < count ? in[Components * v + 1] : 0.f;
    z[v] = v < count && Components == 3 ? in[Components * v + 2] : 0.f;
  }
}

MCV_LOOP_INLINE void loadBlock(const CoordinateView& c, std::size_t first, int count, float* x, float* y, float* z)
{
  alignas(64) float decoded[3 * Block];
  const float* in = c.data + first * c.components;
  if (c.halves)
  {
    halvesToFloats(c.halves + first * c.components, static_cast<std::size_t>(count) * c.components, decoded);
    in = decoded;
  }
  if (c.components == 3)
  {
    loadBlockAs<3>(in, count, x, y, z);
  }
  else
  {
    loadBlockAs<2>(in, count, x, y, z);
  }
}

// Shades the voxels [first, first + count) (count <= Block) into rgba (Colour) or alpha
// arrays of Block floats. `e` is scratch of widgets.size() x Block floats.
template <bool Colour>
MCV_LOOP_INLINE void shadeBlock(const CoordinateView& c, std::size_t first, int count,
  const std::vector<detail::PackedGaussianWidget>& widgets, float* e, float (*rgba)[Block])
{
  alignas(64) float x[Block], y[Block], z[Block], m[Block];
  loadBlock(c, first, count, x, y, z);
  for (int v = 0; v < Block; ++v)
  {
    m[v] = -std::numeric_limits<float>::infinity();
  }
  // Log-weights and their maximum. Same operation order as the CUDA kernel (no FMA: the
  // file is built with -ffp-contract=off), so e and m are the same bits on both.
  const std::size_t nw = widgets.size();
  for (std::size_t i = 0; i < nw; ++i)
  {
    const detail::PackedGaussianWidget w = widgets[i];
    float* ei = e + i * Block;
#pragma omp simd
    for (int v = 0; v < Block; ++v)
    {
      const float dx = x[v] - w.cx, dy = y[v] - w.cy, dz = z[v] - w.cz;
      float d2 = dx * dx + dy * dy;
      d2 = d2 + dz * dz;
      ei[v] = widgetLogWeight(w.logA, w.k, d2);
      m[v] = ei[v] > m[v] ? ei[v] : m[v];
    }
  }
  alignas(64) float scale[Block], transmit[Block], sum[Block], r[Block], g[Block], b[Block];
  for (int v = 0; v < Block; ++v)
  {
    scale[v] = expNonPositiveInline(m[v]); // alpha_i = exp(e_i - m) * exp(m)
    transmit[v] = 1.f;
    sum[v] = r[v] = g[v] = b[v] = 0.f;
  }
  for (std::size_t i = 0; i < nw; ++i)
  {
    const detail::PackedGaussianWidget w = widgets[i];
    const float* ei = e + i * Block;
#pragma omp simd
    for (int v = 0; v < Block; ++v)
    {
      const float weight = expNonPositiveInline(ei[v] - m[v]);
      transmit[v] = widgetTransmit(transmit[v], weight, scale[v]);
      if (Colour)
      {
        sum[v] += weight;
        r[v] += weight * w.r;
        g[v] += weight * w.g;
        b[v] += weight * w.b;
      }
    }
  }
#pragma omp simd
  for (int v = 0; v < Block; ++v)
  {
    // m = -inf: every squared distance overflowed (or no widgets); not finite: no position.
    const bool valid = finite(x[v]) & finite(y[v]) & finite(z[v]) &
      (m[v] > -std::numeric_limits<float>::infinity());
    rgba[3][v] = valid ? 1.f - transmit[v] : 0.f;
    if (Colour)
    {
      const float inv = valid ? 1.f / sum[v] : 0.f; // sum >= 1: the widget at m has weight 1
      rgba[0][v] = r[v] * inv;
      rgba[1][v] = g[v] * inv;
      rgba[2][v] = b[v] * inv;
    }
  }
}

MCV_LOOP_INLINE unsigned char toByte(float v)
{
  // round(255 v) of the float value: 255 v and + 0.5 are exact in double.
  v = std::min(1.f, std::max(0.f, v));
  return static_cast<unsigned char>(static_cast<int>(255.0 * static_cast<double>(v) + 0.5));
}

enum class Output
{
  FloatRGBA,
  ByteRGBA,
  Opacity
};

// The first `count` voxels of a shaded block into the caller's buffer at voxel `first`.
template <Output Kind>
MCV_LOOP_INLINE void store(const float (*rgba)[Block], int count, void* out, std::size_t first)
{
  if (Kind == Output::Opacity)
  {
    std::copy(rgba[3], rgba[3] + count, static_cast<float*>(out) + first);
    return;
  }
  if (Kind == Output::FloatRGBA)
  {
    float* dst = static_cast<float*>(out) + 4 * first;
#pragma omp simd
    for (int v = 0; v < count; ++v)
    {
      for (int k = 0; k < 4; ++k)
        dst[4 * v + k] = rgba[k][v];
    }
    return;
  }
  alignas(64) unsigned char bytes[4 * Block];
#pragma omp simd
  for (int v = 0; v < Block; ++v)
  {
    for (int k = 0; k < 4; ++k)
      bytes[4 * v + k] = toByte(rgba[k][v]);
  }
  std::memcpy(static_cast<unsigned char*>(out) + 4 * first, bytes, 4 * std::size_t(count));
}


template <Output Kind>
MCV_LOOP_INLINE void shadeBlocks(const CoordinateView& c, const std::vector<detail::PackedGaussianWidget>& widgets,
  long long firstBlock, long long endBlock, float* scratch, void* out)
{
  constexpr bool Colour = Kind != Output::Opacity;
  alignas(64) float rgba[4][Block];
  for (long long blk = firstBlock; blk < endBlock; ++blk)
  {
    const std::size_t first = static_cast<std::size_t>(blk) * Block;
    const int count = static_cast<int>(std::min<std::size_t>(Block, c.count - first));
    shadeBlock<Colour>(c, first, count, widgets, scratch, rgba);
    store<Kind>(rgba, count, out, first);
  }
}

MCV_CPU_CLONES
void shadeBlocksCPU(Output kind, const CoordinateView& c, const std::vector<detail::PackedGaussianWidget>& widgets,
  long long firstBlock, long long endBlock, float* scratch, void* out)
{
  switch (kind)
  {
    case Output::FloatRGBA:
      shadeBlocks<Output::FloatRGBA>(c, widgets, firstBlock, endBlock, scratch, out);
      break;
    case Output::ByteRGBA:
      shadeBlocks<Output::ByteRGBA>(c, widgets, firstBlock, endBlock, scratch, out);
      break;
    case Output::Opacity:
      shadeBlocks<Output::Opacity>(c, widgets, firstBlock, endBlock, scratch, out);
      break;
  }
}

void applyCPU(Output kind, const CoordinateView& c, const std::vector<detail::PackedGaussianWidget>& widgets, void* out)
{
  const long long blocks = static_cast<long long>((c.count + Block - 1) / Block);
#pragma omp parallel if (blocks > 64)
  {
    // Contiguous equal shares of blocks per thread (a static schedule).
    const long long threads = omp_get_num_threads(), t = omp_get_thread_num();
    std::vector<float> scratch(std::max<std::size_t>(1, widgets.size()) * Block);
    shadeBlocksCPU(kind, c, widgets, blocks * t / threads, blocks * (t + 1) / threads, scratch.data(), out);
  }
}

template <Output Kind>
TransferFunctionRun apply(
  const CoordinateView& c, const std::vector<GaussianWidget>& widgets, void* out, Device device)
{
  TransferFunctionRun run;
  run.error = checkCoordinates(c, out);
  if (!run.ok())
  {
    return run;
  }
  const std::vector<detail::PackedGaussianWidget> packed =
    detail::packGaussianWidgets(widgets, c.components, run.error, run.warnings);
  if (!run.ok())
  {
    return run;
  }
  std::string warning;
  if (resolveDevice(device, &warning) == Device::GPU)
  {
#ifdef MCV_HAS_CUDA
    constexpr cuda::GaussianTFOutput gpuKind = Kind == Output::FloatRGBA
      ? cuda::GaussianTFOutput::FloatRGBA
      : (Kind == Output::ByteRGBA ? cuda::GaussianTFOutput::ByteRGBA : cuda::GaussianTFOutput::Opacity);
    std::string error;
    if (cuda::shadeGaussianWidgetsCached(
          { c.data, c.count, c.components, c.version, c.halves }, packed, gpuKind, out, &error))
    {
      run.deviceUsed = Device::GPU;
      return run;
    }
    warning = "GPU transfer function failed (" + error + "); running on the CPU.";
#endif
  }
  if (!warning.empty() && device != Device::CPU)
  {
    run.warnings.push_back(warning);
  }
  run.deviceUsed = Device::CPU;
  applyCPU(Kind, c, packed, out);
  return run;
}

} // namespace

namespace detail
{

std::vector<PackedGaussianWidget> packGaussianWidgets(const std::vector<GaussianWidget>& widgets,
  int components, std::string& error, std::vector<std::string>& warnings)
{
  std::vector<PackedGaussianWidget> packed;
  if (widgets.empty())
  {
    return packed; // transparent; parseGaussianWidgets already warned about an empty list
  }
  const std::vector<double> flat = flattenGaussianWidgets(widgets);
  WidgetList checked = parseGaussianWidgets(flat.data(), flat.size());
  if (!checked.ok())
  {
    error = checked.error;
    return packed;
  }
  warnings.insert(warnings.end(), checked.warnings.begin(), checked.warnings.end());
  for (const GaussianWidget& w : checked.widgets)
  {
    if (w.opacity > 0)
    {
      packed.push_back({ float(w.center[0]), float(w.center[1]), components == 3 ? float(w.center[2]) : 0.f,
        float(1.0 / (2.0 * w.sigma * w.sigma)), float(std::log(w.opacity)), float(w.color[0]),
        float(w.color[1]), float(w.color[2]) });
    }
  }
  return packed;
}

float expNonPositive(float x)
{
  return expNonPositiveInline(x);
}

} // namespace detail

TransferFunctionRun applyGaussianWidgets(
  const CoordinateView& coordinates, const std::vector<GaussianWidget>& widgets, float* rgba, Device device)
{
  return apply<Output::FloatRGBA>(coordinates, widgets, rgba, device);
}

TransferFunctionRun applyGaussianWidgets(
  const CoordinateView& coordinates, const std::vector<GaussianWidget>& widgets, unsigned char* rgba, Device device)
{
  return apply<Output::ByteRGBA>(coordinates, widgets, rgba, device);
}

TransferFunctionRun gaussianWidgetOpacity(
  const CoordinateView& coordinates, const std::vector<GaussianWidget>& widgets, float* opacity, Device device)
{
  return apply<Output::Opacity>(coordinates, widgets, opacity, device);
}

void releaseGaussianWidgetDeviceCache()
{
#ifdef MCV_HAS_CUDA
  cuda::releaseGaussianTFCache();
#endif
}

} // namespace mcv
