#include "UMAPLayout.h"

#include "SeededRandom.h"
#include "UMAPGraph.h"

#include <Eigen/Dense>

#include <algorithm>
#include <array>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstring>
#include <numeric>
#include <thread>

#ifdef __SSE__
#include <xmmintrin.h>
#endif
#if defined(__x86_64__) && (defined(__GNUC__) || defined(__clang__))
#define MCV_UMAP_AVX2 1
#include <immintrin.h>
#endif

#ifdef _OPENMP
#include <omp.h>
#else
inline int omp_get_num_threads() { return 1; }
inline int omp_get_thread_num() { return 0; }
inline int omp_get_max_threads() { return 1; }
#endif

namespace mcv
{

// ---- Curve parameters --------------------------------------------------------------------

namespace
{
constexpr int kCurvePoints = 300;

struct CurveFit
{
  Eigen::VectorXd x, y;
  double cost(double a, double b) const
  {
    double s = 0;
    for (Eigen::Index i = 0; i < x.size(); ++i)
    {
      const double r = 1.0 / (1.0 + a * std::pow(x[i], 2 * b)) - y[i];
      s += r * r;
    }
    return s;
  }
};
} // namespace

CurveParameters fitCurveParameters(double minDist, double spread)
{
  CurveFit f;
  f.x = Eigen::VectorXd::LinSpaced(kCurvePoints, 0.0, 3.0 * spread);
  f.y.resize(kCurvePoints);
  for (int i = 0; i < kCurvePoints; ++i)
  {
    f.y[i] = f.x[i] < minDist ? 1.0 : std::exp(-(f.x[i] - minDist) / spread);
  }
  // Levenberg-Marquardt with Marquardt's diagonal scaling (MINPACK's, which curve_fit runs).
  double a = 1.0, b = 1.0, lambda = 1e-3;
  double cost = f.cost(a, b);
  CurveParameters out;
  for (int it = 0; it < 500; ++it)
  {
    Eigen::Matrix2d JtJ = Eigen::Matrix2d::Zero();
    Eigen::Vector2d Jtr = Eigen::Vector2d::Zero();
    for (int i = 0; i < kCurvePoints; ++i)
    {
      const double x = f.x[i];
      const double p = x > 0 ? std::pow(x, 2 * b) : 0.0;
      const double q = 1.0 / (1.0 + a * p);
      const Eigen::Vector2d J(-p * q * q, x > 0 ? -a * p * 2.0 * std::log(x) * q * q : 0.0);
      JtJ += J * J.transpose();
      Jtr += J * (q - f.y[i]);
    }
    bool accepted = false;
    while (!accepted && lambda < 1e12)
    {
      Eigen::Matrix2d A = JtJ;
      A.diagonal() *= 1.0 + lambda;
      const Eigen::Vector2d step = A.ldlt().solve(-Jtr);
      const double na = a + step[0], nb = b + step[1];
      const double nc = (na > 0 && nb > 0) ? f.cost(na, nb) : HUGE_VAL;
      if (nc < cost)
      {
        const bool done = cost - nc <= 1e-15 * cost || step.norm() <= 1e-12 * (1.0 + std::hypot(a, b));
        a = na;
        b = nb;
        cost = nc;
        lambda = std::max(lambda * 0.1, 1e-12);
        accepted = true;
        if (done)
        {
          out = { a, b, true };
          return out;
        }
      }
      else
      {
        lambda *= 10.0;
      }
    }
    if (!accepted) // no step lowers the cost: a minimum (to rounding)
    {
      out = { a, b, true };
      return out;
    }
  }
  out = { a, b, false };
  return out;
}

int defaultEpochs(std::size_t points)
{
  return points <= 10000 ? 500 : 200;
}

// ---- The layout --------------------------------------------------------------------------

namespace
{
constexpr int kPairsPerRound = kLayoutBlocks / 2;
constexpr int kTasks = kLayoutBlocks * kPairsPerRound; // kLayoutBlocks rounds
constexpr int kEpochsPerRegion = 10; // between progress reports (and abort checks)

// task[u][v]: the task (round * kPairsPerRound + slot) of the edges between blocks u and v.
// Rounds 0 .. B-2: the circle method (block B-1 fixed, the others rotating) pairs every two
// blocks once; round B-1: slot s takes the edges within block 2s and within block 2s + 1.
std::array<std::array<int, kLayoutBlocks>, kLayoutBlocks> pairTasks()
{
  std::array<std::array<int, kLayoutBlocks>, kLayoutBlocks> task{};
  constexpr int B = kLayoutBlocks, R = B - 1;
  for (int r = 0; r < R; ++r)
  {
    for (int s = 0; s < kPairsPerRound; ++s)
    {
      const int u = s == 0 ? B - 1 : (r + s) % R;
      const int v = s == 0 ? r : (r - s + R) % R;
      task[u][v] = task[v][u] = r * kPairsPerRound + s;
    }
  }
  for (int s = 0; s < kPairsPerRound; ++s)
  {
    task[2 * s][2 * s] = task[2 * s + 1][2 * s + 1] = R * kPairsPerRound + s;
  }
  return task;
}

// The edges in processing order, with umap-learn's per-edge sampling state.
struct Schedule
{
  std::array<std::array<int, 2>, kTasks> blocks; // the two blocks of each task
  std::vector<std::size_t> taskStart; // kTasks + 1
  // The layout works on the vertices renumbered block by block (slot[v]), so a block's
  // positions are contiguous and two threads never write to one cache line (with the
  // seeded blocks interleaved in memory, false sharing made 2 threads 2.3x slower than 1).
  std::vector<std::uint32_t> slot;
  std::vector<std::uint32_t> head, tail; // slots
  std::vector<double> epochsPerSample, nextSample, epochsPerNegative, nextNegative;
};

Schedule makeSchedule(const FuzzyGraph& g, double negativeSampleRate, std::uint64_t seed)
{
  const std::size_t n = g.n, E = g.edgeCount();
  // Seeded blocks, so that neighbouring points (often consecutive indices) spread over all.
  std::vector<std::uint32_t> order(n);
  std::iota(order.begin(), order.end(), 0u);
  std::uint64_t state = mix64(seed ^ 0x5DEECE66Dull);
  for (std::size_t i = n; i > 1; --i)
  {
    std::swap(order[i - 1], order[uniformIndex(state, i)]);
  }
  Schedule s;
  s.slot.resize(n);
  std::vector<std::uint8_t> block(n);
  for (std::size_t i = 0; i < n; ++i)
  {
    s.slot[order[i]] = static_cast<std::uint32_t>(i);
    block[order[i]] = static_cast<std::uint8_t>(i * kLayoutBlocks / n);
  }
  const auto task = pairTasks();
  const float wMax = E > 0 ? *std::max_element(g.weight.begin(), g.weight.end()) : 1.f;

  for (int u = 0; u < kLayoutBlocks; ++u)
  {
    for (int v = 0; v < kLayoutBlocks; ++v)
    {
      s.blocks[task[u][v]] = u == v ? std::array<int, 2>{ u & ~1, u | 1 } : std::array<int, 2>{ u, v };
    }
  }
  s.taskStart.assign(kTasks + 1, 0);
  std::vector<int> edgeTask(E);
  for (std::size_t i = 0; i < n; ++i)
  {
    for (std::size_t e = g.start[i]; e < g.start[i + 1]; ++e)
    {
      edgeTask[e] = task[block[i]][block[g.to[e]]];
      ++s.taskStart[static_cast<std::size_t>(edgeTask[e]) + 1];
    }
  }
  for (int t = 0; t < kTasks; ++t)
  {
    s.taskStart[t + 1] += s.taskStart[t];
  }
  s.head.resize(E);
  s.tail.resize(E);
  s.epochsPerSample.resize(E);
  std::vector<std::uint32_t> head(E);
  for (std::size_t i = 0; i < n; ++i)
  {
    std::fill(head.begin() + static_cast<std::ptrdiff_t>(g.start[i]), head.begin() + static_cast<std::ptrdiff_t>(g.start[i + 1]),
      static_cast<std::uint32_t>(i));
  }
  // Within a task, the edges go by their rank in the row, then by row (the first edge of
  // every row, then the second, ...): consecutive samples then have different heads, so
  // their updates overlap in the core; in row order a sample waited for the one before to
  // store the head it reads (a chain of dependent updates: the layout ran 2x slower).
  std::size_t maxDegree = 0;
  for (std::size_t i = 0; i < n; ++i)
  {
    maxDegree = std::max(maxDegree, g.start[i + 1] - g.start[i]);
  }
  std::vector<std::size_t> byRank;
  byRank.reserve(E);
  for (std::size_t r = 0; r < maxDegree; ++r)
  {
    for (std::size_t i = 0; i < n; ++i)
    {
      if (g.start[i] + r < g.start[i + 1])
      {
        byRank.push_back(g.start[i] + r);
      }
    }
  }
  std::vector<std::size_t> fill(s.taskStart.begin(), s.taskStart.end() - 1);
  for (const std::size_t e : byRank)
  {
    const std::size_t at = fill[static_cast<std::size_t>(edgeTask[e])]++;
    s.head[at] = s.slot[head[e]];
    s.tail[at] = s.slot[g.to[e]];
    // make_epochs_per_sample: epochs / (epochs * w / wMax).
    s.epochsPerSample[at] = static_cast<double>(wMax) / static_cast<double>(g.weight[e]);
  }
  s.nextSample = s.epochsPerSample;
  s.epochsPerNegative.resize(E);
  for (std::size_t e = 0; e < E; ++e)
  {
    s.epochsPerNegative[e] = s.epochsPerSample[e] / negativeSampleRate;
  }
  s.nextNegative = s.epochsPerNegative;
  return s;
}

// The two gradient coefficients as functions of the squared distance d2,
//   attraction -2ab d2^(b-1) / (1 + a d2^b),   repulsion 2 gamma b / ((0.001 + d2)(1 + a d2^b)),
// tabulated on a grid of 2^kMantissaBits points per octave of d2 (computed in double) and
// interpolated linearly: relative error < 4e-4 for any a, b of MinimumDistance in [0, 1].
// A lookup is a few integer operations and one load where powf and a division took ~100
// cycles of latency on every update's dependency chain (the layout ran 3x slower).
// d2 is clamped to [2^kMinOctave, 2^kMaxOctave): below, points coincide to 1e-4 (the
// coefficient times the difference vanishes either way); above, they are 1000 apart, which
// a layout never is.
class GradientTable
{
public:
  GradientTable(double a, double b, double gamma)
  {
    for (int t = 0; t < 2; ++t)
    {
      table_[t].resize(2 * kEntries + 2);
      for (int k = 0; k <= kEntries; ++k)
      {
        const double x = gridPoint(k);
        const double xb = std::pow(x, b);
        const double v = t == 0 ? -2.0 * a * b * xb / (x * (1.0 + a * xb)) : 2.0 * gamma * b / ((0.001 + x) * (1.0 + a * xb));
        table_[t][2 * k] = static_cast<float>(v);
      }
      for (int k = 0; k < kEntries; ++k) // slope to the next grid point
      {
        table_[t][2 * k + 1] = static_cast<float>((double(table_[t][2 * k + 2]) - table_[t][2 * k]) / (gridPoint(k + 1) - gridPoint(k)));
      }
    }
  }
  float attraction(float d2) const { return lookup(table_[0].data(), d2); }
  float repulsion(float d2) const { return lookup(table_[1].data(), d2); }
  // For negativesAvx2, which repeats lookup two samples at a time.
  const float* repulsionTable() const { return table_[1].data(); }
  static constexpr int kMantissaBits = 6, kMinOctave = -27, kMaxOctave = 20;
  static constexpr int kShift = 23 - kMantissaBits;
  static constexpr float kLow = 1.f / (1u << -kMinOctave);
  static constexpr float kHigh = float(1u << kMaxOctave) * (1.f - 1.f / (1 << 23));

private:
  static constexpr int kEntries = (kMaxOctave - kMinOctave) << kMantissaBits;
  static double gridPoint(int k)
  {
    return std::ldexp(1.0 + double(k & ((1 << kMantissaBits) - 1)) / (1 << kMantissaBits), kMinOctave + (k >> kMantissaBits));
  }
  static float lookup(const float* t, float d2)
  {
    d2 = std::min(std::max(d2, kLow), kHigh);
    std::uint32_t bits;
    std::memcpy(&bits, &d2, sizeof bits);
    const int k = static_cast<int>(bits >> kShift) - ((127 + kMinOctave) << kMantissaBits);
    bits &= ~((1u << kShift) - 1u); // the grid point at or below d2
    float x0;
    std::memcpy(&x0, &bits, sizeof x0);
    return t[2 * k] + (d2 - x0) * t[2 * k + 1];
  }
  std::vector<float> table_[2]; // per entry: value, slope
};

// A position as 4 floats (2D and 3D layouts leave the unused lanes at 0): one SSE register
// on x86-64 (GCC/Clang vector extension, portable), so a difference, a clip or an update
// is one instruction instead of one per axis (the layout ran 1.3x slower per axis).
using Vec4 = float __attribute__((vector_size(16)));
constexpr int kStride = 4;

struct Step;
// The summed repulsions of one positive sample's `count` negative samples (see runTask).
using NegativesFn = Vec4 (*)(std::uint64_t& rng, int count, std::uint32_t head, Vec4 current, const Step& p,
  const float* start);

struct Step
{
  float alpha;
  std::size_t n;
  int epoch;
  std::uint64_t seed;
  const GradientTable* gradient;
  Vec4 coincidentPush; // 4 on the layout's axes, 0 beyond
  NegativesFn negatives;
};

inline Vec4 load4(const float* p)
{
  Vec4 v;
  std::memcpy(&v, p, sizeof v);
  return v;
}

inline void store4(float* p, Vec4 v)
{
  std::memcpy(p, &v, sizeof v);
}

inline float squaredNorm(Vec4 v)
{
  const Vec4 s = v * v;
  return (s[0] + s[1]) + (s[2] + s[3]);
}

// umap-learn's clip of every gradient component to [-4, 4].
inline Vec4 clip4(Vec4 v)
{
#ifdef __SSE__
  // minps/maxps: the compiler keeps the selects below as compare-and-mask sequences.
  return reinterpret_cast<Vec4>(_mm_min_ps(_mm_max_ps(reinterpret_cast<__m128>(v), _mm_set1_ps(-4.f)), _mm_set1_ps(4.f)));
#else
  const Vec4 lo = { -4.f, -4.f, -4.f, -4.f }, hi = { 4.f, 4.f, 4.f, 4.f };
  v = v < lo ? lo : v;
  return v > hi ? hi : v;
#endif
}

// The negative samples of one positive sample all see the head where the attraction left
// it, and their (clipped) pushes are applied together: umap-learn moves the head after
// each, a difference within one sample's step, and independent of each other they overlap
// in the core instead of forming one chain of dependent updates.
// Two vertices per 64-bit draw, each by Lemire's multiply-shift from 32 of its bits: the
// hash's two multiplies were the busiest port of this loop.
Vec4 negativesScalar(std::uint64_t& rng, int count, std::uint32_t head, Vec4 current, const Step& p, const float* start)
{
  Vec4 push = {};
  const auto repel = [&](std::uint64_t k) {
    if (k == head)
    {
      return; // umap-learn skips the point itself
    }
    const Vec4 away = current - load4(start + k * kStride);
    const float d = squaredNorm(away);
    // Another point on top of the head is pushed by +4 per axis (umap-learn's fixed push).
    push += d > 0 ? clip4(p.gradient->repulsion(d) * away) : p.coincidentPush;
  };
  for (int q = 0; q < count; q += 2)
  {
    const std::uint64_t r = splitmix64(rng);
    repel(((r >> 32) * p.n) >> 32);
    if (q + 1 < count)
    {
      repel(((r & 0xFFFFFFFFull) * p.n) >> 32);
    }
  }
  return push;
}

#ifdef MCV_UMAP_AVX2
// negativesScalar two samples at a time, one per 128-bit half of a 256-bit register, with
// the same bits: every half rounds the same float operations in the same order (the
// squared norm as (x^2 + y^2) + (z^2 + w^2) by two in-lane shuffles; this file is compiled
// with -ffp-contract=off, so nothing is fused into an FMA), and the pushes are added in
// draw order. A test compares the two (TestUMAP). 1.2x faster layout than the scalar loop
// (6D, N = 10000, one thread); eight samples a time with AVX-512 gathers of the positions
// and table entries was 1.3x slower than the scalar loop (the dev VM's EPYC).
__attribute__((target("avx2"))) Vec4 negativesAvx2(
  std::uint64_t& rng, int count, std::uint32_t head, Vec4 current, const Step& p, const float* start)
{
  using G = GradientTable;
  const float* const table = p.gradient->repulsionTable();
  __m128 c4, pc4;
  std::memcpy(&c4, &current, sizeof c4);
  std::memcpy(&pc4, &p.coincidentPush, sizeof pc4);
  const __m256 cur = _mm256_set_m128(c4, c4), coincident = _mm256_set_m128(pc4, pc4);
  const __m256 low = _mm256_set1_ps(G::kLow), high = _mm256_set1_ps(G::kHigh);
  const __m256 four = _mm256_set1_ps(4.f), minusFour = _mm256_set1_ps(-4.f), zero = _mm256_setzero_ps();
  const __m256i offset = _mm256_set1_epi32((127 + G::kMinOctave) << G::kMantissaBits);
  const __m256i grid = _mm256_set1_epi32(static_cast<int>(~((1u << G::kShift) - 1u)));
  __m128 push = _mm_setzero_ps();
  for (int q = 0; q < count; q += 2)
  {
    const std::uint64_t r = splitmix64(rng);
    const bool two = q + 1 < count;
    const std::uint64_t k0 = ((r >> 32) * p.n) >> 32;
    const std::uint64_t k1 = two ? ((r & 0xFFFFFFFFull) * p.n) >> 32 : k0;
    const __m256 at = _mm256_insertf128_ps(
      _mm256_castps128_ps256(_mm_loadu_ps(start + k0 * kStride)), _mm_loadu_ps(start + k1 * kStride), 1);
    const __m256 away = _mm256_sub_ps(cur, at);
    const __m256 sq = _mm256_mul_ps(away, away);
    const __m256 pairs = _mm256_add_ps(sq, _mm256_permute_ps(sq, _MM_SHUFFLE(2, 3, 0, 1)));
    const __m256 d2 = _mm256_add_ps(pairs, _mm256_permute_ps(pairs, _MM_SHUFFLE(1, 0, 3, 2)));
    // GradientTable::lookup, the entry's (value, slope) pair as one 64-bit load per half.
    const __m256 d2c = _mm256_min_ps(_mm256_max_ps(d2, low), high);
    const __m256i bits = _mm256_castps_si256(d2c);
    const __m256i entry = _mm256_sub_epi32(_mm256_srli_epi32(bits, G::kShift), offset);
    const __m256 x0 = _mm256_castsi256_ps(_mm256_and_si256(bits, grid));
    const float* const t0 = table + 2 * _mm256_cvtsi256_si32(entry);
    const float* const t1 = table + 2 * _mm256_extract_epi32(entry, 4);
    const __m256 vs = _mm256_insertf128_ps(
      _mm256_castps128_ps256(_mm_castsi128_ps(_mm_loadl_epi64(reinterpret_cast<const __m128i*>(t0)))),
      _mm_castsi128_ps(_mm_loadl_epi64(reinterpret_cast<const __m128i*>(t1))), 1);
    const __m256 coeff =
      _mm256_add_ps(_mm256_permute_ps(vs, 0x00), _mm256_mul_ps(_mm256_sub_ps(d2c, x0), _mm256_permute_ps(vs, 0x55)));
    const __m256 clipped = _mm256_min_ps(_mm256_max_ps(_mm256_mul_ps(coeff, away), minusFour), four);
    const __m256 force = _mm256_blendv_ps(coincident, clipped, _mm256_cmp_ps(d2, zero, _CMP_GT_OQ));
    if (k0 != head)
    {
      push = _mm_add_ps(push, _mm256_castps256_ps128(force));
    }
    if (two && k1 != head)
    {
      push = _mm_add_ps(push, _mm256_extractf128_ps(force, 1));
    }
  }
  Vec4 out;
  std::memcpy(&out, &push, sizeof out);
  return out;
}

bool hasAvx2()
{
  static const bool ok = __builtin_cpu_supports("avx2");
  return ok;
}
#else
bool hasAvx2()
{
  return false;
}
#endif

NegativesFn negativesFor(bool vectorised)
{
#ifdef MCV_UMAP_AVX2
  if (vectorised && hasAvx2())
  {
    return negativesAvx2;
  }
#endif
  (void)vectorised;
  return negativesScalar;
}

// One task's edges in one epoch: umap-learn's _optimize_layout_euclidean_single_epoch.
// Y, start: kStride floats per slot.
void runTask(Schedule& s, int task, const Step& p, float* Y, const float* start)
{
  thread_local std::vector<std::uint32_t> due;
  std::uint64_t rng = mix64(mix64(p.seed) ^ (static_cast<std::uint64_t>(p.epoch) * kTasks + task + 1));
  const double epoch = p.epoch;
  const Vec4 alpha = { p.alpha, p.alpha, p.alpha, p.alpha };
  // The edges due this epoch first, without a branch: an edge is due with probability
  // w / max w, a branch the CPU mispredicts, flushing the updates in flight (the
  // attractions alone ran 1.4x slower).
  const std::size_t first = s.taskStart[task], count = s.taskStart[task + 1] - first;
  due.resize(count);
  std::size_t m = 0;
  for (std::size_t e = 0; e < count; ++e)
  {
    due[m] = static_cast<std::uint32_t>(first + e);
    m += s.nextSample[first + e] <= epoch ? 1 : 0;
  }
  for (std::size_t r = 0; r < m; ++r)
  {
    const std::size_t i = due[r];
    const std::uint32_t j = s.head[i];
    float* const headAt = Y + static_cast<std::size_t>(j) * kStride;
    float* const tailAt = Y + static_cast<std::size_t>(s.tail[i]) * kStride;
    Vec4 current = load4(headAt);
    const Vec4 other = load4(tailAt);
    const Vec4 diff = current - other;
    const float d2 = squaredNorm(diff);
    const float coeff = d2 > 0 ? p.gradient->attraction(d2) : 0.f;
    const Vec4 pull = clip4(coeff * diff) * alpha;
    current += pull;
    store4(tailAt, other - pull);
    s.nextSample[i] += s.epochsPerSample[i];

    const int negatives = static_cast<int>((epoch - s.nextNegative[i]) / s.epochsPerNegative[i]);
    const Vec4 push = p.negatives(rng, negatives, j, current, p, start);
    store4(headAt, current + push * alpha);
    s.nextNegative[i] += negatives * s.epochsPerNegative[i];
  }
}

// A barrier whose waiters spin with a yield (OpenMP's spin without yielding: on a machine
// shared with other work, a waiting thread then burns the time slice the late one needs).
class EpochBarrier
{
public:
  void wait(int threads)
  {
    const long generation = generation_.load(std::memory_order_acquire);
    if (arrived_.fetch_add(1, std::memory_order_acq_rel) + 1 == threads)
    {
      arrived_.store(0, std::memory_order_relaxed);
      generation_.store(generation + 1, std::memory_order_release);
      return;
    }
    while (generation_.load(std::memory_order_acquire) == generation)
    {
      std::this_thread::yield();
    }
  }

private:
  std::atomic<int> arrived_{ 0 };
  std::atomic<long> generation_{ 0 };
};

// Per region of epochs, the layout runs on all threads or on one: whichever took less time
// per epoch when last tried (each is tried again every kRetryRegions regions). The result
// is the same bits on any number of threads, so the choice changes only the time. Why: on
// a machine whose other work leaves this process about one core, two threads wait for each
// other at the 16 rounds of every epoch and took longer than one (6D and 24D, N = 10000:
// layout 1.8-2.2 s on two threads against 1.4-1.6 s on one, same minute).
class ThreadChoice
{
public:
  explicit ThreadChoice(int most)
    : most_(std::max(1, most))
  {
  }
  int next()
  {
    const int region = region_++;
    if (most_ == 1 || region == 1)
    {
      return 1;
    }
    if (region == 0)
    {
      return most_;
    }
    // All threads only when clearly faster: a region is ~20 ms, timed on a busy machine.
    const bool manyFaster = perEpoch_[1] < kClearlyFaster * perEpoch_[0];
    const bool retry = region % kRetryRegions == 0;
    return manyFaster != retry ? most_ : 1;
  }
  void record(int threads, double secondsPerEpoch) { perEpoch_[threads == 1 ? 0 : 1] = secondsPerEpoch; }

private:
  static constexpr int kRetryRegions = 8;
  static constexpr double kClearlyFaster = 0.85;
  int most_;
  int region_ = 0;
  double perEpoch_[2] = { 0.0, 0.0 }; // one thread, all
};

template <int Dim>
void optimize(const FuzzyGraph& graph, const LayoutOptions& o, RowMatrixF& Y)
{
  Schedule s = makeSchedule(graph, o.negativeSampleRate, o.seed);
  const std::size_t n = graph.n;
  std::vector<float> start(n * kStride), slots(n * kStride, 0.f);
  for (std::size_t v = 0; v < n; ++v)
  {
    std::copy(Y.data() + v * Dim, Y.data() + (v + 1) * Dim, slots.data() + std::size_t(s.slot[v]) * kStride);
  }
  Vec4 coincidentPush = {};
  for (int c = 0; c < Dim; ++c)
  {
    coincidentPush[c] = 4.f;
  }
  const GradientTable gradient(o.a, o.b, o.gamma);
  const NegativesFn negatives = negativesFor(o.vectorised);
  float* const y = slots.data();
  float* const snapshot = start.data();
  // The threads take the epoch's tasks in order (round by round) from a shared counter; a
  // task waits only for its two blocks to finish the round before (every block is in one
  // task per round), and the epochs are separated by one barrier (the snapshot). Both waits
  // spin with a yield: on a loaded machine the thread being waited for may need this core.
  std::array<std::atomic<long>, kLayoutBlocks> rounds{}; // rounds each block has finished
  std::atomic<int> nextTask{ 0 };
  EpochBarrier barrier;
  // umap-learn: epoch 0 at the initial rate, epoch e > 0 at alpha (1 - (e - 1) / epochs).
  const auto step = [&](int epoch) {
    return Step{ static_cast<float>(o.initialAlpha * (epoch == 0 ? 1.0 : 1.0 - double(epoch - 1) / o.epochs)), n, epoch,
      o.seed, &gradient, coincidentPush, negatives };
  };
  ThreadChoice choice(omp_get_max_threads());
  for (int e0 = 0; e0 < o.epochs; e0 += kEpochsPerRegion)
  {
    const int e1 = std::min(o.epochs, e0 + kEpochsPerRegion);
    const int threads = choice.next();
    const auto began = std::chrono::steady_clock::now();
    if (threads == 1) // the tasks in order (the order the parallel rounds keep), no waits
    {
      for (int epoch = e0; epoch < e1; ++epoch)
      {
        std::copy(y, y + n * kStride, snapshot);
        const Step p = step(epoch);
        for (int task = 0; task < kTasks; ++task)
        {
          runTask(s, task, p, y, snapshot);
        }
        for (auto& r : rounds)
        {
          r.store(static_cast<long>(epoch + 1) * kLayoutBlocks, std::memory_order_relaxed);
        }
      }
    }
    else
    {
#pragma omp parallel num_threads(threads)
      {
        const int T = omp_get_num_threads(), me = omp_get_thread_num();
        for (int epoch = e0; epoch < e1; ++epoch)
        {
          if (me == 0) // the positions this epoch's negative samples read
          {
            std::copy(y, y + n * kStride, snapshot);
            nextTask.store(0, std::memory_order_relaxed);
          }
          barrier.wait(T);
          const Step p = step(epoch);
          for (int task = nextTask.fetch_add(1); task < kTasks; task = nextTask.fetch_add(1))
          {
            const long before = static_cast<long>(epoch) * kLayoutBlocks + task / kPairsPerRound;
            for (const int b : s.blocks[task])
            {
              while (rounds[b].load(std::memory_order_acquire) < before)
              {
                std::this_thread::yield();
              }
            }
            runTask(s, task, p, y, snapshot);
            for (const int b : s.blocks[task])
            {
              rounds[b].store(before + 1, std::memory_order_release);
            }
          }
          barrier.wait(T);
        }
      }
    }
    choice.record(threads, std::chrono::duration<double>(std::chrono::steady_clock::now() - began).count() / (e1 - e0));
    if (o.progress)
    {
      o.progress("UMAP: layout", double(e1) / o.epochs);
    }
  }
  for (std::size_t v = 0; v < n; ++v)
  {
    std::copy(y + std::size_t(s.slot[v]) * kStride, y + std::size_t(s.slot[v]) * kStride + Dim, Y.data() + v * Dim);
  }
}
} // namespace

bool layoutHasWideNegatives()
{
  return hasAvx2();
}

void optimizeLayout(const FuzzyGraph& graph, const LayoutOptions& options, RowMatrixF& Y)
{
  if (Y.cols() == 2)
  {
    optimize<2>(graph, options, Y);
  }
  else
  {
    optimize<3>(graph, options, Y);
  }
}

} // namespace mcv
