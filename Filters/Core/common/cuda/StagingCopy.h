// Host-side copy of a piece of the caller's volume into pinned staging memory, on several
// threads: one core's memcpy is slower than the PCIe upload it feeds.
#pragma once

#include <cstddef>

namespace mcv
{
namespace cuda
{
namespace detail
{

// memcpy(dst, src, bytes) split over up to 16 OpenMP threads (one thread below 4 MiB).
void stagingCopy(void* dst, const void* src, std::size_t bytes);

} // namespace detail
} // namespace cuda
} // namespace mcv
