// ConcatenatedRows: several row sets read as one equal the matrix of all their rows stacked
// (blocks in order, gathers in any order with repeats), and a fit over time steps on them
// equals the fit of that stacked matrix.
#include "ConcatenatedRows.h"
#include "DimensionReduction.h"

#include <gtest/gtest.h>

#include <memory>
#include <random>
#include <vector>

namespace
{
// A MatrixRows split into blocks of `blockRows`, so the concatenation has several per part.
class BlockedRows final : public mcv::FeatureRows
{
public:
  BlockedRows(std::vector<float> data, int cols, std::size_t blockRows)
    : data_(std::move(data))
    , cols_(cols)
    , blockRows_(blockRows)
  {
  }
  std::size_t rows() const override { return data_.size() / static_cast<std::size_t>(cols_); }
  int cols() const override { return cols_; }
  std::size_t blockCount() const override { return (rows() + blockRows_ - 1) / blockRows_; }
  std::size_t blockBegin(std::size_t b) const override { return std::min(rows(), b * blockRows_); }
  const float* block(std::size_t b) override { return data_.data() + b * blockRows_ * cols_; }
  void gather(const std::size_t* index, std::size_t n, float* out) override
  {
    for (std::size_t i = 0; i < n; ++i)
    {
      std::copy_n(data_.data() + index[i] * cols_, cols_, out + i * cols_);
    }
  }

private:
  std::vector<float> data_;
  int cols_;
  std::size_t blockRows_;
};

std::vector<float> randomRows(std::size_t rows, int cols, unsigned seed)
{
  std::mt19937 random(seed);
  std::normal_distribution<float> normal;
  std::vector<float> data(rows * static_cast<std::size_t>(cols));
  for (float& v : data)
  {
    v = normal(random);
  }
  return data;
}
} // namespace

TEST(ConcatenatedRows, ReadsAsTheStackedMatrix)
{
  const int cols = 4;
  const std::vector<std::size_t> sizes{ 300, 1, 257 };
  std::vector<float> stacked;
  std::vector<std::unique_ptr<mcv::FeatureRows>> parts;
  for (std::size_t p = 0; p < sizes.size(); ++p)
  {
    std::vector<float> data = randomRows(sizes[p], cols, 10 + static_cast<unsigned>(p));
    stacked.insert(stacked.end(), data.begin(), data.end());
    parts.emplace_back(new BlockedRows(std::move(data), cols, 64));
  }
  mcv::ConcatenatedRows rows(std::move(parts));
  ASSERT_EQ(rows.rows(), 558u);
  ASSERT_EQ(rows.cols(), cols);
  ASSERT_EQ(rows.blockBegin(rows.blockCount()), rows.rows());
  for (std::size_t b = 0; b < rows.blockCount(); ++b)
  {
    const std::size_t begin = rows.blockBegin(b), end = rows.blockBegin(b + 1);
    ASSERT_LT(begin, end);
    const float* block = rows.block(b);
    for (std::size_t i = 0; i < (end - begin) * cols; ++i)
    {
      ASSERT_EQ(block[i], stacked[begin * cols + i]) << "block " << b;
    }
  }
  std::mt19937 random(7);
  std::vector<std::size_t> index(500);
  for (std::size_t& i : index)
  {
    i = random() % rows.rows();
  }
  std::vector<float> got(index.size() * cols);
  rows.gather(index.data(), index.size(), got.data());
  for (std::size_t k = 0; k < index.size(); ++k)
  {
    for (int c = 0; c < cols; ++c)
    {
      ASSERT_EQ(got[k * cols + c], stacked[index[k] * cols + c]) << "row " << index[k];
    }
  }
}

TEST(ConcatenatedRows, FitOverTimeStepsIsTheFitOfTheStack)
{
  const int cols = 5;
  std::vector<float> first = randomRows(2000, cols, 1), second = randomRows(2000, cols, 2);
  std::vector<float> stacked = first;
  stacked.insert(stacked.end(), second.begin(), second.end());
  std::vector<std::unique_ptr<mcv::FeatureRows>> parts;
  parts.emplace_back(new BlockedRows(first, cols, 500));
  parts.emplace_back(new BlockedRows(second, cols, 700));
  mcv::ConcatenatedRows steps(std::move(parts));
  mcv::MatrixRows whole(stacked.data(), 4000, cols);

  for (mcv::ReductionMethod method : { mcv::ReductionMethod::PCA, mcv::ReductionMethod::Isomap })
  {
    mcv::ReductionOptions options;
    options.method = method;
    options.referenceSampleSize = 600;
    options.randomSeed = 3;
    options.fitOnly = true;
    mcv::ReductionModel fromSteps, fromWhole;
    options.timeSteps = 2;
    options.fittedModel = &fromSteps;
    const mcv::ReductionResult a = mcv::reduceDimension(steps, options);
    options.timeSteps = 1;
    options.fittedModel = &fromWhole;
    const mcv::ReductionResult b = mcv::reduceDimension(whole, options);
    ASSERT_TRUE(a.ok()) << a.error;
    ASSERT_TRUE(b.ok()) << b.error;
    EXPECT_EQ(a.referenceIndices, b.referenceIndices);
    EXPECT_EQ(a.sampledVoxels, 4000u);
    EXPECT_TRUE(fromSteps.referenceCoordinates == fromWhole.referenceCoordinates);
    // The sample holds rows of both steps.
    std::size_t ofSecond = 0;
    for (std::int64_t i : a.referenceIndices)
    {
      ofSecond += i >= 2000 ? 1 : 0;
    }
    EXPECT_GT(ofSecond, 200u);
    EXPECT_LT(ofSecond, 400u);
  }
  // Several steps are only fitted: placing them is each step's own run.
  mcv::ReductionOptions placing;
  placing.timeSteps = 2;
  EXPECT_FALSE(mcv::reduceDimension(steps, placing).ok());
}
