#include "ConcatenatedRows.h"

#include <algorithm>
#include <cstring>

namespace mcv
{

ConcatenatedRows::ConcatenatedRows(std::vector<std::unique_ptr<FeatureRows>> parts)
  : parts_(std::move(parts))
{
  rowStart_.push_back(0);
  blockStart_.push_back(0);
  cols_ = parts_.empty() ? 0 : parts_.front()->cols();
  for (const std::unique_ptr<FeatureRows>& p : parts_)
  {
    rowStart_.push_back(rowStart_.back() + p->rows());
    blockStart_.push_back(blockStart_.back() + p->blockCount());
    if (p->cols() != cols_)
    {
      cols_ = -1;
    }
  }
}

std::size_t ConcatenatedRows::partOfBlock(std::size_t b) const
{
  return static_cast<std::size_t>(std::upper_bound(blockStart_.begin(), blockStart_.end(), b) - blockStart_.begin()) - 1;
}

std::size_t ConcatenatedRows::partOfRow(std::size_t r) const
{
  return static_cast<std::size_t>(std::upper_bound(rowStart_.begin(), rowStart_.end(), r) - rowStart_.begin()) - 1;
}

std::size_t ConcatenatedRows::blockBegin(std::size_t b) const
{
  if (b >= blockCount())
  {
    return rows();
  }
  const std::size_t p = partOfBlock(b);
  return rowStart_[p] + parts_[p]->blockBegin(b - blockStart_[p]);
}

const float* ConcatenatedRows::block(std::size_t b)
{
  const std::size_t p = partOfBlock(b);
  return parts_[p]->block(b - blockStart_[p]);
}

void ConcatenatedRows::gather(const std::size_t* index, std::size_t n, float* out)
{
  const std::size_t c = static_cast<std::size_t>(std::max(cols_, 0));
  std::vector<std::vector<std::size_t>> local(parts_.size()), slot(parts_.size());
  for (std::size_t i = 0; i < n; ++i)
  {
    const std::size_t p = partOfRow(index[i]);
    local[p].push_back(index[i] - rowStart_[p]);
    slot[p].push_back(i);
  }
  std::vector<float> rows;
  for (std::size_t p = 0; p < parts_.size(); ++p)
  {
    if (local[p].empty())
    {
      continue;
    }
    rows.resize(local[p].size() * c);
    parts_[p]->gather(local[p].data(), local[p].size(), rows.data());
    for (std::size_t k = 0; k < slot[p].size(); ++k)
    {
      std::memcpy(out + slot[p][k] * c, rows.data() + k * c, c * sizeof(float));
    }
  }
}

} // namespace mcv
