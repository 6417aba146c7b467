// Benchmark of the Gaussian-widget recolouring (Filters/Core/transfer_function/GaussianTransferFunction.h) at
// N^3 voxels (default 256^3 = 16.8 M), 2/4/8 widgets, uint8 RGBA out (what the volume mapper
// is given), against a straightforward per-voxel loop measured in the same run:
//   baseline  one thread, double exp per widget per voxel, the header's formula as written;
//   simple    the same loop in float over OpenMP threads (the straightforward parallel code);
//   CPU       mcv::applyGaussianWidgets(Device::CPU): blocks of 64 voxels as structure of
//             arrays, log-domain weights, vectorised polynomial exp, every widget at every
//             voxel;
//   GPU       (CUDA builds with a GPU) coordinates resident: the kernel alone, the kernel +
//             download of the uint8 RGBA, and the whole mcv::applyGaussianWidgets call with
//             an unchanged CoordinateView::version (what a widget edit costs); the first
//             call's upload is shown apart.
// Coordinates: "smooth" = a deterministic smooth 3-field function of the voxel position
// plus 2 % noise (reduced coordinates of a real volume are spatially coherent like this);
// "random" = uniform in the same box (the worst case for skipping widgets).
//
//   mcvBenchmarkGaussianTF [--size N] [--widgets 2,4,8] [--components 2|3] [--runs R]
//                          [--baseline-runs R] [--no-baseline] [--coords smooth|random|both]
//                          [--no-cpu] [--threads T]
//
// Times are medians over the runs; ratio = baseline / time. "max diff" is the largest
// byte difference of our CPU (and GPU) output against the double baseline.
#include "GaussianTransferFunction.h"
#include "SeededRandom.h"

#include "CommandLine.h"
#include "GaussianWidgetsReference.h"
#include "RunStatistics.h"

#ifdef MCV_HAS_CUDA
#include "cuda/GaussianTFCuda.h"
#endif

#include <omp.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <functional>
#include <sstream>
#include <string>
#include <vector>

namespace
{
using Clock = std::chrono::steady_clock;
using mcv::testing::loadAverage;
using mcv::testing::median;

struct Config
{
  int size = 256;
  std::vector<int> widgets{ 2, 4, 8 };
  int components = 3;
  int runs = 5;
  int baselineRuns = 1;
  bool baseline = true;
  bool cpu = true;
  std::vector<std::string> coords{ "smooth", "random" };
  int threads = 0;
};

double timeMs(const std::function<void()>& f, int runs)
{
  std::vector<double> t;
  for (int r = 0; r < runs; ++r)
  {
    const auto t0 = Clock::now();
    f();
    t.push_back(std::chrono::duration<double, std::milli>(Clock::now() - t0).count());
  }
  return median(t);
}

// A float in [0,1) from a 64-bit hash (splitmix64): deterministic, no global state.
float hashUnit(std::uint64_t x)
{
  return static_cast<float>(mcv::mix64(x + 0x9e3779b97f4a7c15ULL) >> 40) / 16777216.f;
}

// Coordinates in [0,1]^components.
std::vector<float> makeCoordinates(int n, int components, bool smooth)
{
  const std::size_t count = std::size_t(n) * n * n;
  std::vector<float> c(count * components);
#pragma omp parallel for schedule(static)
  for (long long v = 0; v < static_cast<long long>(count); ++v)
  {
    const double i = double(v % n) / n, j = double((v / n) % n) / n, k = double(v / (std::size_t(n) * n)) / n;
    for (int d = 0; d < components; ++d)
    {
      const float noise = hashUnit(std::uint64_t(v) * 3 + d);
      float value = noise;
      if (smooth)
      {
        const double f = d == 0 ? 0.5 + 0.45 * std::sin(6.0 * i + 2.0 * k) * std::cos(4.0 * j)
          : d == 1 ? 0.5 + 0.45 * std::cos(5.0 * j - 3.0 * i) * std::sin(3.0 * k + 1.0)
                   : 0.5 + 0.45 * std::sin(4.0 * k + 5.0 * j * i);
        value = static_cast<float>(0.98 * f + 0.02 * noise);
      }
      c[std::size_t(v) * components + d] = value;
    }
  }
  return c;
}

// Widgets spread over the unit box: a realistic palette of clusters, sigma 0.08..0.15.
std::vector<mcv::GaussianWidget> makeWidgets(int count)
{
  std::vector<mcv::GaussianWidget> w(count);
  for (int i = 0; i < count; ++i)
  {
    for (int d = 0; d < 3; ++d)
    {
      w[i].center[d] = 0.1 + 0.8 * hashUnit(1000 + 10 * i + d);
      w[i].color[d] = hashUnit(2000 + 10 * i + d);
    }
    w[i].sigma = 0.08 + 0.07 * hashUnit(3000 + i);
    w[i].opacity = 0.3 + 0.5 * hashUnit(4000 + i);
  }
  return w;
}

unsigned char byteOf(double v)
{
  return static_cast<unsigned char>(std::lround(std::min(1.0, std::max(0.0, v)) * 255.0));
}

// The header's formula, written plainly: one thread, double, one exp per widget per voxel.
void baselineLoop(const float* coords, std::size_t count, int components,
  const std::vector<mcv::GaussianWidget>& widgets, unsigned char* rgba)
{
  for (std::size_t v = 0; v < count; ++v)
  {
    double voxel[4];
    mcv::testing::referenceRGBA(coords + v * components, components, widgets, voxel);
    for (int k = 0; k < 4; ++k)
      rgba[4 * v + k] = byteOf(voxel[k]);
  }
}

// The straightforward parallel code: the same loop in float, expf, OpenMP over voxels.
void simpleLoop(const float* coords, std::size_t count, int components,
  const std::vector<mcv::GaussianWidget>& widgets, unsigned char* rgba)
{
  struct P
  {
    float c[3], k, r, g, b, a;
  };
  std::vector<P> p;
  for (const mcv::GaussianWidget& w : widgets)
    p.push_back({ { float(w.center[0]), float(w.center[1]), float(w.center[2]) },
      float(-1 / (2 * w.sigma * w.sigma)), float(w.color[0]), float(w.color[1]), float(w.color[2]),
      float(w.opacity) });
#pragma omp parallel for schedule(static)
  for (long long v = 0; v < static_cast<long long>(count); ++v)
  {
    const float* x = coords + v * components;
    float transmit = 1, sum = 0, r = 0, g = 0, b = 0;
    for (const P& w : p)
    {
      const float dx = x[0] - w.c[0], dy = x[1] - w.c[1], dz = components == 3 ? x[2] - w.c[2] : 0.f;
      const float alpha = w.a * std::exp((dx * dx + dy * dy + dz * dz) * w.k);
      transmit *= 1 - alpha;
      sum += alpha;
      r += alpha * w.r;
      g += alpha * w.g;
      b += alpha * w.b;
    }
    const float inv = sum > 0 ? 1 / sum : 0;
    rgba[4 * v] = byteOf(r * inv);
    rgba[4 * v + 1] = byteOf(g * inv);
    rgba[4 * v + 2] = byteOf(b * inv);
    rgba[4 * v + 3] = byteOf(1 - transmit);
  }
}

int maxByteDiff(const std::vector<unsigned char>& a, const std::vector<unsigned char>& b)
{
  int d = 0;
  for (std::size_t i = 0; i < a.size(); ++i)
    d = std::max(d, std::abs(int(a[i]) - int(b[i])));
  return d;
}

bool parseArgs(int argc, char** argv, Config& c)
{
  for (int i = 1; i < argc; ++i)
  {
    const std::string a = argv[i];
    const char* next = i + 1 < argc ? argv[i + 1] : nullptr;
    if (a == "--size" && next)
      c.size = std::atoi(argv[++i]);
    else if (a == "--widgets" && next)
      c.widgets = mcv::testing::integerList(argv[++i]);
    else if (a == "--components" && next)
      c.components = std::atoi(argv[++i]);
    else if (a == "--runs" && next)
      c.runs = std::max(1, std::atoi(argv[++i]));
    else if (a == "--baseline-runs" && next)
      c.baselineRuns = std::max(1, std::atoi(argv[++i]));
    else if (a == "--no-baseline")
      c.baseline = false;
    else if (a == "--no-cpu")
      c.cpu = false;
    else if (a == "--threads" && next)
      c.threads = std::atoi(argv[++i]);
    else if (a == "--coords" && next)
    {
      const std::string v = argv[++i];
      c.coords = v == "both" ? std::vector<std::string>{ "smooth", "random" } : std::vector<std::string>{ v };
    }
    else
    {
      std::printf("usage: mcvBenchmarkGaussianTF [--size N] [--widgets 2,4,8] [--components 2|3]\n"
                  "         [--runs R] [--baseline-runs R] [--no-baseline] [--no-cpu]\n"
                  "         [--coords smooth|random|both] [--threads T]\n");
      return false;
    }
  }
  return c.size > 0 && (c.components == 2 || c.components == 3) && !c.widgets.empty();
}

std::string fmt(double ms)
{
  char buf[32];
  if (std::isnan(ms))
    return "-";
  std::snprintf(buf, sizeof buf, ms < 10 ? "%.2f" : "%.1f", ms);
  return buf;
}

std::string ratio(double base, double ms)
{
  char buf[32];
  if (std::isnan(base) || std::isnan(ms) || ms <= 0)
    return "-";
  std::snprintf(buf, sizeof buf, "%.0fx", base / ms);
  return buf;
}

} // namespace

int main(int argc, char** argv)
{
  Config cfg;
  if (!parseArgs(argc, argv, cfg))
    return 2;
  if (cfg.threads > 0)
    omp_set_num_threads(cfg.threads);
  const std::size_t count = std::size_t(cfg.size) * cfg.size * cfg.size;
  std::printf("Gaussian-widget recolouring, %d^3 = %zu voxels, %dD coordinates, uint8 RGBA out\n",
    cfg.size, count, cfg.components);
  std::printf("threads %d, load average %.2f, runs %d (baseline %d)\n", omp_get_max_threads(),
    loadAverage(), cfg.runs, cfg.baselineRuns);
#ifdef MCV_HAS_CUDA
  std::string why;
  const bool gpu = mcv::gpuUsable(&why);
  if (!gpu)
    std::printf("GPU: not usable (%s)\n", why.c_str());
#else
  const bool gpu = false;
  std::printf("GPU: this build has no CUDA\n");
#endif
  std::printf("\n%-7s %3s | %9s | %9s %6s | %9s %6s %4s | %9s %9s %6s %9s %6s %4s | %9s\n", "coords", "W",
    "base ms", "simple ms", "ratio", "CPU ms", "ratio", "diff", "GPU kern", "GPU+dl", "ratio", "GPU call",
    "ratio", "diff", "upload ms");

  for (const std::string& kind : cfg.coords)
  {
    const std::vector<float> coords = makeCoordinates(cfg.size, cfg.components, kind == "smooth");
    for (int nw : cfg.widgets)
    {
      const std::vector<mcv::GaussianWidget> widgets = makeWidgets(nw);
      mcv::CoordinateView view{ coords.data(), count, cfg.components, 0 };
      std::vector<unsigned char> reference(4 * count), out(4 * count);
      double base = NAN, simple = NAN, cpu = NAN;
      int cpuDiff = -1, gpuDiff = -1;
      if (cfg.baseline)
      {
        base = timeMs([&] { baselineLoop(coords.data(), count, cfg.components, widgets, reference.data()); },
          cfg.baselineRuns);
      }
      if (cfg.cpu)
      {
        simple = timeMs([&] { simpleLoop(coords.data(), count, cfg.components, widgets, out.data()); }, cfg.runs);
        bool ok = true;
        cpu = timeMs(
          [&] { ok = mcv::applyGaussianWidgets(view, widgets, out.data(), mcv::Device::CPU).ok() && ok; },
          cfg.runs);
        if (!ok)
          std::printf("CPU path failed\n");
        if (cfg.baseline)
          cpuDiff = maxByteDiff(reference, out);
      }
      double kernel = NAN, withDownload = NAN, call = NAN, upload = NAN;
#ifdef MCV_HAS_CUDA
      if (gpu)
      {
        std::string error;
        mcv::cuda::GaussianTFGpu dev;
        std::vector<std::string> warnings;
        const auto packed = mcv::detail::packGaussianWidgets(widgets, cfg.components, error, warnings);
        const mcv::cuda::GaussianTFCoordinates gc{ coords.data(), count, cfg.components, 1 };
        bool ok = true;
        upload = timeMs([&] { ok = dev.setCoordinates({ gc.data, gc.count, gc.components, 0 }, &error) && ok; }, 1);
        ok = ok && dev.shade(packed, mcv::cuda::GaussianTFOutput::ByteRGBA, &error); // warm-up
        kernel = timeMs(
          [&] { ok = dev.shade(packed, mcv::cuda::GaussianTFOutput::ByteRGBA, &error) && ok; }, cfg.runs);
        withDownload = timeMs([&] {
          ok = dev.shade(packed, mcv::cuda::GaussianTFOutput::ByteRGBA, &error) && dev.download(out.data(), &error) &&
            ok;
        }, cfg.runs);
        dev.release();
        // The public call: the first one uploads (version 1), the timed ones find it resident.
        view.version = 1;
        mcv::TransferFunctionRun run = mcv::applyGaussianWidgets(view, widgets, out.data(), mcv::Device::GPU);
        call = timeMs([&] { run = mcv::applyGaussianWidgets(view, widgets, out.data(), mcv::Device::GPU); },
          cfg.runs);
        mcv::releaseGaussianWidgetDeviceCache();
        if (!ok || run.deviceUsed != mcv::Device::GPU)
        {
          std::printf("GPU path failed: %s %s\n", error.c_str(), run.warnings.empty() ? "" : run.warnings[0].c_str());
          kernel = withDownload = call = NAN;
        }
        else if (cfg.baseline)
        {
          gpuDiff = maxByteDiff(reference, out);
        }
      }
#endif
      std::printf("%-7s %3d | %9s | %9s %6s | %9s %6s %4s | %9s %9s %6s %9s %6s %4s | %9s\n", kind.c_str(), nw,
        fmt(base).c_str(), fmt(simple).c_str(), ratio(base, simple).c_str(), fmt(cpu).c_str(),
        ratio(base, cpu).c_str(), cpuDiff < 0 ? "-" : std::to_string(cpuDiff).c_str(), fmt(kernel).c_str(),
        fmt(withDownload).c_str(), ratio(base, withDownload).c_str(), fmt(call).c_str(), ratio(base, call).c_str(),
        gpuDiff < 0 ? "-" : std::to_string(gpuDiff).c_str(), fmt(upload).c_str());
      std::fflush(stdout);
    }
  }
  std::printf("\nTargets: CPU <= 300 ms, GPU <= 20 ms per recolouring at 16 M voxels.\n");
  return 0;
}
