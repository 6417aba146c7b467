#include "StagingCopy.h"

#include <omp.h>

#include <algorithm>
#include <cstring>

namespace mcv
{
namespace cuda
{
namespace detail
{

void stagingCopy(void* dst, const void* src, std::size_t bytes)
{
  // Hand-written: a plain split of one memcpy. OpenMP's persistent threads, not a thread
  // per call: a piece copies in so little time that starting threads would be a visible
  // part of it.
  constexpr std::size_t kPerThreadMin = std::size_t(4) << 20;
  const int parts = static_cast<int>(
    std::min<std::size_t>({ 16, static_cast<std::size_t>(std::max(1, omp_get_max_threads())),
      std::max<std::size_t>(1, bytes / kPerThreadMin) }));
  if (parts == 1)
  {
    std::memcpy(dst, src, bytes);
    return;
  }
  const std::size_t step = (bytes + parts - 1) / parts;
#pragma omp parallel for num_threads(parts) schedule(static, 1)
  for (int p = 0; p < parts; ++p)
  {
    const std::size_t begin = static_cast<std::size_t>(p) * step;
    const std::size_t end = std::min(bytes, begin + step);
    if (begin < end)
    {
      std::memcpy(static_cast<char*>(dst) + begin, static_cast<const char*>(src) + begin, end - begin);
    }
  }
}

} // namespace detail
} // namespace cuda
} // namespace mcv
