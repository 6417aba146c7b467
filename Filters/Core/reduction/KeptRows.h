// Which rows of a block (x fastest) go to an output that holds only a box of it
// (ReductionOptions::outputLo/outputHi): a split run's piece without its ghost layers. The
// placement writes each chunk of rows through it, so the coordinates are never held for
// the whole block and cropped afterwards.
#pragma once

#include <algorithm>
#include <array>
#include <cstddef>

namespace mcv
{

class KeptRows
{
public:
  // Every row of `rows`, in place.
  explicit KeptRows(std::size_t rows)
    : rows_(rows)
  {
  }
  // The box [lo, hi] (inclusive, block indices) of a block of `dims` voxels; an empty box
  // (hi < lo on any axis) keeps every row.
  KeptRows(const std::array<int, 3>& dims, const std::array<int, 3>& lo, const std::array<int, 3>& hi)
    : dims_(dims)
    , lo_(lo)
    , hi_(hi)
  {
    bool unset = false;
    rows_ = 1;
    std::size_t blockRows = 1;
    for (int a = 0; a < 3; ++a)
    {
      unset = unset || hi[a] < lo[a];
      all_ = all_ && lo[a] == 0 && hi[a] == dims[a] - 1;
      rows_ *= hi[a] >= lo[a] ? static_cast<std::size_t>(hi[a] - lo[a] + 1) : 0;
      blockRows *= static_cast<std::size_t>(std::max(0, dims[a]));
    }
    all_ = all_ || unset;
    if (all_)
    {
      rows_ = blockRows;
    }
  }

  // Every row is kept, at its own index.
  bool all() const { return all_; }
  // Rows of the output.
  std::size_t rows() const { return rows_; }

  // keep(from, to, n) for each run of n consecutive kept rows among the block's rows
  // [begin, begin + count): block rows from.., output rows to...
  template <class Keep>
  void runs(std::size_t begin, std::size_t count, Keep&& keep) const
  {
    if (count == 0)
    {
      return;
    }
    if (all_)
    {
      keep(begin, begin, count);
      return;
    }
    const std::size_t nx = static_cast<std::size_t>(dims_[0]), ny = static_cast<std::size_t>(dims_[1]);
    const std::size_t bx = static_cast<std::size_t>(hi_[0] - lo_[0] + 1);
    const std::size_t by = static_cast<std::size_t>(hi_[1] - lo_[1] + 1);
    const std::size_t end = begin + count;
    for (std::size_t line = begin / nx; line * nx < end; ++line)
    {
      const int j = static_cast<int>(line % ny), k = static_cast<int>(line / ny);
      if (j < lo_[1] || j > hi_[1] || k < lo_[2] || k > hi_[2])
      {
        continue;
      }
      const std::size_t first = std::max(begin, line * nx + static_cast<std::size_t>(lo_[0]));
      const std::size_t last = std::min(end, line * nx + static_cast<std::size_t>(hi_[0]) + 1);
      if (first < last)
      {
        const std::size_t i = first - line * nx - static_cast<std::size_t>(lo_[0]);
        const std::size_t to = (static_cast<std::size_t>(k - lo_[2]) * by + static_cast<std::size_t>(j - lo_[1])) * bx + i;
        keep(first, to, last - first);
      }
    }
  }

private:
  std::array<int, 3> dims_{ 0, 0, 0 }, lo_{ 0, 0, 0 }, hi_{ -1, -1, -1 };
  std::size_t rows_ = 0;
  bool all_ = true;
};

} // namespace mcv
