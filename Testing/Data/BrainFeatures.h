// The real 3-channel brain of the dimension-reduction tests and benchmarks: Colin27 T1
// (ch2.nii.gz) with the AAL and Brodmann label volumes on the same 181 x 217 x 181 grid
// (scripts/fetch-data.sh), and its per-voxel feature matrix. Header-only; link zlib.
#pragma once

#include "FeatureVectors.h"
#include "TestVolumes.h"

#include <array>
#include <string>
#include <vector>

namespace mcv
{
namespace testing
{

inline const std::vector<std::string>& brainFiles()
{
  static const std::vector<std::string> files = { "ch2.nii.gz", "aal.nii.gz", "brodmann.nii.gz" };
  return files;
}

inline bool haveBrain()
{
  for (const auto& f : brainFiles())
    if (!haveDataFile(f))
      return false;
  return true;
}

// The three channels (throws when a file is missing or the grids differ).
inline std::vector<Volume> loadBrain()
{
  std::vector<Volume> ch;
  for (const auto& f : brainFiles())
    ch.push_back(loadNifti(dataFile(f)));
  for (const auto& v : ch)
    if (v.grid.dims != ch[0].grid.dims)
      throw std::runtime_error("the brain channels are not on one grid: " + v.name);
  return ch;
}

// The box [lo, hi) of every channel (index space), for tests that need a smaller piece.
inline std::vector<Volume> cropBrain(const std::vector<Volume>& ch, std::array<int, 3> lo, std::array<int, 3> hi)
{
  std::vector<Volume> out;
  for (const auto& v : ch)
  {
    Volume c;
    c.name = v.name + " (cropped)";
    c.grid = v.grid;
    c.grid.dims = { hi[0] - lo[0], hi[1] - lo[1], hi[2] - lo[2] };
    c.values.reserve(c.grid.voxelCount());
    for (int k = lo[2]; k < hi[2]; ++k)
      for (int j = lo[1]; j < hi[1]; ++j)
        for (int i = lo[0]; i < hi[0]; ++i)
          c.values.push_back(v.values[(static_cast<std::size_t>(k) * v.grid.dims[1] + j) * v.grid.dims[0] + i]);
    out.push_back(std::move(c));
  }
  return out;
}

struct BrainFeatureMatrix
{
  std::vector<float> values; // rows x cols, row-major
  std::size_t rows = 0;
  int cols = 0;
  FeatureResult result;
};

// Views of float channels (the brain as the loader gives it).
inline std::vector<ChannelView> floatViews(const std::vector<Volume>& volumes)
{
  std::vector<ChannelView> views;
  for (const Volume& v : volumes)
  {
    ChannelView cv;
    cv.data = v.values.data();
    cv.type = ScalarType::Float32;
    views.push_back(cv);
  }
  return views;
}

// The 40-slice piece of the brain the GPU tests compare the CPU with (z 70..109).
inline std::vector<Volume> brainPiece()
{
  return cropBrain(loadBrain(), { 0, 0, 70 }, { 181, 217, 110 });
}

// Z-scored features of the channels (SixD or TwentyFourD) on `device`.
inline BrainFeatureMatrix brainFeatures(const std::vector<Volume>& ch, FeaturePreset preset, Device device)
{
  BrainFeatureMatrix f;
  const std::vector<ChannelView> views = floatViews(ch);
  FeatureOptions o;
  o.preset = preset;
  o.device = device;
  f.rows = ch[0].grid.voxelCount();
  f.cols = featureCount(views.size(), o);
  f.values.assign(f.rows * static_cast<std::size_t>(f.cols), 0.f);
  computeFeatures(views, ch[0].grid, o, { f.values.data(), f.rows, f.cols }, f.result);
  return f;
}

} // namespace testing
} // namespace mcv
