// Trustworthiness of an embedding (Venna & Kaski 2001), as scikit-learn computes it:
//   T(k) = 1 - 2 / (n k (2n - 3k - 1)) * sum_i sum_{j in U_k(i)} (r(i, j) - k),
// U_k(i): the k nearest neighbours of i in the embedding that are not among its k nearest
// in the original space; r(i, j): the rank of j among i's neighbours in the original space.
// Exact, O(n^2) time, O(n) memory per thread: meant for a sample of a few thousand points.
#pragma once

#include <cstddef>

namespace mcv
{

// X: n x D, Y: n x d, both row-major float. k must be < n / 2; returns NaN otherwise.
double trustworthiness(const float* X, int D, const float* Y, int d, std::size_t n, int k);

} // namespace mcv
