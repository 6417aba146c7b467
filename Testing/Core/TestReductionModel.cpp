// Reduction models (ReductionModel.h): what a fit produces, applied to other rows without
// a fit. Known answers: a model applied to its own fit rows gives the fit's coordinates bit
// for bit (every method, a matrix and the fused path); a row no reference resembles is out
// of the model and counted; the distance to the model does not depend on how the nearest
// reference was found (the placement's neighbours or a search); bad models and options are
// errors.
#include "BrainFeatures.h"
#include "ModelRuns.h"
#include "TestVolumes.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

namespace
{
namespace mt = mcv::testing;
using mcv::ReductionMethod;

std::vector<float> clusteredRows(std::size_t n, int D, std::uint64_t seed)
{
  std::mt19937_64 rng(seed);
  std::normal_distribution<float> noise(0.0f, 0.3f);
  std::vector<float> rows(n * D);
  for (std::size_t i = 0; i < n; ++i)
    for (int c = 0; c < D; ++c)
      rows[i * D + c] = static_cast<float>(static_cast<int>(i % 4) * (c % 3 == 0 ? 2 : -1)) + noise(rng);
  return rows;
}

mcv::ReductionOptions optionsFor(ReductionMethod method)
{
  mcv::ReductionOptions o;
  o.method = method;
  o.referenceSampleSize = 300;
  o.numberOfNeighbors = 12;
  o.numberOfLandmarks = 100;
  o.numberOfEpochs = 50;
  o.device = mcv::Device::CPU;
  o.trustworthinessSample = 0;
  return o;
}

const ReductionMethod kMethods[] = { ReductionMethod::PCA, ReductionMethod::Isomap, ReductionMethod::LLE,
  ReductionMethod::UMAP };

TEST(ReductionModel, AppliedToItsOwnRowsGivesTheFitBitForBit)
{
  const std::size_t n = 2000;
  const int D = 6;
  const std::vector<float> rows = clusteredRows(n, D, 3);
  const mcv::FeatureMatrix matrix{ rows.data(), n, D };
  std::vector<float> distancePCA;
  for (ReductionMethod method : kMethods)
  {
    mcv::ReductionOptions fit = optionsFor(method);
    mcv::ReductionModel model;
    fit.fittedModel = &model;
    const mcv::ReductionResult fitted = mcv::reduceDimension(matrix, fit);
    ASSERT_TRUE(fitted.ok()) << fitted.error;
    EXPECT_EQ(model.check(), "");
    EXPECT_EQ(model.references, fitted.referenceIndices.size());
    EXPECT_GT(model.referenceRadius, 0.0);

    mcv::ReductionOptions apply;
    apply.model = &model;
    apply.device = mcv::Device::CPU;
    std::vector<float> distance(n);
    apply.modelDistanceOutput = distance.data();
    const mcv::ReductionResult applied = mcv::reduceDimension(matrix, apply);
    ASSERT_TRUE(applied.ok()) << applied.error;
    EXPECT_TRUE(applied.modelApplied);
    EXPECT_EQ(applied.coordinates, fitted.coordinates) << mcv::reductionMethodName(method);
    EXPECT_EQ(applied.eigenvalues, fitted.eigenvalues);
    EXPECT_EQ(applied.outOfModelVoxels, 0u);
    // The references are the same for every method (same seed, same rows), so is the
    // distance: searched (PCA) or from the placement's neighbours (the others).
    if (method == ReductionMethod::PCA)
      distancePCA = distance;
    else
      EXPECT_EQ(distance, distancePCA) << mcv::reductionMethodName(method);
  }
}

TEST(ReductionModel, ARowNoReferenceResemblesIsOutOfTheModel)
{
  const std::size_t n = 1500;
  const int D = 5;
  std::vector<float> rows = clusteredRows(n, D, 7);
  mcv::ReductionOptions fit = optionsFor(ReductionMethod::Isomap);
  mcv::ReductionModel model;
  fit.fittedModel = &model;
  ASSERT_TRUE(mcv::reduceDimension(mcv::FeatureMatrix{ rows.data(), n, D }, fit).ok());
  for (std::size_t i : { std::size_t(10), std::size_t(700) })
    for (int c = 0; c < D; ++c)
      rows[i * D + c] = 40.0f + static_cast<float>(c);
  mcv::ReductionOptions apply;
  apply.model = &model;
  std::vector<float> distance(n);
  apply.modelDistanceOutput = distance.data();
  const mcv::ReductionResult r = mcv::reduceDimension(mcv::FeatureMatrix{ rows.data(), n, D }, apply);
  ASSERT_TRUE(r.ok()) << r.error;
  EXPECT_EQ(r.outOfModelVoxels, 2u);
  EXPECT_GT(distance[10], 10.0f);
  EXPECT_GT(distance[700], 10.0f);
  // The distance is |row - nearest reference| / radius: a reference row is at 0.
  EXPECT_EQ(distance[static_cast<std::size_t>(0)] >= 0.0f, true);
}

TEST(ReductionModel, TheFusedPathAppliesItsOwnNormalisation)
{
  const mcv::ImageGrid grid = mt::makeGrid(24, 20, 14, { 1.0, 1.5, 2.0 });
  const std::vector<mt::Volume> channels{ mt::randomVolume(grid, 11), mt::randomVolume(grid, 12) };
  const std::vector<mcv::ChannelView> views = mt::floatViews(channels); // points into `channels`
  mcv::FeatureOptions fo;
  fo.preset = mcv::FeaturePreset::TwentyFourD;
  fo.device = mcv::Device::CPU;
  for (ReductionMethod method : { ReductionMethod::PCA, ReductionMethod::Isomap })
  {
    const mt::ModelRun fitted = mt::fitModel(views, grid, fo, optionsFor(method));
    ASSERT_EQ(fitted.error, "");
    const mt::ModelRun applied = mt::applyModel(views, grid, fo, fitted, mcv::Device::CPU);
    ASSERT_EQ(applied.error, "");
    EXPECT_EQ(applied.offset, fitted.offset);
    EXPECT_EQ(applied.result.coordinates, fitted.result.coordinates);
    // A brighter copy keeps the fit's normalisation, so its coordinates move.
    std::vector<mt::Volume> brighter = channels;
    for (float& v : brighter[0].values)
      v *= 1.5f;
    const mt::ModelRun moved = mt::applyModel(mt::floatViews(brighter), grid, fo, fitted, mcv::Device::CPU);
    ASSERT_EQ(moved.error, "");
    EXPECT_NE(moved.result.coordinates, fitted.result.coordinates);
  }
}

TEST(ReductionModel, BadModelsAndOptionsAreErrors)
{
  const std::size_t n = 600;
  const int D = 4;
  const std::vector<float> rows = clusteredRows(n, D, 5);
  const mcv::FeatureMatrix matrix{ rows.data(), n, D };
  mcv::ReductionOptions fit = optionsFor(ReductionMethod::PCA);
  mcv::ReductionModel model;
  fit.fittedModel = &model;
  fit.fitOnly = true;
  std::vector<float> untouched(n * 3, -7.0f);
  fit.coordinatesOutput = untouched.data();
  const mcv::ReductionResult fitted = mcv::reduceDimension(matrix, fit);
  ASSERT_TRUE(fitted.ok()) << fitted.error;
  EXPECT_EQ(model.check(), "");
  EXPECT_EQ(untouched, std::vector<float>(n * 3, -7.0f)) << "fitOnly places no row";

  mcv::ReductionOptions apply;
  mcv::ReductionModel broken = model;
  broken.referenceFeatures[3] = std::nanf("");
  apply.model = &broken;
  EXPECT_NE(mcv::reduceDimension(matrix, apply).error.find("non-finite"), std::string::npos);
  broken = model;
  broken.referenceCoordinates.pop_back();
  EXPECT_NE(mcv::reduceDimension(matrix, apply).error.find("reference coordinates hold"), std::string::npos);

  const std::vector<float> wider = clusteredRows(n, D + 1, 5);
  apply.model = &model;
  EXPECT_NE(mcv::reduceDimension(mcv::FeatureMatrix{ wider.data(), n, D + 1 }, apply).error.find(
              "fitted on 4 feature columns; these rows have 5"),
    std::string::npos);

  std::vector<float> nan = rows;
  nan[5 * D + 1] = std::nanf("");
  EXPECT_NE(mcv::reduceDimension(mcv::FeatureMatrix{ nan.data(), n, D }, apply).error.find("non-finite"),
    std::string::npos);

  mcv::ReductionOptions noModel = optionsFor(ReductionMethod::PCA);
  std::vector<float> distance(n);
  noModel.modelDistanceOutput = distance.data();
  EXPECT_NE(mcv::reduceDimension(matrix, noModel).error.find("set options.model"), std::string::npos);
}

} // namespace
