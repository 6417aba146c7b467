// What an exact, bound-pruned best viewpoint would have to compute (issue 36, target 2):
// the share of the Harris kernel's blocks whose response could reach the N-th largest.
//
// For a positive semi-definite structure tensor M, det M <= (tr M / 3)^3 (the arithmetic
// and geometric means of its eigenvalues) and det M <= Mxx Myy Mzz (Hadamard), so
//   R = det M - k tr^3 <= tr^3 (1/27 - k)   and   R <= Mxx Myy Mzz - k tr^3.
// The first needs one smoothed channel (|g|^2) instead of six, the second three. A block
// of voxels whose largest bound is below tau (the N-th largest response) holds none of the
// top N, so a pipeline that knew tau (or a lower bound of it) would compute the exact
// response only in the other blocks. This program measures, on the GPU benchmark's volume
// (Testing/Data/TestVolumes.h structuredVolume, quantised to uint8 as mcvBenchmarkGPU
// does), the share of (32 x 16 x zchunk)-voxel blocks (the Harris kernel's tiles) that pass
// each bound, against the share that holds a non-zero voxel; and checks that each bound
// is >= R at every voxel (R from computeHarrisResponseCPU, the product's own function;
// the bounds in double from the same gradients and taps).
//
// Two cheaper block bounds of the same trace bound are counted beside them: the largest
// x,y-smoothed |g|^2 of the block's output rows in its 2 R + 1 z-neighbourhood of slices
// (what the GPU's bound kernel, HarrisBound.cu, forms), and the largest raw |g|^2 of the
// block dilated by R on every side (no smoothing at all: the Gaussian's weighted mean is at
// most its largest term).
//
// Usage: mcvHarrisBoundShares [--sizes 128,256] [--zchunks 8,16,64] [--n 2048]

#include "HarrisResponse.h"

#include "CommandLine.h"
#include "TestVolumes.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <functional>
#include <vector>

namespace
{
namespace mt = mcv::testing;

// One separable pass along `axis` (0 x, 1 y, 2 z), border replicated.
void smoothAxis(std::vector<double>& a, int n, int axis, const float* taps, int width)
{
  const std::int64_t stride = axis == 0 ? 1 : axis == 1 ? n : static_cast<std::int64_t>(n) * n;
  const std::int64_t count = static_cast<std::int64_t>(n) * n * n;
  std::vector<double> out(a.size());
  const int r = width / 2;
#pragma omp parallel for schedule(static)
  for (std::int64_t i = 0; i < count; ++i)
  {
    const int c = static_cast<int>(i / stride % n);
    double sum = 0;
    for (int t = -r; t <= r; ++t)
    {
      const int q = std::clamp(c + t, 0, n - 1);
      sum += taps[t + r] * a[i + (q - c) * stride];
    }
    out[i] = sum;
  }
  a.swap(out);
}

void measure(int n, const std::vector<int>& zchunks, int topN)
{
  mt::Volume vol = mt::structuredVolume(n);
  for (float& v : vol.values)
  {
    v = static_cast<float>(std::lround(v * 255.0f)) / 255.0f; // the uint8 the GPU reads
  }
  const std::int64_t count = static_cast<std::int64_t>(n) * n * n;
  mcv::HarrisParameters params;
  std::vector<float> response(static_cast<std::size_t>(count));
  mcv::computeHarrisResponseCPU(vol.values.data(), vol.grid, params, response.data());

  // Gradient products xx, yy, zz (central differences, spacing 1, border replicated).
  std::vector<double> g2[3];
  for (auto& a : g2)
  {
    a.assign(static_cast<std::size_t>(count), 0.0);
  }
  auto at = [&](int x, int y, int z) {
    x = std::clamp(x, 0, n - 1);
    y = std::clamp(y, 0, n - 1);
    z = std::clamp(z, 0, n - 1);
    return static_cast<double>(vol.values[(static_cast<std::size_t>(z) * n + y) * n + x]);
  };
#pragma omp parallel for schedule(static)
  for (int z = 0; z < n; ++z)
  {
    for (int y = 0; y < n; ++y)
    {
      for (int x = 0; x < n; ++x)
      {
        const std::size_t i = (static_cast<std::size_t>(z) * n + y) * n + x;
        const double gx = 0.5 * (at(x + 1, y, z) - at(x - 1, y, z));
        const double gy = 0.5 * (at(x, y + 1, z) - at(x, y - 1, z));
        const double gz = 0.5 * (at(x, y, z + 1) - at(x, y, z - 1));
        g2[0][i] = gx * gx;
        g2[1][i] = gy * gy;
        g2[2][i] = gz * gz;
      }
    }
  }
  std::vector<float> taps(static_cast<std::size_t>(params.kernelWidth));
  mcv::gaussianTaps(params, taps.data());
  // |g|^2 unsmoothed and smoothed along x and y only (the cheaper block bounds)
  std::vector<double> rawTrace(static_cast<std::size_t>(count));
  for (std::int64_t i = 0; i < count; ++i)
  {
    rawTrace[i] = g2[0][i] + g2[1][i] + g2[2][i];
  }
  std::vector<double> xyTrace(rawTrace);
  smoothAxis(xyTrace, n, 0, taps.data(), params.kernelWidth);
  smoothAxis(xyTrace, n, 1, taps.data(), params.kernelWidth);
  for (auto& a : g2)
  {
    for (int axis = 0; axis < 3; ++axis)
    {
      smoothAxis(a, n, axis, taps.data(), params.kernelWidth);
    }
  }
  std::vector<double> traceBound(static_cast<std::size_t>(count));
  std::vector<double> hadamardBound(static_cast<std::size_t>(count));
  std::int64_t violations = 0;
  for (std::int64_t i = 0; i < count; ++i)
  {
    const double tr = g2[0][i] + g2[1][i] + g2[2][i];
    const double t3 = tr * tr * tr;
    traceBound[i] = t3 * (1.0 / 27.0 - params.k);
    hadamardBound[i] = g2[0][i] * g2[1][i] * g2[2][i] - params.k * t3;
    // float rounding of R: a relative slack of 1e-4 of tr^3
    const double slack = 1e-4 * t3 + 1e-30;
    violations += response[i] > traceBound[i] + slack || response[i] > hadamardBound[i] + slack;
  }
  std::vector<float> sorted(response);
  std::nth_element(sorted.begin(), sorted.begin() + (topN - 1), sorted.end(), std::greater<float>());
  const double tau = sorted[static_cast<std::size_t>(topN - 1)];
  std::int64_t voxelsT = 0, voxelsH = 0;
  for (std::int64_t i = 0; i < count; ++i)
  {
    voxelsT += traceBound[i] >= tau;
    voxelsH += hadamardBound[i] >= tau;
  }
  std::printf("== %d^3: tau (response %d) %.4g; voxels whose bound reaches tau: trace %.2f %%, "
              "Hadamard %.2f %%; voxels where a bound is below R: %lld (0 expected)\n",
    n, topN, tau, 100.0 * voxelsT / count, 100.0 * voxelsH / count,
    static_cast<long long>(violations));
  std::printf("| z chunk | blocks (32 x 16 x z) | with a non-zero voxel | trace bound reaches tau | "
              "Hadamard bound reaches tau | x,y-smoothed trace (the GPU's bound) | raw squared gradient, "
              "dilated block |\n|---|---|---|---|---|---|---|\n");
  const int r = params.kernelWidth / 2;
  const double cubeFactor = 1.0 / 27.0 - params.k;
  // The largest of `field` over [x0, x1) x [y0, y1) x [z0, z1), clipped to the grid.
  auto largest = [&](const std::vector<double>& field, int x0, int x1, int y0, int y1, int z0, int z1) {
    double m = 0;
    for (int z = std::max(0, z0); z < std::min(n, z1); ++z)
      for (int y = std::max(0, y0); y < std::min(n, y1); ++y)
        for (int x = std::max(0, x0); x < std::min(n, x1); ++x)
          m = std::max(m, field[(static_cast<std::size_t>(z) * n + y) * n + x]);
    return m;
  };
  for (int zc : zchunks)
  {
    std::int64_t blocks = 0, nonEmpty = 0, passT = 0, passH = 0, passXY = 0, passRaw = 0;
    for (int z0 = 0; z0 < n; z0 += zc)
    {
      for (int y0 = 0; y0 < n; y0 += 16)
      {
        for (int x0 = 0; x0 < n; x0 += 32)
        {
          double maxT = -HUGE_VAL, maxH = -HUGE_VAL;
          bool any = false;
          for (int z = z0; z < std::min(n, z0 + zc); ++z)
          {
            for (int y = y0; y < std::min(n, y0 + 16); ++y)
            {
              for (int x = x0; x < std::min(n, x0 + 32); ++x)
              {
                const std::size_t i = (static_cast<std::size_t>(z) * n + y) * n + x;
                maxT = std::max(maxT, traceBound[i]);
                maxH = std::max(maxH, hadamardBound[i]);
                any = any || vol.values[i] != 0.0f;
              }
            }
          }
          const double xy = largest(xyTrace, x0, x0 + 32, y0, y0 + 16, z0 - r, z0 + zc + r);
          const double raw =
            largest(rawTrace, x0 - r, x0 + 32 + r, y0 - r, y0 + 16 + r, z0 - r, z0 + zc + r);
          passXY += xy * xy * xy * cubeFactor >= tau;
          passRaw += raw * raw * raw * cubeFactor >= tau;
          ++blocks;
          nonEmpty += any;
          passT += maxT >= tau;
          passH += maxH >= tau;
        }
      }
    }
    std::printf("| %d | %lld | %.1f %% | %.1f %% | %.1f %% | %.1f %% | %.1f %% |\n", zc,
      static_cast<long long>(blocks), 100.0 * nonEmpty / blocks, 100.0 * passT / blocks,
      100.0 * passH / blocks, 100.0 * passXY / blocks, 100.0 * passRaw / blocks);
  }
}

} // namespace

int main(int argc, char** argv)
{
  using namespace mcv::testing;
  const std::vector<int> sizes = integerList(optionText(argc, argv, "--sizes", "128,256"));
  const std::vector<int> zchunks = integerList(optionText(argc, argv, "--zchunks", "8,16,64"));
  const int topN = static_cast<int>(optionNumber(argc, argv, "--n", 2048));
  for (int n : sizes)
  {
    measure(n, zchunks, topN);
  }
  return 0;
}
