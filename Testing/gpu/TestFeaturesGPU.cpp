// The CUDA path of the feature vectors (features/cuda/FeaturesCuda.h through mcv::computeFeatures)
// against the CPU path: every column within 1e-5 relative (the per-voxel arithmetic is
// the same float operations without contraction, so they agree to a few ulps), on random
// multichannel volumes (6D, 24D, Custom; ZScore, MinMax, None; with NaN/Inf voxels) and
// on the real Colin27 brain (ch2 + aal + brodmann when present). Skips without a GPU.
#include "cuda/FeaturesCuda.h"

#include "FeatureVectors.h"

#include "RequireGpu.h"
#include "TestVolumes.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <string>
#include <vector>

namespace
{

namespace mt = mcv::testing;
using mcv::FeatureNormalization;
using mcv::FeatureOptions;
using mcv::FeaturePreset;
using mcv::ImageGrid;

struct FeatureRun
{
  std::vector<float> m;
  mcv::FeatureResult r;
};

FeatureRun runFeatures(const std::vector<const std::vector<float>*>& chans, const ImageGrid& g,
  FeatureOptions o, mcv::Device device)
{
  FeatureRun out;
  std::vector<mcv::ChannelView> views;
  for (const auto* v : chans)
  {
    mcv::ChannelView c;
    c.data = v->data();
    views.push_back(c);
  }
  o.device = device;
  const int F = mcv::featureCount(views.size(), o);
  out.m.assign(g.voxelCount() * F, -12345.0f);
  EXPECT_TRUE(mcv::computeFeatures(views, g, o, { out.m.data(), g.voxelCount(), F }, out.r))
    << out.r.error;
  return out;
}

// Max over columns of max_v |gpu - cpu| / max(|cpu|, 1e-3 max_v |cpu| of the column).
void compare(const FeatureRun& gpu, const FeatureRun& cpu, std::size_t rows, const char* label)
{
  ASSERT_EQ(gpu.r.deviceUsed, mcv::Device::GPU)
    << label << ": " << (gpu.r.warnings.empty() ? std::string() : gpu.r.warnings.back());
  ASSERT_EQ(cpu.r.deviceUsed, mcv::Device::CPU) << label;
  ASSERT_EQ(gpu.m.size(), cpu.m.size());
  EXPECT_EQ(gpu.r.names, cpu.r.names);
  EXPECT_EQ(gpu.r.constantColumns, cpu.r.constantColumns);
  EXPECT_EQ(gpu.r.nonFiniteVoxels, cpu.r.nonFiniteVoxels);
  const int F = static_cast<int>(cpu.r.names.size());
  double worst = 0.0;
  std::string worstName;
  for (int c = 0; c < F; ++c)
  {
    double colMax = 0.0;
    for (std::size_t v = 0; v < rows; ++v)
      colMax = std::max(colMax, static_cast<double>(std::fabs(cpu.m[v * F + c])));
    for (std::size_t v = 0; v < rows; ++v)
    {
      const double a = gpu.m[v * F + c], b = cpu.m[v * F + c];
      ASSERT_TRUE(std::isfinite(a)) << label << " " << cpu.r.names[c] << " voxel " << v;
      const double denom = std::max({ std::fabs(b), 1e-3 * colMax, 1e-30 });
      const double rel = std::fabs(a - b) / denom;
      if (rel > worst)
      {
        worst = rel;
        worstName = cpu.r.names[c];
      }
    }
    EXPECT_NEAR(gpu.r.columnOffset[c], cpu.r.columnOffset[c],
      1e-9 * (1.0 + std::fabs(cpu.r.columnOffset[c])));
    EXPECT_NEAR(gpu.r.columnScale[c], cpu.r.columnScale[c],
      1e-9 * (1.0 + std::fabs(cpu.r.columnScale[c])));
  }
  std::printf("%s: %d columns, worst relative difference %.3g (%s)\n", label, F, worst,
    worstName.c_str());
  EXPECT_LE(worst, 1e-5) << label << " " << worstName;
}

TEST(FeaturesGPU, RandomVolumesEverySetting)
{
  MCV_REQUIRE_GPU();
  const ImageGrid g = mt::makeGrid(67, 45, 38, { 0.9, 1.1, 2.0 }, { 3, -2, 1 });
  mt::Volume a = mt::randomVolume(g, 21), b = mt::randomVolume(g, 22);
  mt::Volume c = mt::gaussianBlobs(g, { { mt::gridCenter(g), 8.0, 900.0 } }, false);
  for (float& x : c.values)
    x += 1000.0f;
  for (FeaturePreset preset :
    { FeaturePreset::SixD, FeaturePreset::TwentyFourD, FeaturePreset::Custom })
  {
    for (FeatureNormalization norm :
      { FeatureNormalization::ZScore, FeatureNormalization::MinMax, FeatureNormalization::None })
    {
      FeatureOptions o;
      o.preset = preset;
      o.custom.intensity = false;
      o.custom.laplacian = true;
      o.custom.localVariance = true;
      o.normalization = norm;
      const FeatureRun gpu = runFeatures({ &a.values, &b.values, &c.values }, g, o, mcv::Device::GPU);
      const FeatureRun cpu = runFeatures({ &a.values, &b.values, &c.values }, g, o, mcv::Device::CPU);
      const std::string label =
        "random preset " + std::to_string(int(preset)) + " norm " + std::to_string(int(norm));
      compare(gpu, cpu, g.voxelCount(), label.c_str());
    }
  }
}

TEST(FeaturesGPU, NonFiniteVoxelsAndConstantChannel)
{
  MCV_REQUIRE_GPU();
  const ImageGrid g = mt::makeGrid(33, 20, 17);
  mt::Volume a = mt::randomVolume(g, 5);
  mt::Volume flat = mt::constantVolume(g, 3.0f);
  for (std::size_t v = 0; v < a.values.size(); v += 101)
    a.values[v] = (v % 2) ? std::numeric_limits<float>::quiet_NaN()
                          : -std::numeric_limits<float>::infinity();
  for (FeatureNormalization norm :
    { FeatureNormalization::ZScore, FeatureNormalization::MinMax, FeatureNormalization::None })
  {
    FeatureOptions o;
    o.preset = FeaturePreset::TwentyFourD;
    o.normalization = norm;
    const FeatureRun gpu = runFeatures({ &a.values, &flat.values }, g, o, mcv::Device::GPU);
    const FeatureRun cpu = runFeatures({ &a.values, &flat.values }, g, o, mcv::Device::CPU);
    EXPECT_GT(cpu.r.nonFiniteVoxels, 0u);
    compare(gpu, cpu, g.voxelCount(), "NaN + constant");
  }
}

TEST(FeaturesGPU, Colin27Brain)
{
  MCV_REQUIRE_GPU();
  if (!mt::haveDataFile("ch2.nii.gz"))
  {
    GTEST_SKIP() << "ch2.nii.gz not in " << mt::dataDir() << " (scripts/fetch-data.sh)";
  }
  std::vector<mt::Volume> volumes;
  volumes.push_back(mt::loadNifti(mt::dataFile("ch2.nii.gz")));
  for (const char* name : { "aal.nii.gz", "brodmann.nii.gz" })
  {
    if (mt::haveDataFile(name))
    {
      mt::Volume v = mt::loadNifti(mt::dataFile(name));
      if (v.grid.dims == volumes[0].grid.dims)
        volumes.push_back(std::move(v));
    }
  }
  std::vector<const std::vector<float>*> chans;
  for (const mt::Volume& v : volumes)
    chans.push_back(&v.values);
  const ImageGrid& g = volumes[0].grid;
  for (FeaturePreset preset : { FeaturePreset::SixD, FeaturePreset::TwentyFourD })
  {
    FeatureOptions o;
    o.preset = preset;
    const FeatureRun gpu = runFeatures(chans, g, o, mcv::Device::GPU);
    const FeatureRun cpu = runFeatures(chans, g, o, mcv::Device::CPU);
    std::printf("Colin27 %zu channel(s), %zu voxels: GPU %.1f ms, CPU %.1f ms\n", chans.size(),
      g.voxelCount(), gpu.r.totalMs, cpu.r.totalMs);
    compare(gpu, cpu, g.voxelCount(), preset == FeaturePreset::SixD ? "Colin27 6D" : "Colin27 24D");
  }
}

} // namespace
