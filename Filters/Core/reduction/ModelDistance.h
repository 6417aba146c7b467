// How far a voxel lies from a reduction model (ReductionModel.h): the distance of its
// feature vector to the nearest reference vector, in units of the model's referenceRadius.
// A voxel of a later volume that no reference resembles (a new tissue, an artefact) gets a
// large value instead of silently taking the colour of the nearest known one.
#pragma once

#include "Embedding.h"
#include "ExactKnn.h"

#include <cstddef>
#include <cstdint>
#include <vector>

namespace mcv
{

// The largest distance of a reference to its 3rd nearest other reference (the references
// are distinct rows): the farthest the fit itself reaches for the 3 neighbours a voxel is
// placed by. 0 for fewer than 4 references.
double referenceRadius(const RowMatrixF& refX);

// out[r] = |row r - nearest reference| / radius (float; radius 0: 0 for an exact match,
// +inf otherwise). `rows` n x dim row-major, `columns` the dim columns the references use
// (empty: all, dim == D). `nearest` (optional, n entries): each row's nearest reference as
// the placement found it (its first neighbour); without it the index is searched (k = 1,
// the canonical rule of ExactKnn.h). Returns the rows beyond kOutOfModelRatio. OpenMP.
std::size_t modelDistances(const RowMatrixF& refX, const ExactKnn* index, double radius, const float* rows,
  std::size_t n, int dim, const std::vector<int>& columns, const std::uint32_t* nearest, std::size_t nearestStride,
  float* out);

} // namespace mcv
