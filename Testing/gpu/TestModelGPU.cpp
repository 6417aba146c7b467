// A reduction model applied on the GPU (the fused placement with the model's references and
// normalisation, features/cuda/FusedPlacementCuda.h) against the CPU: the same model, coordinates
// within 1e-6 of their range, the same distances to the model (measured on the CPU from the
// same features) and the same out-of-model count. On a random 3-channel volume of mixed
// scalar types with NaN voxels, and on the real Colin27 brain (a 40-slice piece). Skips
// without a GPU.
#include "BrainFeatures.h"
#include "FusedRuns.h"
#include "ModelRuns.h"
#include "RequireGpu.h"

#include <gtest/gtest.h>

#include <cstdio>

namespace
{
namespace mt = mcv::testing;
using mcv::Device;

void expectSameApplication(const std::vector<mcv::ChannelView>& views, const mcv::ImageGrid& grid,
  mcv::ReductionMethod method, std::size_t sample)
{
  mcv::ReductionOptions ro = mt::isomapOptions(sample, Device::CPU);
  ro.method = method;
  const mcv::FeatureOptions fo = mt::fused24D(Device::CPU);
  const mt::ModelRun fitted = mt::fitModel(views, grid, fo, ro);
  ASSERT_EQ(fitted.error, "");
  const mt::ModelRun cpu = mt::applyModel(views, grid, fo, fitted, Device::CPU);
  const mt::ModelRun gpu = mt::applyModel(views, grid, fo, fitted, Device::GPU);
  ASSERT_EQ(cpu.error, "");
  ASSERT_EQ(gpu.error, "");
  EXPECT_EQ(cpu.result.coordinates, fitted.result.coordinates) << "the model on its fit volume, one path";
  if (method != mcv::ReductionMethod::PCA)
    EXPECT_EQ(gpu.result.deviceUsed, Device::GPU);
  const float range = mt::coordinateRange(cpu.result.coordinates);
  const float diff = mt::maxDifference(gpu.result.coordinates, cpu.result.coordinates);
  std::printf("[ model ] %s, %zu voxels: max |GPU - CPU| = %.3g (range %.3g, ratio %.2g), out of model %zu / %zu\n",
    mcv::reductionMethodName(method), grid.voxelCount(), diff, range, diff / range, gpu.result.outOfModelVoxels,
    cpu.result.outOfModelVoxels);
  EXPECT_LE(diff, 1e-6f * range);
  EXPECT_EQ(gpu.distance, cpu.distance);
  EXPECT_EQ(gpu.result.outOfModelVoxels, cpu.result.outOfModelVoxels);
}

TEST(ModelGPU, RandomVolumeMatchesTheCpu)
{
  MCV_REQUIRE_GPU();
  const mt::TypedChannels t = mt::randomChannels({ 37, 29, 26 }, 21);
  for (mcv::ReductionMethod m : { mcv::ReductionMethod::PCA, mcv::ReductionMethod::Isomap })
    expectSameApplication(t.views(), t.grid, m, 600);
}

TEST(ModelGPU, RealBrainPieceMatchesTheCpu)
{
  MCV_REQUIRE_GPU();
  if (!mt::haveBrain())
    GTEST_SKIP() << "the brain volumes are missing (scripts/fetch-data.sh)";
  const std::vector<mt::Volume> piece = mt::brainPiece();
  expectSameApplication(mt::floatViews(piece), piece[0].grid, mcv::ReductionMethod::Isomap, 3000);
}

} // namespace
