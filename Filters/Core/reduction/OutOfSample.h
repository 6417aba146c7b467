// Out-of-sample placement (dissertation section 5.4.2): a voxel x is placed by its 3
// nearest reference vectors x_1..x_3 in feature space, with barycentric weights
//   w = argmin |x - sum w_i x_i|^2  subject to  sum w_i = 1,
// solved as LLE does: G_ij = (x - x_i).(x - x_j), (G + r I) w = 1, w /= sum w, with
// r = 1e-3 * trace(G) (a small ridge for collinear or coincident neighbours), and
//   y = sum w_i y_i.
// A voxel whose feature vector equals a reference vector exactly is given that reference
// point's embedding exactly (so reference points land on themselves).
//
// The neighbours are exact under the canonical rule of ExactKnn.h (double distances, ties
// by index) on every path: kd-tree or tiled brute force on the CPU (by dimension), or the
// CUDA kernel (cuda/OutOfSampleCuda.h), so all of them place a voxel the same way.
#pragma once

#include "Device.h"
#include "Embedding.h"
#include "ExactKnn.h"

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace mcv
{

struct OutOfSampleOptions
{
  int neighbors = 3;
  double regularization = 1e-3;
  KnnMethod knn = KnnMethod::Auto; // the CPU backend
  // CPU: consecutive rows with equal features are searched once (same answer, bit for
  // bit); false searches every row (the benchmark's in-run baseline).
  bool mergeEqualRows = true;
  // GPU: the CUDA kernel; on any CUDA failure (out of memory included) the CPU path runs
  // and the report carries a warning. Auto is resolved by the caller (resolveDevice).
  Device device = Device::CPU;
  StageProgress progress; // called from the calling thread only
};

struct OutOfSampleReport
{
  Device deviceUsed = Device::CPU;
  KnnMethod knnUsed = KnnMethod::KdTree; // the CPU backend (when the CPU ran)
  std::size_t radiusScans = 0;           // rows whose float candidates needed a radius scan
  std::vector<std::string> warnings;
  double uploadMs = 0, computeMs = 0, downloadMs = 0; // GPU path only
};

// refX: M x D reference features (distinct rows), refY: M x d their embedding.
// rows: n x dim row-major (any layout of the features: `columns` picks the D used, in the
// order of refX's columns; empty means all dim == D). out: n x d row-major. OpenMP over rows.
// neighbors (optional, n x min(k, M)): the references each row was placed by.
OutOfSampleReport placeOutOfSample(const RowMatrixF& refX, const RowMatrixF& refY, const float* rows, std::size_t n,
  int dim, const std::vector<int>& columns, float* out, const OutOfSampleOptions& options = {},
  std::uint32_t* neighbors = nullptr);

} // namespace mcv
