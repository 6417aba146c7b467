// Automatic widgets from k-means of the reduced domain: well-separated blobs with known
// centres, sizes and spreads must come back as the widgets, largest first.
#include "WidgetSeeding.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <set>

namespace
{

struct Blob
{
  double center[3];
  double sigma;
  int count;
};

std::vector<float> sampleBlobs(const std::vector<Blob>& blobs, int dims, unsigned seed)
{
  std::mt19937 rng(seed);
  std::normal_distribution<double> normal(0.0, 1.0);
  std::vector<float> points;
  for (const Blob& b : blobs)
  {
    for (int i = 0; i < b.count; ++i)
    {
      for (int d = 0; d < dims; ++d)
      {
        points.push_back(static_cast<float>(b.center[d] + b.sigma * normal(rng)));
      }
    }
  }
  return points;
}

} // namespace

TEST(WidgetSeeding, RecoversSeparatedBlobsLargestFirst)
{
  for (int dims : { 2, 3 })
  {
    const std::vector<Blob> blobs = { { { 5, 0, 0 }, 0.2, 300 }, { { -3, 4, 1 }, 0.1, 600 },
      { { 0, -5, -2 }, 0.3, 150 } };
    const std::vector<float> points = sampleBlobs(blobs, dims, 7);
    mcv::WidgetSeedingOptions options;
    options.count = 3;
    options.opacity = 0.6;
    const mcv::WidgetSeeding s =
      mcv::seedGaussianWidgets({ points.data(), points.size() / dims, dims }, options);
    ASSERT_TRUE(s.ok()) << s.error;
    ASSERT_EQ(s.widgets.size(), 3u);
    const int expectedOrder[3] = { 1, 0, 2 }; // by size: 600, 300, 150
    for (int i = 0; i < 3; ++i)
    {
      const Blob& b = blobs[static_cast<std::size_t>(expectedOrder[i])];
      const mcv::GaussianWidget& w = s.widgets[static_cast<std::size_t>(i)];
      EXPECT_EQ(s.clusterSizes[static_cast<std::size_t>(i)], static_cast<std::size_t>(b.count));
      for (int d = 0; d < dims; ++d)
      {
        // The mean of n normal samples is within a few sigma/sqrt(n) of the centre.
        EXPECT_NEAR(w.center[d], b.center[d], 5 * b.sigma / std::sqrt(b.count)) << "dims " << dims;
      }
      EXPECT_NEAR(w.sigma, b.sigma, 0.15 * b.sigma);
      EXPECT_DOUBLE_EQ(w.opacity, 0.6);
    }
    // Every point carries the label of its blob's widget.
    std::size_t offset = 0;
    for (std::size_t b = 0; b < blobs.size(); ++b)
    {
      const int widget = static_cast<int>(std::find(expectedOrder, expectedOrder + 3, static_cast<int>(b)) - expectedOrder);
      for (int i = 0; i < blobs[b].count; ++i)
      {
        ASSERT_EQ(s.labels[offset++], widget);
      }
    }
  }
}

TEST(WidgetSeeding, DistinctColoursAndSameSeedSameResult)
{
  const std::vector<float> points = sampleBlobs({ { { 0, 0, 0 }, 1.0, 2000 } }, 3, 3);
  mcv::WidgetSeedingOptions options;
  options.count = 6;
  options.seed = 42;
  const mcv::WidgetSeeding a = mcv::seedGaussianWidgets({ points.data(), 2000, 3 }, options);
  const mcv::WidgetSeeding b = mcv::seedGaussianWidgets({ points.data(), 2000, 3 }, options);
  ASSERT_TRUE(a.ok());
  ASSERT_EQ(a.widgets.size(), 6u);
  EXPECT_EQ(mcv::flattenGaussianWidgets(a.widgets), mcv::flattenGaussianWidgets(b.widgets));
  std::set<std::vector<double>> colours;
  for (const mcv::GaussianWidget& w : a.widgets)
  {
    colours.insert({ w.color[0], w.color[1], w.color[2] });
    EXPECT_GE(*std::max_element(w.color, w.color + 3), 1.0 - 1e-12); // full value
  }
  EXPECT_EQ(colours.size(), 6u);
}

TEST(WidgetSeeding, FewDistinctPointsNonFiniteAndBadInput)
{
  const float nan = std::nanf("");
  const std::vector<float> points = { 1, 1, 1, 1, 4, 4, nan, 0, 4, 4 }; // 2D: 2 distinct finite
  mcv::WidgetSeedingOptions options;
  options.count = 5;
  const mcv::WidgetSeeding s = mcv::seedGaussianWidgets({ points.data(), 5, 2 }, options);
  ASSERT_TRUE(s.ok()) << s.error;
  ASSERT_EQ(s.widgets.size(), 2u);
  EXPECT_EQ(s.labels[3], -1);
  EXPECT_EQ(s.labels[0], s.labels[1]);
  EXPECT_NE(s.labels[0], s.labels[2]);
  for (const mcv::GaussianWidget& w : s.widgets)
  {
    EXPECT_GT(w.sigma, 0.0); // a cluster of identical points still gets a usable widget
  }
  EXPECT_FALSE(mcv::seedGaussianWidgets({ points.data(), 5, 1 }, options).ok());
  options.count = 0;
  EXPECT_FALSE(mcv::seedGaussianWidgets({ points.data(), 5, 2 }, options).ok());
  const std::vector<float> allNan = { nan, nan };
  options.count = 1;
  EXPECT_FALSE(mcv::seedGaussianWidgets({ allNan.data(), 1, 2 }, options).ok());
}

TEST(WidgetSeeding, SkipLargestLeavesTheBackgroundOut)
{
  // A big tight "background" blob and two small structures: the widgets go to the two.
  const std::vector<float> points = sampleBlobs(
    { { { 0, 0, 0 }, 0.05, 5000 }, { { 4, 4, 0 }, 0.2, 300 }, { { -4, 3, 1 }, 0.2, 200 } }, 3, 11);
  mcv::WidgetSeedingOptions options;
  options.count = 2;
  options.skipLargest = true;
  const mcv::WidgetSeeding s = mcv::seedGaussianWidgets({ points.data(), 5500, 3 }, options);
  ASSERT_TRUE(s.ok()) << s.error;
  ASSERT_EQ(s.widgets.size(), 2u);
  EXPECT_EQ(s.skippedSize, 5000u);
  EXPECT_NEAR(s.widgets[0].center[0], 4.0, 0.1);
  EXPECT_NEAR(s.widgets[1].center[0], -4.0, 0.1);
  EXPECT_EQ(s.labels[0], -2);
  EXPECT_EQ(s.labels[5000], 0);
  EXPECT_EQ(s.labels[5300], 1);
  EXPECT_NE(mcv::flattenGaussianWidgets(s.widgets)[4], mcv::flattenGaussianWidgets(s.widgets)[12]);
}
