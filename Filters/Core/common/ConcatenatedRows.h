// Several FeatureRows as one, their rows one after another: the time steps of a series,
// each computed on its own (FeatureBricks with the same normalisation), seen by the fit of
// all steps (ReductionOptions::timeSteps) as one set of rows.
#pragma once

#include "FeatureRows.h"

#include <cstddef>
#include <memory>
#include <vector>

namespace mcv
{

class ConcatenatedRows final : public FeatureRows
{
public:
  // The parts must have the same number of columns (checked: cols() is then -1).
  explicit ConcatenatedRows(std::vector<std::unique_ptr<FeatureRows>> parts);

  std::size_t rows() const override { return rowStart_.back(); }
  int cols() const override { return cols_; }
  std::size_t blockCount() const override { return blockStart_.back(); }
  std::size_t blockBegin(std::size_t b) const override;
  const float* block(std::size_t b) override;
  // Grouped by part, so that each part gathers its rows in one call.
  void gather(const std::size_t* index, std::size_t n, float* out) override;

private:
  // The part holding global block b / row r.
  std::size_t partOfBlock(std::size_t b) const;
  std::size_t partOfRow(std::size_t r) const;

  std::vector<std::unique_ptr<FeatureRows>> parts_;
  std::vector<std::size_t> rowStart_, blockStart_; // parts + 1 entries each
  int cols_ = 0;
};

} // namespace mcv
