// Comparing two embeddings of the same points (CPU vs GPU UMAP layouts): shared by the GPU
// tests and the UMAP benchmark.
#pragma once

#include "Embedding.h"

#include <Eigen/Dense>

namespace mcv
{
namespace testing
{

// scipy.spatial.procrustes's disparity: 1 - (sum of the singular values of A^T B)^2 after
// centring and scaling each layout to unit Frobenius norm; 0 for layouts equal up to
// rotation, reflection, scale and translation.
inline double procrustesDisparity(const RowMatrixF& a, const RowMatrixF& b)
{
  Eigen::MatrixXd A = a.cast<double>(), B = b.cast<double>();
  A.rowwise() -= A.colwise().mean();
  B.rowwise() -= B.colwise().mean();
  A /= A.norm();
  B /= B.norm();
  const Eigen::JacobiSVD<Eigen::MatrixXd> svd(A.transpose() * B);
  const double s = svd.singularValues().sum();
  return 1.0 - s * s;
}

} // namespace testing
} // namespace mcv
