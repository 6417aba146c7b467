// Out-of-sample placement (dissertation section 5.4.2): a voxel x is placed by its 3
// nearest reference vectors x_1..x_3 in feature space, with barycentric weights
//   w = argmin |x - sum w_i x_i|^2  subject to  sum w_i = 1,
// solved as LLE does: G_ij = (x - x_i).(x - x_j), (G + r I) w = 1, w /= sum w, with
// r = 1e-3 * trace(G) (a small ridge for collinear or coincident neighbours), and
//   y = sum w_i y_i.
// A voxel whose feature vector equals a reference vector exactly is given that reference
// point's embedding exactly (so reference points land on themselves).
#pragma once

#include "Embedding.h"
#include "FeatureKnn.h"

#include <cstddef>
#include <vector>

namespace mcv
{

struct OutOfSampleOptions
{
  int neighbors = 3;
  double regularization = 1e-3;
  StageProgress progress; // called from the calling thread only
};

// refX: M x D reference features (distinct rows), refY: M x d their embedding.
// rows: n x dim row-major (any layout of the features: `columns` picks the D used, in the
// order of refX's columns; empty means all dim == D). out: n x d row-major. OpenMP over rows.
void placeOutOfSample(const RowMatrixF& refX, const RowMatrixF& refY, const float* rows, std::size_t n, int dim,
  const std::vector<int>& columns, float* out, const OutOfSampleOptions& options = {});

} // namespace mcv
