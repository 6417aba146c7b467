// What the out-of-sample tests (CPU and GPU) and the UMAP layout tests place and compare:
// random matrices, lattice points (many exactly equal distances), and the reference sample
// the reduction draws from the real brain's features.
// Header-only.
#pragma once

#include "BrainFeatures.h"
#include "Embedding.h" // RowMatrixF
#include "ReferenceSample.h"

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <numeric>
#include <random>
#include <vector>

namespace mcv
{
namespace testing
{

// rows x cols values of the standard normal distribution, drawn from `rng` in row order.
inline RowMatrixF randomMatrix(std::size_t rows, int cols, std::mt19937& rng)
{
  std::normal_distribution<float> g(0.f, 1.f);
  RowMatrixF m(static_cast<Eigen::Index>(rows), cols);
  for (Eigen::Index i = 0; i < m.size(); ++i)
  {
    m.data()[i] = g(rng);
  }
  return m;
}

// An out-of-sample case with many exactly equal distances, in 6 dimensions: as references,
// `references` distinct points of the lattice {0, ..., side - 1}^6 (all its points in an
// order shuffled by the generator, the first ones; point p has the base-`side` digits of p
// as coordinates, lowest first), random 2D targets (randomMatrix), and `queries` rows on the
// half-integer lattice (k / 2 for k uniform in [0, steps]); one generator seeded with
// `seed` draws them in that order.
struct LatticeTies
{
  RowMatrixF refX;
  RowMatrixF refY;
  std::vector<float> rows;
};

inline LatticeTies latticeTies(int side, int references, std::size_t queries, int steps, unsigned seed)
{
  constexpr int dim = 6;
  std::mt19937 rng(seed);
  int points = 1;
  for (int c = 0; c < dim; ++c)
  {
    points *= side;
  }
  std::vector<int> order(static_cast<std::size_t>(points));
  std::iota(order.begin(), order.end(), 0);
  std::shuffle(order.begin(), order.end(), rng);
  LatticeTies t;
  t.refX.resize(references, dim);
  for (int r = 0; r < references; ++r)
  {
    int x = order[static_cast<std::size_t>(r)];
    for (int c = 0; c < dim; ++c, x /= side)
    {
      t.refX(r, c) = static_cast<float>(x % side);
    }
  }
  t.refY = randomMatrix(static_cast<std::size_t>(references), 2, rng);
  std::uniform_int_distribution<int> k(0, steps);
  t.rows.resize(queries * dim);
  for (float& x : t.rows)
  {
    x = static_cast<float>(k(rng)) * 0.5f;
  }
  return t;
}

// The reference sample of (at most) `size` rows that the reduction draws from the features
// `f` (drawReferenceSample with its default options), as the matrix of those rows.
inline RowMatrixF referenceSampleRows(const BrainFeatureMatrix& f, std::size_t size)
{
  ReferenceSampleOptions so;
  so.size = size;
  const std::vector<std::int64_t> rows =
    drawReferenceSample(f.values.data(), f.rows, f.cols, {}, {}, so);
  RowMatrixF X(static_cast<Eigen::Index>(rows.size()), f.cols);
  for (std::size_t r = 0; r < rows.size(); ++r)
  {
    const auto first = f.values.begin() + rows[r] * f.cols;
    std::copy(first, first + f.cols, X.row(static_cast<Eigen::Index>(r)).data());
  }
  return X;
}

} // namespace testing
} // namespace mcv
