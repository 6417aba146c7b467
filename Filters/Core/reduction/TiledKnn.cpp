#include "TiledKnn.h"

#include <algorithm>
#include <cstring>
#include <limits>

#if defined(__x86_64__) && (defined(__GNUC__) || defined(__clang__))
#define MCV_TILED_AVX2 1
#include <immintrin.h>
#endif

namespace mcv
{

namespace
{
// Queries per register block: 3 x 2 accumulators, the references, the broadcast query
// feature and a difference fit the 16 AVX registers; with 4 GCC kept one accumulator on the
// stack, a store and reload on every FMA's dependency chain (the 24D sweep ran 1.3x slower).
constexpr int kQB = 3;
constexpr std::size_t kRB = 16;        // references per register block (two AVX vectors)
constexpr std::size_t kChunk = 2048;   // references per cache chunk (24D: 192 KiB, fits L2)
constexpr float kPad = 1e30f;          // padding references: distance overflows to +inf

// v < f[kp-1] on entry. References arrive in increasing index order, so an equal distance
// stays behind the earlier (smaller) index: the list is ordered by (distance, index).
inline void insert(float* f, std::uint32_t* id, int kp, float v, std::uint32_t j)
{
  int p = kp - 1;
  while (p > 0 && f[p - 1] > v)
  {
    f[p] = f[p - 1];
    id[p] = id[p - 1];
    --p;
  }
  f[p] = v;
  id[p] = j;
}

void candidatesGeneric(const float* soa, std::size_t Mpad, int D, const float* queries, std::size_t count, int kp,
  std::uint32_t* cIdx, float* cF)
{
  for (std::size_t c0 = 0; c0 < Mpad; c0 += kChunk)
  {
    const std::size_t c1 = std::min(Mpad, c0 + kChunk);
    for (std::size_t q0 = 0; q0 < count; q0 += kQB)
    {
      const int nq = static_cast<int>(std::min<std::size_t>(kQB, count - q0));
      for (std::size_t base = c0; base < c1; base += kRB)
      {
        float acc[kQB][kRB] = {};
        for (int c = 0; c < D; ++c)
        {
          const float* r = soa + static_cast<std::size_t>(c) * Mpad + base;
          for (int qq = 0; qq < nq; ++qq)
          {
            const float qc = queries[(q0 + qq) * static_cast<std::size_t>(D) + c];
            for (std::size_t j = 0; j < kRB; ++j)
            {
              const float t = r[j] - qc;
              acc[qq][j] += t * t;
            }
          }
        }
        for (int qq = 0; qq < nq; ++qq)
        {
          float* f = cF + (q0 + qq) * static_cast<std::size_t>(kp);
          std::uint32_t* id = cIdx + (q0 + qq) * static_cast<std::size_t>(kp);
          for (std::size_t j = 0; j < kRB; ++j)
          {
            if (acc[qq][j] < f[kp - 1])
            {
              insert(f, id, kp, acc[qq][j], static_cast<std::uint32_t>(base + j));
            }
          }
        }
      }
    }
  }
}

#ifdef MCV_TILED_AVX2
// The same sweep with kQB x 16 accumulators in registers; a compare + movemask per vector
// skips the (rare, once the lists are full) insertions.
__attribute__((target("avx2,fma"))) void candidatesAvx2(const float* soa, std::size_t Mpad, int D,
  const float* queries, std::size_t count, int kp, std::uint32_t* cIdx, float* cF)
{
  for (std::size_t c0 = 0; c0 < Mpad; c0 += kChunk)
  {
    const std::size_t c1 = std::min(Mpad, c0 + kChunk);
    for (std::size_t q0 = 0; q0 < count; q0 += kQB)
    {
      const int nq = static_cast<int>(std::min<std::size_t>(kQB, count - q0));
      const float* qp[kQB];
      for (int qq = 0; qq < kQB; ++qq)
      {
        // A short last block repeats its last query; its results are not used.
        qp[qq] = queries + (q0 + static_cast<std::size_t>(std::min(qq, nq - 1))) * static_cast<std::size_t>(D);
      }
      for (std::size_t base = c0; base < c1; base += kRB)
      {
        __m256 a[kQB][2];
        for (int qq = 0; qq < kQB; ++qq)
        {
          a[qq][0] = _mm256_setzero_ps();
          a[qq][1] = _mm256_setzero_ps();
        }
        const float* r = soa + base;
        for (int c = 0; c < D; ++c, r += Mpad)
        {
          const __m256 r0 = _mm256_loadu_ps(r);
          const __m256 r1 = _mm256_loadu_ps(r + 8);
          for (int qq = 0; qq < kQB; ++qq)
          {
            const __m256 b = _mm256_broadcast_ss(qp[qq] + c);
            const __m256 d0 = _mm256_sub_ps(r0, b);
            const __m256 d1 = _mm256_sub_ps(r1, b);
            a[qq][0] = _mm256_fmadd_ps(d0, d0, a[qq][0]);
            a[qq][1] = _mm256_fmadd_ps(d1, d1, a[qq][1]);
          }
        }
        // The sums leave the registers here, once: indexed by the run-time qq below, the
        // accumulators themselves were kept in memory by GCC, two stores per FMA pair in
        // the loop above (the kernel ran ~2x slower).
        alignas(32) float sums[kQB][kRB];
        for (int qq = 0; qq < kQB; ++qq)
        {
          _mm256_store_ps(sums[qq], a[qq][0]);
          _mm256_store_ps(sums[qq] + 8, a[qq][1]);
        }
        for (int qq = 0; qq < nq; ++qq)
        {
          float* f = cF + (q0 + qq) * static_cast<std::size_t>(kp);
          std::uint32_t* id = cIdx + (q0 + qq) * static_cast<std::size_t>(kp);
          const __m256 thr = _mm256_set1_ps(f[kp - 1]);
          const float* const t = sums[qq];
          unsigned mask = static_cast<unsigned>(_mm256_movemask_ps(_mm256_cmp_ps(_mm256_load_ps(t), thr, _CMP_LT_OQ))) |
            (static_cast<unsigned>(_mm256_movemask_ps(_mm256_cmp_ps(_mm256_load_ps(t + 8), thr, _CMP_LT_OQ))) << 8);
          if (mask == 0)
          {
            continue;
          }
          while (mask != 0)
          {
            const int j = __builtin_ctz(mask);
            mask &= mask - 1;
            if (t[j] < f[kp - 1]) // the threshold tightens as we insert
            {
              insert(f, id, kp, t[j], static_cast<std::uint32_t>(base + static_cast<std::size_t>(j)));
            }
          }
        }
      }
    }
  }
}
#endif
} // namespace

TiledKnn::TiledKnn(const float* refs, std::size_t M, int D)
  : M_(M)
  , Mpad_((M + kRB - 1) / kRB * kRB)
  , D_(D)
{
  soa_.assign(static_cast<std::size_t>(D) * Mpad_, kPad);
  for (std::size_t i = 0; i < M; ++i)
  {
    for (int c = 0; c < D; ++c)
    {
      soa_[static_cast<std::size_t>(c) * Mpad_ + i] = refs[i * static_cast<std::size_t>(D) + c];
    }
  }
}

bool TiledKnn::vectorKernel()
{
#ifdef MCV_TILED_AVX2
  static const bool ok = __builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma");
  return ok;
#else
  return false;
#endif
}

void TiledKnn::candidates(const float* queries, std::size_t count, int kp, std::uint32_t* cIdx, float* cF) const
{
  std::fill(cF, cF + count * static_cast<std::size_t>(kp), std::numeric_limits<float>::infinity());
  std::fill(cIdx, cIdx + count * static_cast<std::size_t>(kp), std::numeric_limits<std::uint32_t>::max());
  if (count == 0 || kp <= 0 || M_ == 0)
  {
    return;
  }
#ifdef MCV_TILED_AVX2
  if (vectorKernel())
  {
    candidatesAvx2(soa_.data(), Mpad_, D_, queries, count, kp, cIdx, cF);
    return;
  }
#endif
  candidatesGeneric(soa_.data(), Mpad_, D_, queries, count, kp, cIdx, cF);
}

void TiledKnn::distances(const float* query, float* f) const
{
  std::fill(f, f + M_, 0.f);
  for (int c = 0; c < D_; ++c)
  {
    const float qc = query[c];
    const float* r = soa_.data() + static_cast<std::size_t>(c) * Mpad_;
    for (std::size_t j = 0; j < M_; ++j)
    {
      const float t = r[j] - qc;
      f[j] += t * t;
    }
  }
}

} // namespace mcv
