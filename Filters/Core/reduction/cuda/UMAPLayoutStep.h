// One sampled edge of UMAP's SGD epoch as the GPU layout runs it (UMAPLayoutCuda.h): the
// attraction of the edge's two ends and the repulsion of its head from its negative
// samples, computed from the positions at the start of the round and returned as
// fixed-point moves. Host-and-device code without CUDA types, so the kernel's arithmetic can
// also be run (and checked) on the CPU.
//
// The moves are rounded to multiples of 2^-32 and summed as 64-bit integers: integer sums
// do not depend on the order the GPU's atomics land in, so the layout is the same on every
// run for a fixed seed. 2^-32 is far below a float's resolution at layout scale (positions
// ~10, ulp ~1e-6); a vertex's summed moves stay below 2^31 (every term is clipped to 4).
#pragma once

#include <cmath>
#include <cstdint>

#ifdef __CUDACC__
#define MCV_UMAP_HD __host__ __device__ __forceinline__
#else
#define MCV_UMAP_HD inline
#endif

namespace mcv
{
namespace cuda
{
namespace umap
{

constexpr double kFixedScale = 4294967296.0; // 2^32
constexpr double kFixedUnit = 1.0 / kFixedScale;

MCV_UMAP_HD long long toFixed(float v)
{
#ifdef __CUDA_ARCH__
  return __double2ll_rn(static_cast<double>(v) * kFixedScale);
#else
  return std::llrint(static_cast<double>(v) * kFixedScale);
#endif
}

// splitmix64's finalizer (SeededRandom.h's mix64): the negative samples of edge e in
// epoch t come from the counter (seed, t, e), not from a stream shared between threads.
MCV_UMAP_HD std::uint64_t mix(std::uint64_t z)
{
  z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
  z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
  return z ^ (z >> 31);
}

MCV_UMAP_HD float clip4(float v)
{
  return v < -4.f ? -4.f : (v > 4.f ? 4.f : v);
}

struct Curve
{
  float a, b, gamma;
};

// d2 > 0. The attraction coefficient -2ab d2^(b-1) / (1 + a d2^b) and the repulsion
// coefficient 2 gamma b / ((0.001 + d2)(1 + a d2^b)) of umap-learn's
// _optimize_layout_euclidean_single_epoch.
MCV_UMAP_HD float powb(float d2, float b)
{
#ifdef __CUDA_ARCH__
  return __powf(d2, b);
#else
  return std::pow(d2, b);
#endif
}

MCV_UMAP_HD float attraction(const Curve& c, float d2)
{
  const float p = powb(d2, c.b);
  return -2.f * c.a * c.b * p / (d2 * (1.f + c.a * p));
}

MCV_UMAP_HD float repulsion(const Curve& c, float d2)
{
  return 2.f * c.gamma * c.b / ((0.001f + d2) * (1.f + c.a * powb(d2, c.b)));
}

// Positions are 4 floats per vertex (Dim of them used). headMove and tailMove receive the
// fixed-point moves of the edge's two ends; `vertices` draws the negative samples.
template <int Dim>
MCV_UMAP_HD void sampleEdge(const float* positions, std::uint32_t head, std::uint32_t tail, int negatives,
  std::uint64_t stream, std::uint64_t vertices, const Curve& curve, float alpha, long long* headMove,
  long long* tailMove)
{
  float current[Dim], pull[Dim];
  float d2 = 0.f;
  for (int c = 0; c < Dim; ++c)
  {
    const float diff = positions[4 * head + c] - positions[4 * tail + c];
    current[c] = diff;
    d2 += diff * diff;
  }
  const float coeff = d2 > 0.f ? attraction(curve, d2) : 0.f;
  for (int c = 0; c < Dim; ++c)
  {
    pull[c] = clip4(coeff * current[c]) * alpha;
    current[c] = positions[4 * head + c] + pull[c];
  }
  // umap-learn's negative samples, seen from where the attraction moved the head.
  float push[Dim] = {};
  for (int q = 0; q < negatives; ++q)
  {
    const std::uint64_t k = ((mix(stream + static_cast<std::uint64_t>(q)) >> 32) * vertices) >> 32;
    if (k == head)
    {
      continue; // umap-learn skips the point itself
    }
    float diff[Dim];
    d2 = 0.f;
    for (int c = 0; c < Dim; ++c)
    {
      diff[c] = current[c] - positions[4 * k + c];
      d2 += diff[c] * diff[c];
    }
    const float r = d2 > 0.f ? repulsion(curve, d2) : 0.f;
    for (int c = 0; c < Dim; ++c)
    {
      push[c] += d2 > 0.f ? clip4(r * diff[c]) : 4.f; // a coincident point: umap-learn's fixed push
    }
  }
  for (int c = 0; c < Dim; ++c)
  {
    headMove[c] = toFixed(pull[c] + push[c] * alpha);
    tailMove[c] = toFixed(-pull[c]);
  }
}

// The counter the negative samples of edge e in epoch t are drawn from.
MCV_UMAP_HD std::uint64_t sampleStream(std::uint64_t seed, int epoch, std::uint64_t edge)
{
  return mix(mix(seed ^ 0x243F6A8885A308D3ull) + (static_cast<std::uint64_t>(epoch) << 40) + edge) << 8;
}

} // namespace umap
} // namespace cuda
} // namespace mcv
