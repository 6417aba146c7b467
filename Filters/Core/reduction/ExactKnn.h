// Exact k nearest reference vectors under ONE rule shared by every backend (kd-tree, tiled
// brute force, the CUDA kernel), so they all pick the same neighbours:
//
//   d2(q, r) = sum over c = 0..D-1, in that order, of (double(q_c) - double(r_c))^2,
//              in double, each product and sum rounded on its own (no FMA contraction);
//   neighbours ordered by (d2, index).
//
// Backends find candidates fast in float: the kp = k + kKnnCandidateMargin smallest float
// distances. The rule is then applied to those candidates and checked with a rigorous
// bound: a float squared distance is within a relative floatDistanceMargin(D) of d2 (any
// summation order, with or without FMA), so when the kp-th float distance exceeds the
// k-th candidate's d2 by that margin no other reference can be nearer. Where the check
// fails (exact or near ties, e.g. quantised label features) the row is solved again by a
// radius scan of every reference, so the answer is exact in every case.
#pragma once

#include "FeatureKnn.h"
#include "TiledKnn.h"

#include <cstddef>
#include <cstdint>
#include <limits>
#include <memory>

namespace mcv
{

enum class KnnMethod
{
  Auto = 0,      // by dimension and reference count (chooseKnnMethod)
  KdTree = 1,    // nanoflann
  BruteForce = 2 // TiledKnn
};

const char* knnMethodName(KnnMethod method);

// Extra float candidates kept beyond k.
constexpr int kKnnCandidateMargin = 5;
// At most this many float candidates per row: a k above kMaxKnnCandidates - the margin is
// still answered exactly, but every row then takes the radius scan (a full sort).
constexpr int kMaxKnnCandidates = 64;
// Rows per query() call that the callers use: the brute force sweeps the references once
// per block, and a block's candidate lists stay small.
constexpr std::size_t kKnnQueryBlock = 256;

// The backend Auto picks for a dimension and a number of references: kd-tree below the
// dimension crossover unless the references are few, brute force otherwise, while k
// neighbours fit its candidate lists (beyond, every row would take a radius scan).
KnnMethod chooseKnnMethod(int dimension, int k = 1, std::size_t references = std::numeric_limits<std::size_t>::max());

// The canonical squared distance (see above).
double canonicalSquaredDistance(const float* a, const float* b, int dimension);

// Relative margin that covers the rounding of a float squared distance in `dimension`
// dimensions (4 (D + 4) 2^-24: four times the gamma_(D+4) bound, which also covers the
// kd-tree's float bounding-box pruning).
double floatDistanceMargin(int dimension);

class ExactKnn
{
public:
  // refs: M x D row-major; must outlive the index (the brute force keeps its own copy).
  ExactKnn(const float* refs, std::size_t M, int D, KnnMethod method = KnnMethod::Auto);
  ~ExactKnn();
  ExactKnn(const ExactKnn&) = delete;
  ExactKnn& operator=(const ExactKnn&) = delete;

  KnnMethod method() const { return method_; }
  std::size_t size() const { return M_; }

  // For `count` queries (row-major, D floats each) the k (<= M) nearest references by the
  // canonical rule: idx[q*k + j], d2[q*k + j]. Returns how many rows needed the radius
  // fallback. Thread-safe; call it on blocks of a few hundred rows (the brute force sweeps
  // the references once per block).
  std::size_t query(const float* queries, std::size_t count, int k, std::uint32_t* idx, double* d2) const;

private:
  const float* refs_;
  std::size_t M_;
  int D_;
  KnnMethod method_;
  std::unique_ptr<KnnIndex> tree_;
  std::unique_ptr<TiledKnn> tiled_;
};

// Applies the rule to one row's float candidates (kp of them, ordered by (f, index), as
// TiledKnn::candidates or a kd-tree gives them): writes the k nearest and returns true
// when the bound proves them exact; false when the row needs a radius scan.
bool resolveCandidates(const float* query, const float* refs, std::size_t M, int D, const std::uint32_t* cIdx,
  const float* cF, int kp, int k, std::uint32_t* idx, double* d2);

} // namespace mcv
