// GPU path of UMAP's layout (Filters/Core/reduction/UMAPLayout.h): the same SGD of the
// fuzzy-set cross-entropy with negative sampling, umap-learn 0.5.3's schedule (edge e is
// sampled every max w / w_e epochs with rate * that many negative samples accumulated), clip
// of every gradient component to [-4, 4], learning rate decaying linearly to 0. Plain C++
// interface (no CUDA types) so the core can call it; built only when MCV_ENABLE_CUDA is on.
// Returns false with `error` set on any CUDA failure (allocation included): the core then
// runs the CPU layout.
//
// How it differs from the CPU layout (agreement measured by trustworthiness and Procrustes
// distance in Testing/gpu/TestUMAPLayoutGPU.cpp, not bit equality):
//  - An epoch's sampled edges run in `rounds` parallel rounds (edge e in round e mod rounds,
//    in the graph's row order); every edge of a round reads the positions as they were at the
//    round's start, and the round's moves are summed per vertex (UMAPLayoutStep.h) and
//    applied at its end. The CPU moves the ends of an edge before the next edge of its
//    block reads them. More rounds keep a vertex from taking many pulls of an epoch from
//    one stale position. Each round costs two launches per epoch; on the brain's features
//    (docs/benchmarks.md section 13.1) a small sample reaches the CPU's trustworthiness
//    with few rounds, a large one only with more. Hence the default (rounds = 0): 4 up to
//    10000 vertices, 16 beyond.
//  - Negative samples come from a counter-based hash of (seed, epoch, edge), not from the
//    CPU's per-block streams.
//  - The gradient coefficients use the GPU's __powf instead of the CPU's table.
// Deterministic: the moves are fixed-point integers, whose sums do not depend on the order
// of the atomics, so a fixed seed gives the same layout bit for bit on every run
// (TestUMAPLayoutGPU.SameSeedSameLayout). What may vary: the layout on another GPU
// architecture or CUDA version (__powf and float contraction may round differently), and
// of course against the CPU layout.
#pragma once

#include <cstddef>
#include <cstdint>
#include <functional>
#include <string>

namespace mcv
{
namespace cuda
{

struct LayoutProblem
{
  std::size_t n = 0; // vertices
  int dim = 2;       // 2 or 3
  // The fuzzy graph as directed edges (both directions of each pair, as umap-learn samples
  // them), weights in (0, 1].
  std::size_t edges = 0;
  const std::uint32_t* head = nullptr;
  const std::uint32_t* tail = nullptr;
  const float* weight = nullptr;
  int epochs = 500;
  double a = 1.577, b = 0.8951, gamma = 1.0, initialAlpha = 1.0;
  int negativeSampleRate = 5;
  std::uint64_t seed = 0;
  int rounds = 0; // parallel rounds per epoch (see above); 0: defaultLayoutRounds(n)
};

// 4 up to 10000 vertices, 16 beyond (see above).
int defaultLayoutRounds(std::size_t n);

struct LayoutStats
{
  double uploadMs = 0, computeMs = 0, downloadMs = 0;
};

// Y: n x dim floats, row-major: the start, replaced by the layout. progress (optional)
// receives the fraction of epochs done, from the calling thread.
bool optimizeLayout(const LayoutProblem& problem, float* Y, const std::function<void(double)>& progress,
  LayoutStats* stats, std::string* error);

} // namespace cuda
} // namespace mcv
