// Where one process's block of a volume lies in the whole volume, for computations split
// over processes (MPI ranks; see Communicator.h). A block holds the process's piece plus
// ghost layers; inside it, the voxels the process OWNS. Every voxel of the whole volume is
// owned by exactly one process, so global sums and top-N lists count it once (VTK's pieces
// of image data share their boundary layer, and ghost layers overlap more).
#pragma once

#include "ImageGrid.h"

#include <array>
#include <cstddef>
#include <cstdint>

namespace mcv
{

struct GridPiece
{
  std::array<int, 3> wholeDims{ 0, 0, 0 }; // voxels of the whole volume
  std::array<int, 3> offset{ 0, 0, 0 };    // whole-volume index of the block's voxel (0,0,0)
  std::array<int, 3> ownedLo{ 0, 0, 0 };   // owned voxels, block indices, inclusive
  std::array<int, 3> ownedHi{ -1, -1, -1 };

  // The whole volume as one block owned by one process.
  static GridPiece whole(const ImageGrid& grid)
  {
    GridPiece p;
    p.wholeDims = grid.dims;
    for (int a = 0; a < 3; ++a)
    {
      p.ownedHi[a] = grid.dims[a] - 1;
    }
    return p;
  }

  // True when the block is the whole volume and all of it is owned (the serial case).
  bool isWhole(const ImageGrid& block) const
  {
    for (int a = 0; a < 3; ++a)
    {
      if (offset[a] != 0 || block.dims[a] != wholeDims[a] || ownedLo[a] != 0 ||
        ownedHi[a] != block.dims[a] - 1)
      {
        return false;
      }
    }
    return true;
  }

  bool owns(int i, int j, int k) const
  {
    return i >= ownedLo[0] && i <= ownedHi[0] && j >= ownedLo[1] && j <= ownedHi[1] &&
      k >= ownedLo[2] && k <= ownedHi[2];
  }

  std::size_t ownedCount() const
  {
    std::size_t n = 1;
    for (int a = 0; a < 3; ++a)
    {
      n *= ownedHi[a] >= ownedLo[a] ? static_cast<std::size_t>(ownedHi[a] - ownedLo[a] + 1) : 0;
    }
    return n;
  }

  // Block linear index (x fastest) -> linear index in the whole volume.
  std::int64_t globalIndex(std::int64_t blockIndex, const ImageGrid& block) const
  {
    const std::int64_t nx = block.dims[0], nxy = nx * block.dims[1];
    const std::int64_t k = blockIndex / nxy, rest = blockIndex - k * nxy;
    const std::int64_t j = rest / nx, i = rest - j * nx;
    return (i + offset[0]) +
      static_cast<std::int64_t>(wholeDims[0]) *
      ((j + offset[1]) + static_cast<std::int64_t>(wholeDims[1]) * (k + offset[2]));
  }
};

} // namespace mcv
