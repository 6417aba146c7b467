// UMAP's layout on the GPU: per round, one thread per edge of the round (UMAPLayoutStep.h's
// sampleEdge when the edge is due), its moves added to per-vertex 64-bit accumulators with
// atomics, then one thread per vertex applies them. The schedule state (next sample, next
// negative sample) stays in double as in umap-learn and the CPU layout, so the same epochs
// sample the same edges.
#include "UMAPLayoutCuda.h"

#include "cuda/CudaCheck.h"
#include "cuda/DeviceBuffer.cuh"
#include "UMAPLayoutStep.h"

#include <algorithm>
#include <chrono>
#include <vector>

namespace mcv
{
namespace cuda
{

namespace
{
using Clock = std::chrono::steady_clock;
constexpr int kThreads = 256;
constexpr int kEpochsPerReport = 10; // between progress reports (as the CPU layout)

double msSince(Clock::time_point t)
{
  return std::chrono::duration<double, std::milli>(Clock::now() - t).count();
}

struct EdgeState
{
  const std::uint32_t* head;
  const std::uint32_t* tail;
  const double* epochsPerSample;
  double* nextSample;
  double* nextNegative;
  double negativeRate;
};

template <int Dim>
__global__ void __launch_bounds__(kThreads) edgeKernel(EdgeState s, std::size_t first, std::size_t count,
  const float* __restrict__ positions, unsigned long long* __restrict__ moves, std::size_t n, int epoch,
  float alpha, umap::Curve curve, std::uint64_t seed)
{
  const std::size_t i = blockIdx.x * static_cast<std::size_t>(kThreads) + threadIdx.x;
  if (i >= count)
  {
    return;
  }
  const std::size_t e = first + i;
  const double next = s.nextSample[e];
  if (next > epoch)
  {
    return;
  }
  const double eps = s.epochsPerSample[e];
  const double epochsPerNegative = eps / s.negativeRate;
  const double nextNegative = s.nextNegative[e];
  const int negatives = static_cast<int>((epoch - nextNegative) / epochsPerNegative);
  s.nextSample[e] = next + eps;
  s.nextNegative[e] = nextNegative + negatives * epochsPerNegative;
  const std::uint32_t head = s.head[e], tail = s.tail[e];
  long long headMove[Dim], tailMove[Dim];
  umap::sampleEdge<Dim>(positions, head, tail, negatives, umap::sampleStream(seed, epoch, e), n, curve, alpha,
    headMove, tailMove);
  for (int c = 0; c < Dim; ++c)
  {
    // Two's complement: adding the unsigned image of a negative move subtracts it.
    atomicAdd(moves + 4 * static_cast<std::size_t>(head) + c, static_cast<unsigned long long>(headMove[c]));
    atomicAdd(moves + 4 * static_cast<std::size_t>(tail) + c, static_cast<unsigned long long>(tailMove[c]));
  }
}

template <int Dim>
__global__ void __launch_bounds__(kThreads) applyKernel(float* positions, unsigned long long* moves, std::size_t n)
{
  const std::size_t v = blockIdx.x * static_cast<std::size_t>(kThreads) + threadIdx.x;
  if (v >= n)
  {
    return;
  }
  for (int c = 0; c < Dim; ++c)
  {
    const long long m = static_cast<long long>(moves[4 * v + c]);
    if (m != 0)
    {
      positions[4 * v + c] += static_cast<float>(static_cast<double>(m) * umap::kFixedUnit);
      moves[4 * v + c] = 0;
    }
  }
}

unsigned blocksFor(std::size_t count)
{
  return static_cast<unsigned>((count + kThreads - 1) / kThreads);
}

template <int Dim>
bool runEpochs(const LayoutProblem& p, const EdgeState& s, const std::vector<std::size_t>& roundStart,
  float* positions, unsigned long long* moves, const std::function<void(double)>& progress, std::string* error)
{
  const umap::Curve curve{ static_cast<float>(p.a), static_cast<float>(p.b), static_cast<float>(p.gamma) };
  for (int epoch = 0; epoch < p.epochs; ++epoch)
  {
    // umap-learn: epoch 0 at the initial rate, epoch e > 0 at alpha (1 - (e - 1) / epochs).
    const float alpha =
      static_cast<float>(p.initialAlpha * (epoch == 0 ? 1.0 : 1.0 - static_cast<double>(epoch - 1) / p.epochs));
    for (int r = 0; r < p.rounds; ++r)
    {
      const std::size_t first = roundStart[r], count = roundStart[r + 1] - first;
      if (count == 0)
      {
        continue;
      }
      edgeKernel<Dim><<<blocksFor(count), kThreads>>>(s, first, count, positions, moves, p.n, epoch, alpha, curve, p.seed);
      MCV_CUDA_TRY(cudaGetLastError());
      applyKernel<Dim><<<blocksFor(p.n), kThreads>>>(positions, moves, p.n);
      MCV_CUDA_TRY(cudaGetLastError());
    }
    if ((epoch + 1) % kEpochsPerReport == 0 || epoch + 1 == p.epochs)
    {
      MCV_CUDA_TRY(cudaDeviceSynchronize()); // also surfaces a failed kernel here
      if (progress)
      {
        progress(static_cast<double>(epoch + 1) / p.epochs);
      }
    }
  }
  return true;
}
} // namespace

int defaultLayoutRounds(std::size_t n)
{
  return n <= 10000 ? 4 : 16;
}

bool optimizeLayout(const LayoutProblem& problem, float* Y, const std::function<void(double)>& progress,
  LayoutStats* stats, std::string* error)
{
  FaultStage stage("umaplayout");
  LayoutProblem p = problem;
  if (p.rounds == 0)
  {
    p.rounds = defaultLayoutRounds(p.n);
  }
  if ((p.dim != 2 && p.dim != 3) || p.n == 0 || p.n >= 0xffffffffull || p.epochs < 1 || p.rounds < 1 ||
    p.negativeSampleRate < 1 || (p.edges > 0 && (!p.head || !p.tail || !p.weight)))
  {
    return detail::fail(error, "invalid GPU layout arguments");
  }
  LayoutStats local;
  LayoutStats& st = stats ? *stats : local;
  st = LayoutStats{};
  auto start = Clock::now();

  // The edges grouped by round (edge e of the graph's order in round e mod rounds), with
  // make_epochs_per_sample's max w / w_e.
  const std::size_t E = p.edges;
  const float wMax = E > 0 ? *std::max_element(p.weight, p.weight + E) : 1.f;
  std::vector<std::size_t> roundStart(static_cast<std::size_t>(p.rounds) + 1, 0);
  for (int r = 0; r < p.rounds; ++r)
  {
    const std::size_t inRound = E > static_cast<std::size_t>(r) ? (E - r + p.rounds - 1) / p.rounds : 0;
    roundStart[r + 1] = roundStart[r] + inRound;
  }
  std::vector<std::uint32_t> head(E), tail(E);
  std::vector<double> epochsPerSample(E), nextNegative(E);
  for (std::size_t e = 0; e < E; ++e)
  {
    const std::size_t at = roundStart[e % p.rounds] + e / p.rounds;
    head[at] = p.head[e];
    tail[at] = p.tail[e];
    epochsPerSample[at] = static_cast<double>(wMax) / static_cast<double>(p.weight[e]);
    nextNegative[at] = epochsPerSample[at] / p.negativeSampleRate;
  }
  std::vector<float> positions(p.n * 4, 0.f);
  for (std::size_t v = 0; v < p.n; ++v)
  {
    std::copy(Y + v * p.dim, Y + (v + 1) * p.dim, positions.begin() + static_cast<std::ptrdiff_t>(4 * v));
  }

  DeviceBuffer dHead, dTail, dEps, dNext, dNextNeg, dPos, dMoves;
  const std::size_t edgeBytes = std::max<std::size_t>(E, 1);
  MCV_CUDA_TRY(cudaMalloc(&dHead.ptr, edgeBytes * sizeof(std::uint32_t)));
  MCV_CUDA_TRY(cudaMalloc(&dTail.ptr, edgeBytes * sizeof(std::uint32_t)));
  MCV_CUDA_TRY(cudaMalloc(&dEps.ptr, edgeBytes * sizeof(double)));
  MCV_CUDA_TRY(cudaMalloc(&dNext.ptr, edgeBytes * sizeof(double)));
  MCV_CUDA_TRY(cudaMalloc(&dNextNeg.ptr, edgeBytes * sizeof(double)));
  MCV_CUDA_TRY(cudaMalloc(&dPos.ptr, positions.size() * sizeof(float)));
  MCV_CUDA_TRY(cudaMalloc(&dMoves.ptr, positions.size() * sizeof(unsigned long long)));
  if (E > 0)
  {
    MCV_CUDA_TRY(cudaMemcpy(dHead.ptr, head.data(), E * sizeof(std::uint32_t), cudaMemcpyHostToDevice));
    MCV_CUDA_TRY(cudaMemcpy(dTail.ptr, tail.data(), E * sizeof(std::uint32_t), cudaMemcpyHostToDevice));
    MCV_CUDA_TRY(cudaMemcpy(dEps.ptr, epochsPerSample.data(), E * sizeof(double), cudaMemcpyHostToDevice));
    // next sample starts at epochs per sample, as umap-learn's epoch_of_next_sample
    MCV_CUDA_TRY(cudaMemcpy(dNext.ptr, epochsPerSample.data(), E * sizeof(double), cudaMemcpyHostToDevice));
    MCV_CUDA_TRY(cudaMemcpy(dNextNeg.ptr, nextNegative.data(), E * sizeof(double), cudaMemcpyHostToDevice));
  }
  MCV_CUDA_TRY(cudaMemcpy(dPos.ptr, positions.data(), positions.size() * sizeof(float), cudaMemcpyHostToDevice));
  MCV_CUDA_TRY(cudaMemset(dMoves.ptr, 0, positions.size() * sizeof(unsigned long long)));
  st.uploadMs = msSince(start);

  start = Clock::now();
  const EdgeState s{ dHead.as<std::uint32_t>(), dTail.as<std::uint32_t>(), dEps.as<double>(), dNext.as<double>(),
    dNextNeg.as<double>(), static_cast<double>(p.negativeSampleRate) };
  const bool ok = p.dim == 2
    ? runEpochs<2>(p, s, roundStart, dPos.as<float>(), dMoves.as<unsigned long long>(), progress, error)
    : runEpochs<3>(p, s, roundStart, dPos.as<float>(), dMoves.as<unsigned long long>(), progress, error);
  if (!ok)
  {
    return false;
  }
  st.computeMs = msSince(start);

  start = Clock::now();
  MCV_CUDA_TRY(cudaMemcpy(positions.data(), dPos.ptr, positions.size() * sizeof(float), cudaMemcpyDeviceToHost));
  for (std::size_t v = 0; v < p.n; ++v)
  {
    std::copy(positions.begin() + static_cast<std::ptrdiff_t>(4 * v),
      positions.begin() + static_cast<std::ptrdiff_t>(4 * v + p.dim), Y + v * p.dim);
  }
  st.downloadMs = msSince(start);
  return true;
}

} // namespace cuda
} // namespace mcv
