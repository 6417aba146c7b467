// The method table (ReductionMethods.h): one row per ReductionMethod value, in its order,
// names that find their rows, and each row's fit gives an embedding of the asked dimension
// (PCA's with its linear map) on a small random sample.
#include "ReductionMethods.h"

#include <gtest/gtest.h>

#include <random>
#include <set>
#include <string>

TEST(ReductionMethods, OneRowPerMethodInTheEnumsOrder)
{
  const std::vector<mcv::ReductionMethodInfo>& table = mcv::reductionMethods();
  ASSERT_EQ(table.size(), 4u);
  std::set<std::string> names;
  for (std::size_t i = 0; i < table.size(); ++i)
  {
    EXPECT_EQ(static_cast<std::size_t>(table[i].method), i);
    EXPECT_EQ(mcv::findReductionMethod(table[i].method), &table[i]);
    EXPECT_EQ(mcv::findReductionMethod(std::string(table[i].name)), &table[i]);
    EXPECT_STREQ(mcv::reductionMethodName(table[i].method), table[i].name);
    names.insert(table[i].name);
  }
  EXPECT_EQ(names.size(), table.size());
  EXPECT_EQ(mcv::findReductionMethod(static_cast<mcv::ReductionMethod>(17)), nullptr);
  EXPECT_EQ(mcv::findReductionMethod(std::string("tSNE")), nullptr);
  // Only a linear map is projected; only PCA and Isomap have a variance spectrum.
  EXPECT_TRUE(mcv::findReductionMethod(mcv::ReductionMethod::PCA)->projects);
  EXPECT_FALSE(mcv::findReductionMethod(mcv::ReductionMethod::Isomap)->projects);
  EXPECT_TRUE(mcv::findReductionMethod(mcv::ReductionMethod::Isomap)->varianceSpectrum);
  EXPECT_FALSE(mcv::findReductionMethod(mcv::ReductionMethod::LLE)->varianceSpectrum);
  EXPECT_FALSE(mcv::findReductionMethod(mcv::ReductionMethod::UMAP)->varianceSpectrum);
}

TEST(ReductionMethods, EveryFitEmbedsTheSample)
{
  std::mt19937 random(4);
  std::normal_distribution<float> normal;
  mcv::RowMatrixF x(300, 5);
  for (Eigen::Index i = 0; i < x.size(); ++i)
  {
    x.data()[i] = normal(random);
  }
  mcv::ReductionOptions options;
  options.numberOfNeighbors = 12;
  options.numberOfLandmarks = 100;
  options.device = mcv::Device::CPU;
  for (const mcv::ReductionMethodInfo& m : mcv::reductionMethods())
  {
    for (int d : { 2, 3 })
    {
      options.outputDimension = d;
      mcv::PCAModel pca;
      const mcv::Embedding e = m.fit(x, options, [](const char*, double) {}, &pca);
      ASSERT_TRUE(e.error.empty()) << m.name << ": " << e.error;
      EXPECT_EQ(e.coordinates.rows(), x.rows()) << m.name;
      EXPECT_EQ(e.coordinates.cols(), d) << m.name;
      EXPECT_TRUE(e.coordinates.allFinite()) << m.name;
      EXPECT_EQ(pca.axes.cols(), m.projects ? d : 0) << m.name;
    }
  }
}
