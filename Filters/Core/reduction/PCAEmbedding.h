// PCA: eigen-decomposition of the covariance of the reference sample (D x D, D = number of
// features, so a dense Eigen solver is exact and instant). The model is a linear map, so
// every voxel is placed by projection rather than by the 3-neighbour interpolation.
#pragma once

#include "Embedding.h"

#include <cstdint>

namespace mcv
{

struct PCAModel
{
  Eigen::VectorXd mean; // D
  Eigen::MatrixXd axes; // D x d, unit columns, by decreasing variance
};

// `rows`: n x dim row-major; `sample`: the rows fitted on (empty: all); `columns`: the
// features used (empty: all). The embedding's coordinates are those of the sample rows.
Embedding fitPCA(const float* rows, std::size_t n, int dim, const std::vector<std::int64_t>& sample,
  const std::vector<int>& columns, int outputDimension, PCAModel* model);

// y = (x - mean) * axes for every row; out is n x d row-major. OpenMP over rows.
void projectPCA(const PCAModel& model, const float* rows, std::size_t n, int dim, const std::vector<int>& columns,
  float* out);

} // namespace mcv
