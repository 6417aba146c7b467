// Feature vectors as the dimension reduction reads them: rows (voxels) x cols (features),
// float32, block by block. Either a matrix in memory (MatrixRows: the `Features` array of
// MultichannelFeatures), or vectors computed from the channels a block at a time and never
// stored whole (features/FeatureBricks.h: the fused path of issue 20). In common/ because
// the features and the reduction meet here without including each other.
#pragma once

#include <cstddef>
#include <cstring>

namespace mcv
{

class FeatureRows
{
public:
  virtual ~FeatureRows() = default;
  virtual std::size_t rows() const = 0;
  virtual int cols() const = 0;

  // Consecutive blocks of rows, in order, that cover [0, rows()): block b is the rows
  // [blockBegin(b), blockBegin(b + 1)), blockBegin(blockCount()) == rows().
  virtual std::size_t blockCount() const = 0;
  virtual std::size_t blockBegin(std::size_t b) const = 0;
  // Block b's rows, row-major; valid until the next call of block() (not thread-safe: one
  // caller walks the blocks, OpenMP runs inside).
  virtual const float* block(std::size_t b) = 0;
  // The rows of `index` (any order, repeats allowed) into out (n x cols()).
  virtual void gather(const std::size_t* index, std::size_t n, float* out) = 0;
};

// A matrix in memory: one block, gathered by copying rows.
class MatrixRows final : public FeatureRows
{
public:
  MatrixRows(const float* data, std::size_t rows, int cols)
    : data_(data)
    , rows_(rows)
    , cols_(cols)
  {
  }
  std::size_t rows() const override { return rows_; }
  int cols() const override { return cols_; }
  std::size_t blockCount() const override { return 1; }
  std::size_t blockBegin(std::size_t b) const override { return b == 0 ? 0 : rows_; }
  const float* block(std::size_t) override { return data_; }
  void gather(const std::size_t* index, std::size_t n, float* out) override
  {
    const std::size_t c = static_cast<std::size_t>(cols_);
    for (std::size_t i = 0; i < n; ++i)
    {
      std::memcpy(out + i * c, data_ + index[i] * c, c * sizeof(float));
    }
  }

private:
  const float* data_;
  std::size_t rows_;
  int cols_;
};

} // namespace mcv
