// The reference sample the embedding is fitted on (dissertation section 5.4.2): M rows of
// the feature matrix, seeded, with distinct feature vectors.
//
// Scheme (norm-stratified, so rare bright structures are kept):
//  - every row gets the Euclidean norm of its (used, centred) feature vector;
//  - half of the sample is drawn uniformly at random from all rows (keeps the density:
//    what is common in the volume is common in the domain);
//  - the other half is shared equally among 8 strata of the norm whose upper quantile
//    edges halve towards the top: [0, .5), [.5, .75), [.75, .875), ... , [.9921875, 1].
//    The top 0.8 % of voxels by norm (the bright, high-gradient ones a user looks for)
//    thus get 1/16 of the sample instead of 0.8 % of it.
//  - exact duplicates (many background voxels share one feature vector) are drawn once:
//    a duplicate adds nothing to the fit and would break kNN graphs (zero distances).
// When fewer distinct vectors exist than asked for, all of them are returned.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

namespace mcv
{

struct ReferenceSampleOptions
{
  std::size_t size = 10000;
  std::uint64_t seed = 0;
  int strata = 8;
  double stratifiedFraction = 0.5; // of the sample shared equally among the strata
};

// `data` is n x dim row-major; `columns` the columns used (empty: all), `center` their mean
// (empty: no centring). Returns sorted row indices of distinct feature vectors.
// When size >= n every distinct row is returned.
std::vector<std::int64_t> drawReferenceSample(const float* data, std::size_t n, int dim,
  const std::vector<int>& columns, const std::vector<double>& center, const ReferenceSampleOptions& options);

// Seeded uniform integer in [0, n): portable (std::uniform_int_distribution is not the same
// on every standard library, and "same seed, same result" should hold across builds).
std::uint64_t uniformIndex(std::uint64_t& state, std::uint64_t n);

} // namespace mcv
