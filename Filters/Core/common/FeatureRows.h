// Feature vectors as the dimension reduction reads them: rows (voxels) x cols (features),
// float32, block by block. Either a matrix in memory (MatrixRows: the `Features` array of
// MultichannelFeatures), or vectors computed from the channels a block at a time and never
// stored whole (features/FeatureBricks.h: the fused path). In common/ because
// the features and the reduction meet here without including each other.
#pragma once

#include <cstddef>
#include <cstdint>
#include <cstring>
#include <functional>
#include <limits>
#include <string>
#include <vector>

namespace mcv
{

// What the placement needs to run where the rows are made (the GPU fused path): the fit's
// references and where the coordinates go. Plain pointers, so common/ needs no Eigen.
struct DevicePlacement
{
  const float* refX = nullptr; // M x D reference features (the used columns), row-major
  const float* refY = nullptr; // M x d their embedding
  std::size_t M = 0;
  int D = 0;
  int d = 0;
  const int* columns = nullptr; // D column indices into a row, or null (cols() == D)
  int neighbors = 3;
  double regularization = 1e-3;
  double distanceMargin = 0; // floatDistanceMargin(D) of ExactKnn.h
  float* out = nullptr;      // rows() x d
  // Instead of out: rows() x d binary16 values (HalfCoordinates.h), each slab's coordinates
  // rounded into it from the slab's float staging buffer.
  std::uint16_t* outHalf = nullptr;
  std::function<void(double)> progress; // fraction of the rows placed
  // Optional, rows() floats: each row's distance to the nearest reference over modelRadius
  // (reduction/ModelDistance.h), computed where the rows are placed.
  float* distance = nullptr;
  double modelRadius = 0.0;
};

struct DevicePlacementReport
{
  bool attempted = false;   // false: these rows have no device path (the caller places them)
  std::size_t rowsDone = 0; // rows [0, rowsDone) of out are placed, also after a failure
  std::string error;        // non-empty: the device failed; the caller places the rest
  std::size_t radiusScans = 0;
  std::size_t halfOverflow = 0; // values of outHalf beyond float16's range (stored as +-inf)
};

// The column check of reduceDimension computed where the rows are made (the GPU fused path):
// per column, exact integer sums per float exponent field (cols x 256, as
// DimensionReduction.cpp's addExact), the extremes, and the non-finite values with the first
// one (row x cols + column).
struct DeviceColumnSums
{
  bool attempted = false; // false: no such path (the caller walks the blocks)
  std::string error;      // non-empty: the device failed; the caller walks the blocks
  std::vector<std::int64_t> bins;
  std::vector<double> minimum, maximum;
  double nonFinite = 0;
  double firstBad = std::numeric_limits<double>::infinity();
};

// The reference sample's strata computed where the rows are made: stratum[row] = the number
// of edges <= the float norm of the row's `columns` less `center` (ReferenceSample.cpp's
// Sampler::norm), for the rows with eligible[row] != 0 (all when null), notEligible for the
// others.
struct DeviceStrata
{
  std::vector<int> columns;
  std::vector<double> center;
  std::vector<float> edges;
  const unsigned char* eligible = nullptr;
  std::uint8_t notEligible = 0xFF;
  std::uint8_t* stratum = nullptr; // rows()
  std::function<void(double)> progress;
};

struct DevicePassReport
{
  bool attempted = false;
  std::string error;
};

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
  // The out-of-sample placement of every row on the GPU where the rows are computed there
  // (FeatureBricks: features and placement per slab on the device, only channels up and
  // coordinates down). Default: no such path.
  virtual DevicePlacementReport placeOnDevice(const DevicePlacement&) { return {}; }
  // The two other passes over every row, on the device where the rows are computed there
  // (single-process volumes: every row owned). Default: no such path.
  virtual DeviceColumnSums columnSumsOnDevice(const std::function<void(double)>&) { return {}; }
  virtual DevicePassReport strataOnDevice(const DeviceStrata&) { return {}; }
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
