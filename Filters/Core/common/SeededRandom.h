// Seeded, portable random numbers shared by the reference sample, the landmarks and the
// widget seeding. Hand-written because std::uniform_int_distribution differs between
// standard libraries, and "same seed, same result" must hold across builds.
#pragma once

#include <cstdint>

namespace mcv
{

// splitmix64's finalizer: a bijection of 64-bit words with good avalanche.
inline std::uint64_t mix64(std::uint64_t z)
{
  z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
  z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
  return z ^ (z >> 31);
}

// The next word of the splitmix64 sequence whose state is `state`.
inline std::uint64_t splitmix64(std::uint64_t& state)
{
  return mix64(state += 0x9E3779B97F4A7C15ull);
}

// Seeded uniform integer in [0, n) (rejection removes the modulo bias).
inline std::uint64_t uniformIndex(std::uint64_t& state, std::uint64_t n)
{
  if (n <= 1)
  {
    return 0;
  }
  const std::uint64_t limit = ~0ull - (~0ull % n);
  std::uint64_t x;
  do
  {
    x = splitmix64(state);
  } while (x >= limit);
  return x % n;
}

} // namespace mcv
