// Hand-written: 2.0-2.9x faster than FAISS 1.7.3 IndexFlatL2 (OpenBLAS) on the 24D brain kNN graph (k=11, N=2000-10000) and 1.7x on out-of-sample 3-NN, 2 threads; HNSW slower and inexact (docs/benchmarks.md, section 9)
// Blocked brute-force nearest-neighbour candidates in float: the fast first pass of the
// exact kNN (ExactKnn.h) in high dimension, where a kd-tree visits most of its leaves.
//
// The references are kept transposed (D x M, padded to a multiple of 16) so a register
// block of 3 queries x 16 references is a handful of vector loads, subtractions and FMAs
// per feature; L2-sized reference chunks are swept by every query block. An AVX2+FMA
// kernel is chosen at run time where the CPU has it (the library itself is built for
// baseline x86-64), a portable loop otherwise; both keep, per query, the kp smallest float
// squared distances ordered by (distance, index).
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

namespace mcv
{

class TiledKnn
{
public:
  // refs: M x D row-major (copied).
  TiledKnn(const float* refs, std::size_t M, int D);

  std::size_t size() const { return M_; }
  int dimension() const { return D_; }

  // For `count` queries (row-major, D floats each) the kp smallest float squared distances
  // and their indices, nearest first, ties by index: cIdx[q*kp + s], cF[q*kp + s]. Slots
  // beyond M (kp > M) get index UINT32_MAX and +inf. Thread-safe (read-only).
  void candidates(const float* queries, std::size_t count, int kp, std::uint32_t* cIdx, float* cF) const;

  // The float squared distance of one query to every reference (M floats).
  void distances(const float* query, float* f) const;

  // True when the AVX2+FMA kernel runs on this CPU.
  static bool vectorKernel();

private:
  std::vector<float> soa_; // D x Mpad, padding references at 1e30 (distance +inf)
  std::size_t M_ = 0, Mpad_ = 0;
  int D_ = 0;
};

} // namespace mcv
