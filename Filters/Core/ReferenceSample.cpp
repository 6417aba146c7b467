#include "ReferenceSample.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <unordered_map>

namespace mcv
{

namespace
{
std::uint64_t splitmix64(std::uint64_t& state)
{
  std::uint64_t z = (state += 0x9E3779B97F4A7C15ull);
  z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
  z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
  return z ^ (z >> 31);
}

// Keeps one row per distinct feature vector (over the used columns).
class DistinctRows
{
public:
  DistinctRows(const float* data, int dim, const std::vector<int>& columns)
    : data_(data)
    , dim_(dim)
    , columns_(columns)
  {
  }

  // True (and remembered) when row i's vector was not seen before.
  bool insert(std::int64_t i)
  {
    const std::uint64_t h = hash(i);
    auto it = seen_.find(h);
    if (it == seen_.end())
    {
      seen_.emplace(h, i);
      return true;
    }
    // Same hash: a duplicate unless the vectors differ (a 64-bit collision: keep the row).
    return !equal(i, it->second);
  }

private:
  float value(std::int64_t i, int c) const
  {
    const float v = data_[static_cast<std::size_t>(i) * static_cast<std::size_t>(dim_) + static_cast<std::size_t>(c)];
    return v == 0.f ? 0.f : v; // -0 and +0 are one vector
  }
  std::uint64_t hash(std::int64_t i) const
  {
    std::uint64_t h = 0x84222325CBF29CE4ull;
    for (int c : columns_)
    {
      const float v = value(i, c);
      std::uint32_t bits;
      std::memcpy(&bits, &v, sizeof bits);
      h = (h ^ bits) * 0x100000001B3ull;
      h ^= h >> 29;
    }
    return h;
  }
  bool equal(std::int64_t a, std::int64_t b) const
  {
    for (int c : columns_)
    {
      if (value(a, c) != value(b, c))
      {
        return false;
      }
    }
    return true;
  }

  const float* data_;
  int dim_;
  const std::vector<int>& columns_;
  std::unordered_map<std::uint64_t, std::int64_t> seen_;
};
} // namespace

std::uint64_t uniformIndex(std::uint64_t& state, std::uint64_t n)
{
  if (n <= 1)
  {
    return 0;
  }
  // Rejection removes the modulo bias.
  const std::uint64_t limit = ~0ull - (~0ull % n);
  std::uint64_t x;
  do
  {
    x = splitmix64(state);
  } while (x >= limit);
  return x % n;
}

std::vector<std::int64_t> drawReferenceSample(const float* data, std::size_t n, int dim,
  const std::vector<int>& columnsIn, const std::vector<double>& center, const ReferenceSampleOptions& options)
{
  std::vector<int> columns = columnsIn;
  if (columns.empty())
  {
    for (int c = 0; c < dim; ++c)
    {
      columns.push_back(c);
    }
  }
  std::vector<std::int64_t> chosen;
  DistinctRows distinct(data, dim, columns);
  if (options.size >= n)
  {
    for (std::size_t i = 0; i < n; ++i)
    {
      if (distinct.insert(static_cast<std::int64_t>(i)))
      {
        chosen.push_back(static_cast<std::int64_t>(i));
      }
    }
    return chosen;
  }

  std::uint64_t rng = options.seed ^ 0x5DEECE66Dull;
  std::vector<unsigned char> taken(n, 0);
  chosen.reserve(options.size);
  auto take = [&](std::int64_t i) {
    if (taken[static_cast<std::size_t>(i)])
    {
      return false;
    }
    taken[static_cast<std::size_t>(i)] = 1;
    if (!distinct.insert(i))
    {
      return false;
    }
    chosen.push_back(i);
    return true;
  };
  // Lazy Fisher-Yates over a pool: uniform without replacement, cost ~ rows visited.
  auto drawFrom = [&](std::vector<std::int64_t>& pool, std::size_t quota) {
    std::size_t got = 0;
    for (std::size_t p = 0; p < pool.size() && got < quota; ++p)
    {
      const std::size_t q = p + static_cast<std::size_t>(uniformIndex(rng, pool.size() - p));
      std::swap(pool[p], pool[q]);
      if (take(pool[p]))
      {
        ++got;
      }
    }
    return got;
  };

  // Norm of every (centred) feature vector.
  std::vector<float> norm(n);
  const long long count = static_cast<long long>(n);
#pragma omp parallel for schedule(static)
  for (long long ii = 0; ii < count; ++ii)
  {
    const float* row = data + static_cast<std::size_t>(ii) * static_cast<std::size_t>(dim);
    double s = 0;
    for (std::size_t k = 0; k < columns.size(); ++k)
    {
      const double v = row[columns[k]] - (center.empty() ? 0.0 : center[k]);
      s += v * v;
    }
    norm[static_cast<std::size_t>(ii)] = static_cast<float>(std::sqrt(s));
  }

  // Stratum edges at the quantiles 1/2, 3/4, 7/8, ... of the norm.
  const int S = std::max(1, options.strata);
  std::vector<float> edges;
  {
    std::vector<float> sorted = norm;
    for (int s = 1; s < S; ++s)
    {
      const double q = 1.0 - std::ldexp(1.0, -s);
      const std::size_t pos = std::min(n - 1, static_cast<std::size_t>(q * static_cast<double>(n)));
      std::nth_element(sorted.begin(), sorted.begin() + static_cast<std::ptrdiff_t>(pos), sorted.end());
      edges.push_back(sorted[pos]);
    }
  }
  std::vector<std::vector<std::int64_t>> strata(static_cast<std::size_t>(S));
  for (std::size_t i = 0; i < n; ++i)
  {
    const int s = static_cast<int>(std::upper_bound(edges.begin(), edges.end(), norm[i]) - edges.begin());
    strata[static_cast<std::size_t>(s)].push_back(static_cast<std::int64_t>(i));
  }
  norm.clear();
  norm.shrink_to_fit();

  const std::size_t stratified =
    static_cast<std::size_t>(std::llround(static_cast<double>(options.size) * options.stratifiedFraction));
  const std::size_t share = stratified / static_cast<std::size_t>(S);
  for (auto& pool : strata)
  {
    drawFrom(pool, share);
  }

  // The uniform part: rejection sampling over all rows (cheap while M << n), capped; the
  // rest (many duplicates, or M close to n) walks a shuffled list of every row.
  std::size_t attempts = 0;
  const std::size_t maxAttempts = 20 * options.size + 1000;
  while (chosen.size() < options.size && attempts < maxAttempts)
  {
    take(static_cast<std::int64_t>(uniformIndex(rng, n)));
    ++attempts;
  }
  if (chosen.size() < options.size)
  {
    std::vector<std::int64_t> all;
    all.reserve(n);
    for (std::size_t i = 0; i < n; ++i)
    {
      if (!taken[i])
      {
        all.push_back(static_cast<std::int64_t>(i));
      }
    }
    drawFrom(all, options.size - chosen.size());
  }
  std::sort(chosen.begin(), chosen.end());
  return chosen;
}

} // namespace mcv
