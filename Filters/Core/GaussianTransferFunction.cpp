#include "GaussianTransferFunction.h"

#include <algorithm>
#include <cmath>
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
        msg << "Gaussian widget " << i << ": value " << k << " is not finite.";
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

// Widgets in the form the per-voxel loop wants: float, -1/(2 sigma^2) premultiplied.
struct PackedWidget
{
  float cx, cy, cz, negInvTwoSigma2, r, g, b, a;
};

std::vector<PackedWidget> packWidgets(const std::vector<GaussianWidget>& widgets)
{
  std::vector<PackedWidget> packed;
  for (const GaussianWidget& w : widgets)
  {
    packed.push_back({ float(w.center[0]), float(w.center[1]), float(w.center[2]),
      float(-1.0 / (2.0 * w.sigma * w.sigma)), float(w.color[0]), float(w.color[1]), float(w.color[2]),
      float(w.opacity) });
  }
  return packed;
}

// One voxel: RGBA in [0,1]. Shared by the colour and the opacity-only passes.
inline void shadeVoxel(const float* x, int components, const PackedWidget* widgets, std::size_t count, float out[4])
{
  bool finite = std::isfinite(x[0]) && std::isfinite(x[1]) && (components < 3 || std::isfinite(x[2]));
  float transmittance = 1.f, sumAlpha = 0.f, r = 0.f, g = 0.f, b = 0.f;
  if (finite)
  {
    for (std::size_t i = 0; i < count; ++i)
    {
      const PackedWidget& w = widgets[i];
      const float dx = x[0] - w.cx, dy = x[1] - w.cy;
      const float dz = components == 3 ? x[2] - w.cz : 0.f;
      const float alpha = w.a * std::exp((dx * dx + dy * dy + dz * dz) * w.negInvTwoSigma2);
      transmittance *= 1.f - alpha;
      sumAlpha += alpha;
      r += alpha * w.r;
      g += alpha * w.g;
      b += alpha * w.b;
    }
  }
  const float inv = sumAlpha > 0.f ? 1.f / sumAlpha : 0.f;
  out[0] = r * inv;
  out[1] = g * inv;
  out[2] = b * inv;
  out[3] = 1.f - transmittance;
}

std::string checkCoordinates(const CoordinateView& c, const void* out)
{
  if (c.components != 2 && c.components != 3)
  {
    return "The coordinates must have 2 or 3 components, not " + std::to_string(c.components) + ".";
  }
  if ((c.count > 0 && !c.data) || (c.count > 0 && !out))
  {
    return "No coordinates or no output buffer.";
  }
  return {};
}

template <typename Store>
TransferFunctionRun applyCPU(const CoordinateView& c, const std::vector<GaussianWidget>& widgets, const void* out,
  Device device, Store store)
{
  TransferFunctionRun run;
  run.error = checkCoordinates(c, out);
  if (!run.ok())
  {
    return run;
  }
  // The CUDA path is added by GaussianTransferFunctionCuda; until then everything runs here.
  (void)device;
  run.deviceUsed = Device::CPU;
  const std::vector<PackedWidget> packed = packWidgets(widgets);
  const long long n = static_cast<long long>(c.count);
#pragma omp parallel for schedule(static)
  for (long long v = 0; v < n; ++v)
  {
    float rgba[4];
    shadeVoxel(c.data + v * c.components, c.components, packed.data(), packed.size(), rgba);
    store(static_cast<std::size_t>(v), rgba);
  }
  return run;
}

} // namespace

TransferFunctionRun applyGaussianWidgets(
  const CoordinateView& coordinates, const std::vector<GaussianWidget>& widgets, float* rgba, Device device)
{
  return applyCPU(coordinates, widgets, rgba, device, [rgba](std::size_t v, const float* c) {
    std::copy(c, c + 4, rgba + 4 * v);
  });
}

TransferFunctionRun applyGaussianWidgets(
  const CoordinateView& coordinates, const std::vector<GaussianWidget>& widgets, unsigned char* rgba, Device device)
{
  return applyCPU(coordinates, widgets, rgba, device, [rgba](std::size_t v, const float* c) {
    for (int k = 0; k < 4; ++k)
    {
      rgba[4 * v + k] = static_cast<unsigned char>(std::lround(std::min(1.f, std::max(0.f, c[k])) * 255.f));
    }
  });
}

TransferFunctionRun gaussianWidgetOpacity(
  const CoordinateView& coordinates, const std::vector<GaussianWidget>& widgets, float* opacity, Device device)
{
  return applyCPU(coordinates, widgets, opacity, device, [opacity](std::size_t v, const float* c) {
    opacity[v] = c[3];
  });
}

} // namespace mcv
