#include "HugePageBuffer.h"

#include <cstdlib>
#include <new>

#if defined(__linux__)
#include <sys/mman.h>
#endif

namespace mcv
{

namespace
{
constexpr std::size_t kHugePage = std::size_t(1) << 21; // 2 MiB, x86-64 and most arm64 kernels
constexpr std::size_t kHugePageMinimum = std::size_t(1) << 20;
} // namespace

void HugePageBuffer::Free::operator()(double* p) const
{
  std::free(p);
}

HugePageBuffer::HugePageBuffer(std::size_t doubles)
{
  const std::size_t bytes = doubles * sizeof(double);
  void* p = nullptr;
  if (bytes >= kHugePageMinimum)
  {
    const std::size_t rounded = (bytes + kHugePage - 1) / kHugePage * kHugePage;
    p = std::aligned_alloc(kHugePage, rounded);
#if defined(__linux__) && defined(MADV_HUGEPAGE)
    if (p)
    {
      madvise(p, rounded, MADV_HUGEPAGE); // advice only: a failure leaves 4 KB pages
    }
#endif
  }
  else
  {
    p = std::malloc(bytes > 0 ? bytes : 1);
  }
  if (!p)
  {
    throw std::bad_alloc();
  }
  data_.reset(static_cast<double*>(p));
}

} // namespace mcv
