// Sparse test matrices for LLE's eigen steps (TestLLEEigen.cpp, TestLLELandmarks.cpp).
#pragma once

#include "LLEEigen.h"

#include <algorithm>
#include <random>
#include <vector>

namespace mcvtest
{

// A = I - W, W with k random neighbours per row and positive weights summing to 1, within
// blocks of the given sizes (each block is a closed set: a null vector of A per block).
inline mcv::LLESparse randomWeights(const std::vector<int>& blocks, int k, unsigned seed)
{
  std::mt19937 rng(seed);
  std::vector<Eigen::Triplet<double, int>> t;
  int start = 0;
  for (int size : blocks)
  {
    std::uniform_int_distribution<int> pick(start, start + size - 1);
    std::uniform_real_distribution<double> weight(0.2, 1.0);
    for (int i = start; i < start + size; ++i)
    {
      t.emplace_back(i, i, 1.0);
      std::vector<int> nb;
      std::vector<double> w;
      while (static_cast<int>(nb.size()) < k)
      {
        const int j = pick(rng);
        if (j != i && std::find(nb.begin(), nb.end(), j) == nb.end())
        {
          nb.push_back(j);
          w.push_back(weight(rng));
        }
      }
      double s = 0;
      for (double v : w)
      {
        s += v;
      }
      for (int a = 0; a < k; ++a)
      {
        t.emplace_back(i, nb[a], -w[a] / s);
      }
    }
    start += size;
  }
  mcv::LLESparse A(start, start);
  A.setFromTriplets(t.begin(), t.end());
  return A;
}

} // namespace mcvtest
