// What the CPU benchmarks report beside their times: the median of repeated runs and how
// busy the machine was (a ratio measured on a loaded machine is read differently).
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <vector>

namespace mcv
{
namespace testing
{

// The median of `v`; NaN when it is empty.
inline double median(std::vector<double> v)
{
  if (v.empty())
  {
    return NAN;
  }
  std::sort(v.begin(), v.end());
  const std::size_t n = v.size();
  return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

// The 1-minute load average (Linux /proc/loadavg); -1 when unknown.
inline double loadAverage()
{
  double l = -1;
  if (FILE* f = std::fopen("/proc/loadavg", "r"))
  {
    if (std::fscanf(f, "%lf", &l) != 1)
    {
      l = -1;
    }
    std::fclose(f);
  }
  return l;
}

} // namespace testing
} // namespace mcv
