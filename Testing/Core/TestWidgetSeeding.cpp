// Automatic widgets from k-means of the reduced domain: well-separated blobs with known
// centres, sizes and spreads must come back as the widgets, largest first, in the palette's
// colours, the largest one faint, and sigmas that overlap little.
#include "WidgetSeeding.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <set>
#include <vector>

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
      // The largest of the widgets is a faint veil (0.05 of the opacity), the others 0.6.
      EXPECT_NEAR(w.opacity, i == 0 ? 0.03 : 0.6, 1e-12);
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
  for (std::size_t i = 0; i < a.widgets.size(); ++i)
  {
    const mcv::GaussianWidget& w = a.widgets[i];
    colours.insert({ w.color[0], w.color[1], w.color[2] });
    double expected[3];
    mcv::widgetColor(static_cast<int>(i), expected); // the palette, in order
    for (int c = 0; c < 3; ++c)
    {
      EXPECT_DOUBLE_EQ(w.color[c], expected[c]);
    }
  }
  EXPECT_EQ(colours.size(), 6u);
}

TEST(WidgetSeeding, PaletteIsColorBrewerSet1)
{
  ASSERT_EQ(mcv::widgetPaletteSize(), 8);
  double rgb[3];
  const int set1[8][3] = { { 228, 26, 28 }, { 55, 126, 184 }, { 77, 175, 74 }, { 152, 78, 163 },
    { 255, 127, 0 }, { 255, 255, 51 }, { 166, 86, 40 }, { 247, 129, 191 } };
  for (int i = 0; i < 8; ++i)
  {
    mcv::widgetColor(i, rgb);
    for (int c = 0; c < 3; ++c)
    {
      EXPECT_NEAR(rgb[c] * 255.0, set1[i][c], 1e-9) << "colour " << i;
    }
    mcv::widgetColor(i + 8, rgb); // the second round: the same hue, darker
    for (int c = 0; c < 3; ++c)
    {
      EXPECT_NEAR(rgb[c] * 255.0, 0.6 * set1[i][c], 1e-9) << "colour " << i + 8;
    }
  }
  std::set<std::vector<double>> first16;
  for (int i = 0; i < 16; ++i)
  {
    mcv::widgetColor(i, rgb);
    first16.insert({ rgb[0], rgb[1], rgb[2] });
  }
  EXPECT_EQ(first16.size(), 16u);
}

TEST(WidgetSeeding, SigmaCappedSoNeighboursOverlapLittle)
{
  // Two broad blobs (sigma 1) whose centres are 2 apart: each cluster's own spread is about
  // 0.9, more than a quarter of the distance between the k-means centres (about 2.8), so the
  // cap decides: sigma = d / 4, and each widget weighs exp(-8) at the other's centre.
  const std::vector<float> points =
    sampleBlobs({ { { -1, 0, 0 }, 1.0, 1500 }, { { 1, 0, 0 }, 1.0, 1500 } }, 3, 5);
  mcv::WidgetSeedingOptions options;
  options.count = 2;
  options.seed = 1;
  const mcv::WidgetSeeding s = mcv::seedGaussianWidgets({ points.data(), 3000, 3 }, options);
  ASSERT_TRUE(s.ok()) << s.error;
  ASSERT_EQ(s.widgets.size(), 2u);
  const mcv::GaussianWidget& a = s.widgets[0];
  const mcv::GaussianWidget& b = s.widgets[1];
  const double d = std::sqrt(std::pow(a.center[0] - b.center[0], 2) + std::pow(a.center[1] - b.center[1], 2) +
    std::pow(a.center[2] - b.center[2], 2));
  EXPECT_GT(d, 2.0);
  EXPECT_NEAR(a.sigma, 0.25 * d, 1e-12);
  EXPECT_NEAR(b.sigma, 0.25 * d, 1e-12);
  EXPECT_NEAR(std::exp(-d * d / (2 * a.sigma * a.sigma)), std::exp(-8.0), 1e-12);
}

TEST(WidgetSeeding, WeightsAreVoxelsInSizesNotInTheClustering)
{
  // Two blobs of 200 points; each point of the second stands for 10 voxels: it becomes the
  // largest cluster (first, the faint one), with the same centres as unweighted.
  const std::vector<float> points = sampleBlobs({ { { -5, 0, 0 }, 0.3, 200 }, { { 5, 0, 0 }, 0.3, 200 } }, 3, 9);
  std::vector<double> weights(400, 1.0);
  std::fill(weights.begin() + 200, weights.end(), 10.0);
  mcv::WidgetSeedingOptions options;
  options.count = 2;
  options.opacity = 0.5;
  const mcv::WidgetSeeding plain = mcv::seedGaussianWidgets({ points.data(), 400, 3 }, options);
  options.weights = weights.data();
  const mcv::WidgetSeeding s = mcv::seedGaussianWidgets({ points.data(), 400, 3 }, options);
  ASSERT_TRUE(s.ok() && plain.ok());
  ASSERT_EQ(s.widgets.size(), 2u);
  EXPECT_NEAR(s.widgets[0].center[0], 5.0, 0.1);
  EXPECT_EQ(s.clusterSizes, (std::vector<std::size_t>{ 2000, 200 }));
  EXPECT_NEAR(s.widgets[0].opacity, 0.025, 1e-12);
  EXPECT_NEAR(s.widgets[1].opacity, 0.5, 1e-12);
  for (const mcv::GaussianWidget& w : plain.widgets)
  {
    const mcv::GaussianWidget& same = s.widgets[w.center[0] > 0 ? 0 : 1];
    EXPECT_DOUBLE_EQ(w.center[0], same.center[0]);
    EXPECT_DOUBLE_EQ(w.sigma, same.sigma);
  }
  // Weighted the other way, the first blob is the largest and the faint one.
  std::fill(weights.begin(), weights.begin() + 200, 100.0);
  const mcv::WidgetSeeding other = mcv::seedGaussianWidgets({ points.data(), 400, 3 }, options);
  EXPECT_NEAR(other.widgets[0].center[0], -5.0, 0.1);
  EXPECT_NEAR(other.widgets[0].opacity, 0.025, 1e-12);
  // One widget alone is not a veil.
  options.count = 1;
  EXPECT_NEAR(mcv::seedGaussianWidgets({ points.data(), 400, 3 }, options).widgets[0].opacity, 0.5, 1e-12);
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

TEST(WidgetSeeding, OpacityFromShareAndRayLengthHidesTheBackgroundSizedClass)
{
  // Three blobs standing for 7000, 2000 and 1000 voxels: shares 0.7, 0.2, 0.1 of the
  // widgets' clusters. A ray crossing L = 50 unit distances of foreground crosses s L of
  // each; the peak lets half the light through: a = (1 - 0.5^(1 / (s L))) / g, at most
  // the asked opacity; the class of more than half of the voxels is flagged hidden.
  const std::vector<float> points = sampleBlobs(
    { { { -6, 0, 0 }, 0.4, 100 }, { { 6, 0, 0 }, 0.4, 100 }, { { 0, 8, 0 }, 0.4, 100 } }, 3, 5);
  std::vector<double> weights(300);
  std::fill(weights.begin(), weights.begin() + 100, 70.0);
  std::fill(weights.begin() + 100, weights.begin() + 200, 20.0);
  std::fill(weights.begin() + 200, weights.end(), 10.0);
  mcv::WidgetSeedingOptions options;
  options.count = 3;
  options.opacity = 0.5;
  options.weights = weights.data();
  options.rayLength = 50.0;
  const mcv::WidgetSeeding s = mcv::seedGaussianWidgets({ points.data(), 300, 3 }, options);
  ASSERT_TRUE(s.ok()) << s.error;
  ASSERT_EQ(s.widgets.size(), 3u);
  const double shares[3] = { 0.7, 0.2, 0.1 };
  for (int w = 0; w < 3; ++w)
  {
    EXPECT_NEAR(s.shares[w], shares[w], 1e-12);
    EXPECT_GT(s.meanWeights[w], 0.0);
    EXPECT_LE(s.meanWeights[w], 1.0);
    const double crossed = shares[w] * 50.0;
    const double expected = std::min(0.5, (1.0 - std::pow(0.5, 1.0 / crossed)) / s.meanWeights[w]);
    EXPECT_NEAR(s.widgets[w].opacity, expected, 1e-12) << "widget " << w;
    EXPECT_EQ(s.hidden[w], w == 0);
  }
  // The larger the share, the fainter: 0.7 of the voxels gets less than 0.1 of them.
  EXPECT_LT(s.widgets[0].opacity, s.widgets[2].opacity);
  // Without a ray length: the fixed peaks and the veil, nothing hidden.
  options.rayLength = 0;
  const mcv::WidgetSeeding fixed = mcv::seedGaussianWidgets({ points.data(), 300, 3 }, options);
  EXPECT_NEAR(fixed.widgets[0].opacity, 0.025, 1e-12);
  EXPECT_NEAR(fixed.widgets[1].opacity, 0.5, 1e-12);
  EXPECT_EQ(fixed.hidden, (std::vector<bool>{ false, false, false }));
}
