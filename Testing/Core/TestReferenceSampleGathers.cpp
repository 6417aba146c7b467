// The reference sample reads each row's features at most once (ReferenceSample.cpp keeps the
// used features of the rows it gathered), and the vectors it returns are the source's rows,
// bit for bit, in the used columns.
#include "FeatureRows.h"
#include "ForwardingRows.h"
#include "ReferenceSample.h"

#include <gtest/gtest.h>

#include <cmath>
#include <map>
#include <random>
#include <vector>

namespace
{
// The rows of a matrix, counting how often each row is gathered.
class CountingRows final : public mcv::testing::ForwardingRows
{
public:
  explicit CountingRows(mcv::FeatureRows& rows)
    : ForwardingRows(rows)
  {
  }
  void gather(const std::size_t* index, std::size_t n, float* out) override
  {
    for (std::size_t i = 0; i < n; ++i)
    {
      ++gathered[index[i]];
    }
    ++calls;
    ForwardingRows::gather(index, n, out);
  }
  std::map<std::size_t, int> gathered;
  int calls = 0;
};
} // namespace

TEST(ReferenceSampleGathers, EachRowOnceAndTheSourcesValues)
{
  // 400000 rows of 6 columns; 70 % of them one background vector, the rest quantised, so the
  // lists hold many duplicates and grow beyond the strata edges' subsample (each round looks
  // at the rows of the last one again, and the proposal at rows the rounds saw).
  const int cols = 6;
  const std::size_t n = 400000;
  std::mt19937 random(11);
  std::uniform_real_distribution<float> u(0.f, 1.f);
  std::vector<float> data(n * cols, 0.f);
  for (std::size_t r = 0; r < n; ++r)
  {
    if (u(random) < 0.7f)
    {
      continue;
    }
    for (int c = 0; c < cols; ++c)
    {
      data[r * cols + c] = std::round(u(random) * 40.f) / 8.f;
    }
  }
  const std::vector<int> used{ 0, 2, 3, 5 };
  const std::vector<double> center{ 0.5, 1.0, 0.25, 2.0 };
  mcv::ReferenceSampleOptions options;
  options.size = 20000;
  options.seed = 7;
  mcv::MatrixRows matrix(data.data(), n, cols);
  CountingRows source(matrix);
  const mcv::ReferenceSample sample =
    mcv::drawReferenceSample(source, mcv::RowLayout::plain(n), used, center, options, nullptr);
  ASSERT_TRUE(sample.error.empty()) << sample.error;
  ASSERT_EQ(sample.indices.size(), options.size);
  EXPECT_GT(source.calls, 2) << "the draw should read the rows in several calls";
  for (const auto& row : source.gathered)
  {
    ASSERT_EQ(row.second, 1) << "row " << row.first << " was gathered " << row.second << " times";
  }
  for (std::size_t i = 0; i < sample.indices.size(); ++i)
  {
    const std::size_t row = static_cast<std::size_t>(sample.indices[i]);
    EXPECT_EQ(source.gathered.count(row), 1u);
    for (std::size_t k = 0; k < used.size(); ++k)
    {
      ASSERT_EQ(sample.vectors[i * used.size() + k], data[row * cols + static_cast<std::size_t>(used[k])]) << i;
    }
  }
  // The same sample as from the matrix itself (the draw's other entry point).
  const mcv::ReferenceSample again = mcv::drawReferenceSample(data.data(), cols, mcv::RowLayout::plain(n), used, center,
    options, nullptr);
  EXPECT_EQ(again.indices, sample.indices);
  EXPECT_EQ(again.vectors, sample.vectors);
}
