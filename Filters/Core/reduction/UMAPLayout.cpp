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
#include <limits>
#include <numeric>
#include <thread>

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
  // For batchAvx2, which repeats lookup eight samples at a time.
  const float* attractionTable() const { return table_[0].data(); }
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

// Positions as kStride floats per slot (2D and 3D layouts leave the unused ones at 0):
// aligned rows, and a slot's offset is one shift.
constexpr int kStride = 4;

// umap-learn's clip of every gradient component to [-4, 4].
inline float clip(float v)
{
  return std::min(std::max(v, -4.f), 4.f);
}

// The negative samples' vertices come from a counter-based generator: draw q of the sample
// of edge e in epoch t is hash32(key(t, e) + q * kDrawStep) (lowbias32, a 32-bit bijection
// with good avalanche), mapped to [0, n) by Lemire's multiply-shift. Every sample has its own
// stream, so eight samples side by side draw their vertices in eight lanes at once with the
// same bits as one after the other (a shared sequential stream cost ~7 instructions per
// draw in the eight-lane loop, more than the rest of a negative sample).
inline std::uint32_t hash32(std::uint32_t x)
{
  x ^= x >> 16;
  x *= 0x7FEB352Du;
  x ^= x >> 15;
  x *= 0x846CA68Bu;
  x ^= x >> 16;
  return x;
}
constexpr std::uint32_t kDrawStep = 0x9E3779B9u;

inline std::uint32_t sampleKey(std::uint32_t epochKey, std::size_t edge)
{
  return hash32(epochKey ^ static_cast<std::uint32_t>(edge * 0x85EBCA6Bull) ^ static_cast<std::uint32_t>(edge >> 32));
}

inline std::uint32_t drawVertex(std::uint32_t key, int q, std::uint32_t n)
{
  const std::uint32_t r = hash32(key + static_cast<std::uint32_t>(q) * kDrawStep);
  return static_cast<std::uint32_t>((static_cast<std::uint64_t>(r) * n) >> 32);
}

struct Step
{
  float alpha;
  int epoch;
  std::uint32_t n;
  std::uint32_t epochKey;
  const GradientTable* gradient;
  bool batched; // eight samples side by side (AVX2)
};

// One positive sample of edge (head j, tail k), umap-learn's loop body, on positions stored
// as kStride floats per slot (Y, and start: the epoch's snapshot):
//  - attraction: both ends move by the clipped gradient times alpha;
//  - `count` negative samples: all see the head where the attraction left it, their clipped
//    pushes summed in draw order and applied together (umap-learn moves the head after
//    each: a difference within one sample's step, and independent of each other they
//    overlap in the core instead of forming one chain of dependent updates); a draw of the
//    head itself is skipped, as umap-learn skips it; another point on top of the head
//    pushes by +4 per axis (umap-learn's fixed push).
// Squared norms are rounded as (x^2 + y^2) + z^2 (2D: x^2 + y^2), the same in batchAvx2.
template <int Dim>
void sampleScalar(
  std::uint32_t j, std::uint32_t k, int count, std::uint32_t key, const Step& p, float* Y, const float* start)
{
  float* const h = Y + static_cast<std::size_t>(j) * kStride;
  float* const t = Y + static_cast<std::size_t>(k) * kStride;
  float diff[Dim], cur[Dim], push[Dim];
  for (int c = 0; c < Dim; ++c)
  {
    diff[c] = h[c] - t[c];
  }
  float d2 = diff[0] * diff[0] + diff[1] * diff[1];
  if (Dim == 3)
  {
    d2 = d2 + diff[Dim - 1] * diff[Dim - 1];
  }
  const float coeff = d2 > 0 ? p.gradient->attraction(d2) : 0.f;
  for (int c = 0; c < Dim; ++c)
  {
    const float pull = clip(coeff * diff[c]) * p.alpha;
    cur[c] = h[c] + pull;
    t[c] = t[c] - pull;
    push[c] = 0.f;
  }
  for (int q = 0; q < count; ++q)
  {
    const std::uint32_t v = drawVertex(key, q, p.n);
    if (v == j)
    {
      continue;
    }
    float away[Dim];
    for (int c = 0; c < Dim; ++c)
    {
      away[c] = cur[c] - start[static_cast<std::size_t>(v) * kStride + c];
    }
    float d = away[0] * away[0] + away[1] * away[1];
    if (Dim == 3)
    {
      d = d + away[Dim - 1] * away[Dim - 1];
    }
    const float rep = p.gradient->repulsion(d);
    for (int c = 0; c < Dim; ++c)
    {
      push[c] += d > 0 ? clip(rep * away[c]) : 4.f;
    }
  }
  for (int c = 0; c < Dim; ++c)
  {
    h[c] = cur[c] + push[c] * p.alpha;
  }
}

constexpr int kLanes = 8;

// Up to eight samples of one task, due consecutively and sharing no vertex.
struct Batch
{
  int lanes = 0;
  alignas(32) std::uint32_t head[kLanes], tail[kLanes], key[kLanes];
  alignas(32) std::int32_t count[kLanes];
};

#ifdef MCV_UMAP_AVX2
// Rows of kStride floats at byte offsets at[0..7] from base, transposed: axis c of the
// eight rows in out[c]. Eight 128-bit loads and a 4 x 4 transpose per half: with the AVX2
// gather instruction for the rows and table entries the eight-lane step was no faster than
// two samples at a time (Zen 3).
template <int Dim>
__attribute__((target("avx2"))) inline void loadRows8(const float* base, const std::uint32_t* at, __m256* out)
{
  const char* const bytes = reinterpret_cast<const char*>(base);
  const auto row = [&](int l) { return _mm_load_ps(reinterpret_cast<const float*>(bytes + at[l])); };
  const __m256 r0 = _mm256_insertf128_ps(_mm256_castps128_ps256(row(0)), row(4), 1);
  const __m256 r1 = _mm256_insertf128_ps(_mm256_castps128_ps256(row(1)), row(5), 1);
  const __m256 r2 = _mm256_insertf128_ps(_mm256_castps128_ps256(row(2)), row(6), 1);
  const __m256 r3 = _mm256_insertf128_ps(_mm256_castps128_ps256(row(3)), row(7), 1);
  const __m256 t0 = _mm256_unpacklo_ps(r0, r1), t2 = _mm256_unpacklo_ps(r2, r3); // x0 x1 y0 y1, x2 x3 y2 y3
  out[0] = _mm256_shuffle_ps(t0, t2, _MM_SHUFFLE(1, 0, 1, 0));
  out[1] = _mm256_shuffle_ps(t0, t2, _MM_SHUFFLE(3, 2, 3, 2));
  if (Dim == 3)
  {
    const __m256 t1 = _mm256_unpackhi_ps(r0, r1), t3 = _mm256_unpackhi_ps(r2, r3);
    out[Dim - 1] = _mm256_shuffle_ps(t1, t3, _MM_SHUFFLE(1, 0, 1, 0));
  }
}

// loadRows8 backwards: the eight rows of axes in[0..Dim) (the other axes 0) stored at byte
// offsets at[7], ..., at[0], in that order (a row stored twice keeps lane 0's, see runTask).
template <int Dim>
__attribute__((target("avx2"))) inline void storeRows8(float* base, const std::uint32_t* at, const __m256* in)
{
  char* const bytes = reinterpret_cast<char*>(base);
  const __m256 zero = _mm256_setzero_ps(), z = Dim == 3 ? in[Dim - 1] : zero;
  const __m256 t0 = _mm256_unpacklo_ps(in[0], in[1]), t1 = _mm256_unpackhi_ps(in[0], in[1]); // x0 y0 x1 y1, x2 y2 x3 y3
  const __m256 t2 = _mm256_unpacklo_ps(z, zero), t3 = _mm256_unpackhi_ps(z, zero);
  const __m256 r0 = _mm256_shuffle_ps(t0, t2, _MM_SHUFFLE(1, 0, 1, 0)); // rows 0 and 4
  const __m256 r1 = _mm256_shuffle_ps(t0, t2, _MM_SHUFFLE(3, 2, 3, 2)); // rows 1 and 5
  const __m256 r2 = _mm256_shuffle_ps(t1, t3, _MM_SHUFFLE(1, 0, 1, 0)); // rows 2 and 6
  const __m256 r3 = _mm256_shuffle_ps(t1, t3, _MM_SHUFFLE(3, 2, 3, 2)); // rows 3 and 7
  const auto row = [&](int l) { return reinterpret_cast<float*>(bytes + at[l]); };
  _mm_store_ps(row(7), _mm256_extractf128_ps(r3, 1));
  _mm_store_ps(row(6), _mm256_extractf128_ps(r2, 1));
  _mm_store_ps(row(5), _mm256_extractf128_ps(r1, 1));
  _mm_store_ps(row(4), _mm256_extractf128_ps(r0, 1));
  _mm_store_ps(row(3), _mm256_castps256_ps128(r3));
  _mm_store_ps(row(2), _mm256_castps256_ps128(r2));
  _mm_store_ps(row(1), _mm256_castps256_ps128(r1));
  _mm_store_ps(row(0), _mm256_castps256_ps128(r0));
}

// GradientTable::lookup in eight lanes; each entry's (value, slope) pair is one 64-bit load.
__attribute__((target("avx2"))) inline __m256 lookup8(const float* table, __m256 d2)
{
  using G = GradientTable;
  const __m256 d2c = _mm256_min_ps(_mm256_max_ps(d2, _mm256_set1_ps(G::kLow)), _mm256_set1_ps(G::kHigh));
  const __m256i bits = _mm256_castps_si256(d2c);
  const __m256i entry =
    _mm256_sub_epi32(_mm256_srli_epi32(bits, G::kShift), _mm256_set1_epi32((127 + G::kMinOctave) << G::kMantissaBits));
  const __m256 x0 =
    _mm256_castsi256_ps(_mm256_and_si256(bits, _mm256_set1_epi32(static_cast<int>(~((1u << G::kShift) - 1u)))));
  alignas(32) volatile std::uint32_t e[kLanes]; // byte offsets of the pairs (see loadRows8)
  _mm256_store_si256(const_cast<__m256i*>(reinterpret_cast<volatile __m256i*>(e)), _mm256_slli_epi32(entry, 3));
  const char* const bytes = reinterpret_cast<const char*>(table);
  std::uint32_t o[kLanes];
  for (int l = 0; l < kLanes; ++l)
  {
    o[l] = e[l];
  }
  const auto two = [&](int l, int m) { // entries l, m as (value, slope, value, slope)
    return _mm_castpd_ps(_mm_loadh_pd(_mm_load_sd(reinterpret_cast<const double*>(bytes + o[l])),
      reinterpret_cast<const double*>(bytes + o[m])));
  };
  const __m256 a = _mm256_insertf128_ps(_mm256_castps128_ps256(two(0, 1)), two(4, 5), 1);
  const __m256 b = _mm256_insertf128_ps(_mm256_castps128_ps256(two(2, 3)), two(6, 7), 1);
  const __m256 value = _mm256_shuffle_ps(a, b, _MM_SHUFFLE(2, 0, 2, 0));
  const __m256 slope = _mm256_shuffle_ps(a, b, _MM_SHUFFLE(3, 1, 3, 1));
  return _mm256_add_ps(value, _mm256_mul_ps(_mm256_sub_ps(d2c, x0), slope));
}

__attribute__((target("avx2"))) inline __m256 clip8(__m256 v)
{
  return _mm256_min_ps(_mm256_max_ps(v, _mm256_set1_ps(-4.f)), _mm256_set1_ps(4.f));
}

__attribute__((target("avx2"))) inline __m256i hash8(__m256i x)
{
  x = _mm256_xor_si256(x, _mm256_srli_epi32(x, 16));
  x = _mm256_mullo_epi32(x, _mm256_set1_epi32(0x7FEB352D));
  x = _mm256_xor_si256(x, _mm256_srli_epi32(x, 15));
  x = _mm256_mullo_epi32(x, _mm256_set1_epi32(static_cast<int>(0x846CA68Bu)));
  return _mm256_xor_si256(x, _mm256_srli_epi32(x, 16));
}

// sampleScalar for the batch's samples, one per lane: every lane rounds the same float
// operations in the same order (no FMA: this file is compiled with -ffp-contract=off), so
// the bits are those of the samples one after the other (they share no vertex, and the
// negative samples read the snapshot). Lanes beyond b.lanes repeat lane 0's vertices;
// their stores are overwritten by lane 0's. Why: eight negative samples per vector, not
// two; it runs at ~6 cycles a negative sample where two at a time took ~17
// (docs/benchmarks.md).
template <int Dim>
__attribute__((target("avx2"))) void batchAvx2(const Batch& b, const Step& p, float* Y, const float* start)
{
  const __m256 zero = _mm256_setzero_ps(), alpha = _mm256_set1_ps(p.alpha);
  const __m256i head = _mm256_load_si256(reinterpret_cast<const __m256i*>(b.head));
  alignas(32) std::uint32_t headAt[kLanes], tailAt[kLanes]; // byte offsets of the rows
  _mm256_store_si256(reinterpret_cast<__m256i*>(headAt), _mm256_slli_epi32(head, 4));
  _mm256_store_si256(reinterpret_cast<__m256i*>(tailAt),
    _mm256_slli_epi32(_mm256_load_si256(reinterpret_cast<const __m256i*>(b.tail)), 4));
  static_assert(kStride * sizeof(float) == 16, "row offsets are slot << 4");
  __m256 cur[Dim], tails[Dim], diff[Dim], push[Dim];
  loadRows8<Dim>(Y, headAt, cur);
  loadRows8<Dim>(Y, tailAt, tails);
  for (int c = 0; c < Dim; ++c)
  {
    diff[c] = _mm256_sub_ps(cur[c], tails[c]);
    push[c] = zero;
  }
  __m256 d2 = _mm256_add_ps(_mm256_mul_ps(diff[0], diff[0]), _mm256_mul_ps(diff[1], diff[1]));
  if (Dim == 3)
  {
    d2 = _mm256_add_ps(d2, _mm256_mul_ps(diff[Dim - 1], diff[Dim - 1]));
  }
  const __m256 coeff = _mm256_and_ps(lookup8(p.gradient->attractionTable(), d2), _mm256_cmp_ps(d2, zero, _CMP_GT_OQ));
  for (int c = 0; c < Dim; ++c)
  {
    const __m256 pull = _mm256_mul_ps(clip8(_mm256_mul_ps(coeff, diff[c])), alpha);
    cur[c] = _mm256_add_ps(cur[c], pull);
    tails[c] = _mm256_sub_ps(tails[c], pull);
  }
  const __m256i count = _mm256_load_si256(reinterpret_cast<const __m256i*>(b.count));
  const __m256i key = _mm256_load_si256(reinterpret_cast<const __m256i*>(b.key));
  const __m256i n = _mm256_set1_epi32(static_cast<int>(p.n));
  const __m256 four = _mm256_set1_ps(4.f);
  const float* const table = p.gradient->repulsionTable();
  int most = 0;
  for (int l = 0; l < kLanes; ++l)
  {
    most = std::max(most, b.count[l]);
  }
  // The draws first, kChunk at a time (they do not depend on the positions): the loop
  // below then starts every load without waiting for the hash (one chain of ~25 cycles).
  constexpr int kChunk = 16;
  alignas(32) std::uint32_t vertexAt[kChunk][kLanes];
  __m256i use[kChunk];
  __m256i draw = key;
  for (int q0 = 0; q0 < most; q0 += kChunk)
  {
    const int q1 = std::min(most, q0 + kChunk);
    for (int q = q0; q < q1; ++q)
    {
      const __m256i r = hash8(draw);
      draw = _mm256_add_epi32(draw, _mm256_set1_epi32(static_cast<int>(kDrawStep)));
      // (r n) >> 32 per lane: the even lanes' products shifted down, the odd lanes' high words.
      const __m256i even = _mm256_srli_epi64(_mm256_mul_epu32(r, n), 32);
      const __m256i odd = _mm256_mul_epu32(_mm256_srli_epi64(r, 32), n);
      const __m256i v = _mm256_blend_epi32(even, odd, 0xAA);
      use[q - q0] = _mm256_andnot_si256(_mm256_cmpeq_epi32(v, head), _mm256_cmpgt_epi32(count, _mm256_set1_epi32(q)));
      _mm256_store_si256(reinterpret_cast<__m256i*>(vertexAt[q - q0]), _mm256_slli_epi32(v, 4));
    }
    for (int q = q0; q < q1; ++q)
    {
      __m256 away[Dim];
      loadRows8<Dim>(start, vertexAt[q - q0], away);
      for (int c = 0; c < Dim; ++c)
      {
        away[c] = _mm256_sub_ps(cur[c], away[c]);
      }
      __m256 d = _mm256_add_ps(_mm256_mul_ps(away[0], away[0]), _mm256_mul_ps(away[1], away[1]));
      if (Dim == 3)
      {
        d = _mm256_add_ps(d, _mm256_mul_ps(away[Dim - 1], away[Dim - 1]));
      }
      const __m256 rep = lookup8(table, d);
      const __m256 apart = _mm256_cmp_ps(d, zero, _CMP_GT_OQ);
      for (int c = 0; c < Dim; ++c)
      {
        const __m256 force = _mm256_blendv_ps(four, clip8(_mm256_mul_ps(rep, away[c])), apart);
        push[c] = _mm256_blendv_ps(push[c], _mm256_add_ps(push[c], force), _mm256_castsi256_ps(use[q - q0]));
      }
    }
  }
  __m256 heads[Dim];
  for (int c = 0; c < Dim; ++c)
  {
    heads[c] = _mm256_add_ps(cur[c], _mm256_mul_ps(push[c], alpha));
  }
  // Padding lanes repeat lane 0's vertices: lane 0 is stored last. A padding lane's tail is
  // lane 0's (same inputs, same pull); its head, without negative samples, is overwritten.
  storeRows8<Dim>(Y, tailAt, tails);
  storeRows8<Dim>(Y, headAt, heads);
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

// Per thread: the batch each vertex last joined (batches are numbered per thread).
struct BatchMarks
{
  std::vector<std::uint32_t> mark;
  std::uint32_t current = 0;
  // Before a task of `edges` due edges (each starts at most one batch).
  void reset(std::size_t n, std::size_t edges)
  {
    if (mark.size() != n || current >= std::numeric_limits<std::uint32_t>::max() - edges - 1)
    {
      mark.assign(n, 0);
      current = 0;
    }
  }
};

// One task's edges in one epoch: umap-learn's _optimize_layout_euclidean_single_epoch.
// Y, start (the epoch's snapshot): kStride floats per slot.
template <int Dim>
void runTask(Schedule& s, int task, const Step& p, float* Y, const float* start)
{
  thread_local std::vector<std::uint32_t> due;
  const double epoch = p.epoch;
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
  // The schedule (make_epochs_per_sample, umap-learn's bookkeeping of negative samples)
  // moves on before the positions, which it does not depend on.
  const auto advance = [&](std::size_t i) {
    const int negatives = static_cast<int>((epoch - s.nextNegative[i]) / s.epochsPerNegative[i]);
    s.nextSample[i] += s.epochsPerSample[i];
    s.nextNegative[i] += negatives * s.epochsPerNegative[i];
    return negatives;
  };
#ifdef MCV_UMAP_AVX2
  if (p.batched)
  {
    thread_local BatchMarks marks;
    marks.reset(p.n, m);
    Batch b;
    ++marks.current;
    const auto run = [&]() { // lanes beyond b.lanes: lane 0's vertices, no negative samples
      for (int l = b.lanes; l < kLanes; ++l)
      {
        b.head[l] = b.head[0];
        b.tail[l] = b.tail[0];
        b.key[l] = 0;
        b.count[l] = 0;
      }
      batchAvx2<Dim>(b, p, Y, start);
      b.lanes = 0;
      ++marks.current;
    };
    for (std::size_t r = 0; r < m; ++r)
    {
      const std::size_t i = due[r];
      const std::uint32_t j = s.head[i], k = s.tail[i];
      if (marks.mark[j] == marks.current || marks.mark[k] == marks.current) // shares a vertex: run the batch first
      {
        run();
      }
      marks.mark[j] = marks.mark[k] = marks.current;
      const int l = b.lanes++;
      b.head[l] = j;
      b.tail[l] = k;
      b.key[l] = sampleKey(p.epochKey, i);
      b.count[l] = advance(i);
      if (b.lanes == kLanes)
      {
        run();
      }
    }
    if (b.lanes > 0)
    {
      run();
    }
    return;
  }
#endif
  for (std::size_t r = 0; r < m; ++r)
  {
    const std::size_t i = due[r];
    const std::uint32_t key = sampleKey(p.epochKey, i);
    const int negatives = advance(i);
    sampleScalar<Dim>(s.head[i], s.tail[i], negatives, key, p, Y, start);
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
  const GradientTable gradient(o.a, o.b, o.gamma);
  // The eight-lane step addresses rows by 32-bit byte offsets (slot << 4).
  const bool batched = o.vectorised && hasAvx2() && n < (std::size_t(1) << 28);
  float* const y = slots.data();
  float* const snapshot = start.data();
  // The positions this epoch's negative samples read.
  const auto takeSnapshot = [&]() { std::copy(y, y + n * kStride, snapshot); };
  // The threads take the epoch's tasks in order (round by round) from a shared counter; a
  // task waits only for its two blocks to finish the round before (every block is in one
  // task per round), and the epochs are separated by one barrier (the snapshot). Both waits
  // spin with a yield: on a loaded machine the thread being waited for may need this core.
  std::array<std::atomic<long>, kLayoutBlocks> rounds{}; // rounds each block has finished
  std::atomic<int> nextTask{ 0 };
  EpochBarrier barrier;
  // umap-learn: epoch 0 at the initial rate, epoch e > 0 at alpha (1 - (e - 1) / epochs).
  const auto step = [&](int epoch) {
    const std::uint64_t epochKey = mix64(mix64(o.seed) ^ static_cast<std::uint64_t>(epoch));
    return Step{ static_cast<float>(o.initialAlpha * (epoch == 0 ? 1.0 : 1.0 - double(epoch - 1) / o.epochs)), epoch,
      static_cast<std::uint32_t>(n), static_cast<std::uint32_t>(epochKey), &gradient, batched };
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
        takeSnapshot();
        const Step p = step(epoch);
        for (int task = 0; task < kTasks; ++task)
        {
          runTask<Dim>(s, task, p, y, snapshot);
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
            takeSnapshot();
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
            runTask<Dim>(s, task, p, y, snapshot);
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

bool layoutIsVectorised()
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
