// The GPU placement's reference tiles (OutOfSampleCuda.cu, "Tile pruning"), built on the
// host when the references are uploaded: the references reordered so that each tile of
// kReferenceTile consecutive ones is compact, and per tile what the candidate kernel tests
// before it scans one (centroid, bounding box, largest norm) plus every reference's squared
// norm (the dot-product filter). Plain C++ so that it is tested without a GPU.
#pragma once

#include <cstddef>
#include <vector>

namespace mcv
{
namespace cuda
{

// References per tile: 32, as many as a warp has lanes; of 16, 32 and 64, 32 placed the
// brain's rows fastest.
constexpr int kReferenceTile = 32;

struct ReferenceTiles
{
  std::vector<unsigned> order; // sorted position -> original reference index
  // Per tile, DP floats each (the coordinates padded with zeros to DP): the centroid and the
  // box [lo, hi] (the exact float minimum and maximum of each coordinate over the tile's
  // references); a tile with a value that is not finite gets an infinite box and radius.
  std::vector<float> centroids, lo, hi;
  std::vector<float> centroidNorms; // per tile: |centroid|^2 (double sum rounded to float)
  std::vector<float> radius;        // per tile: the largest |r|, rounded up to a float
  std::vector<float> norms;         // per reference, in tile order: |r|^2 (double sum rounded)

  std::size_t tiles() const { return radius.size(); }
};

// X: M x D row-major; DP >= D the padded dimension of the kernels.
ReferenceTiles buildReferenceTiles(const float* X, std::size_t M, int D, int DP);

} // namespace cuda
} // namespace mcv
