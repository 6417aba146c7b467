// The geometry of a uniform 3D grid: what the core needs to know of a vtkImageData.
#pragma once

#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <sstream>
#include <string>

namespace mcv
{

struct ImageGrid
{
  std::array<int, 3> dims{ 0, 0, 0 };            // voxels along x, y, z (x fastest)
  std::array<double, 3> spacing{ 1.0, 1.0, 1.0 }; // world units per voxel
  std::array<double, 3> origin{ 0.0, 0.0, 0.0 };  // world position of voxel (0,0,0)

  std::size_t voxelCount() const
  {
    return static_cast<std::size_t>(dims[0]) * static_cast<std::size_t>(dims[1]) *
      static_cast<std::size_t>(dims[2]);
  }

  // Linear index -> (i, j, k) -> world position.
  std::array<double, 3> worldPosition(std::int64_t linearIndex) const
  {
    const std::int64_t nx = dims[0], nxy = static_cast<std::int64_t>(dims[0]) * dims[1];
    const std::int64_t k = linearIndex / nxy;
    const std::int64_t rest = linearIndex - k * nxy;
    const std::int64_t j = rest / nx;
    const std::int64_t i = rest - j * nx;
    return { origin[0] + spacing[0] * static_cast<double>(i),
      origin[1] + spacing[1] * static_cast<double>(j),
      origin[2] + spacing[2] * static_cast<double>(k) };
  }

  // Number of axes with more than one voxel (3 for a volume, 2 for a single slice).
  int extendedAxes() const { return (dims[0] > 1) + (dims[1] > 1) + (dims[2] > 1); }

  // "" when every axis has a positive, finite spacing; else which axis does not and what
  // to do (shared by the filters that work in world units, so they say it alike).
  std::string spacingProblem() const
  {
    for (int a = 0; a < 3; ++a)
    {
      if (!(spacing[a] > 0.0) || !std::isfinite(spacing[a]))
      {
        std::ostringstream msg;
        msg << "the voxel spacing (" << spacing[0] << ", " << spacing[1] << ", " << spacing[2]
            << ") is not positive along axis " << a << " (" << "xyz"[a]
            << "): every axis needs a positive, finite spacing; give the volume one (the "
               "reader's DataSpacing, or the spacing in the file's header)";
        return msg.str();
      }
    }
    return std::string();
  }
};

} // namespace mcv
