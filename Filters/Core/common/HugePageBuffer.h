// Storage for one large dense matrix, backed by transparent huge pages where the system
// allows it (Linux madvise(MADV_HUGEPAGE); THP in "always" or "madvise" mode).
//
// Why: the landmark pencil's 500 x 500 matrix is fresh memory on every fit, and its 512
// page faults of 4 KB cost several times what one 2 MB page costs, a noticeable share of
// an LLE fit of 2000 points. Buffers under 1 MB are plain allocations (a huge page would
// mostly be waste).
#pragma once

#include <cstddef>
#include <memory>

namespace mcv
{

class HugePageBuffer
{
public:
  explicit HugePageBuffer(std::size_t doubles); // contents undefined; throws std::bad_alloc
  double* data() { return data_.get(); }

private:
  struct Free
  {
    void operator()(double* p) const;
  };
  std::unique_ptr<double, Free> data_;
};

} // namespace mcv
