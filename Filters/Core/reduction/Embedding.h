// What every embedding method (PCA, Isomap, LLE) returns for the reference sample, and
// the matrix type they read. Internal to the dimension-reduction code.
#pragma once

#include <Eigen/Core>

#include <functional>
#include <string>
#include <vector>

namespace mcv
{

// n x D feature vectors (or n x d coordinates), row-major float: one row per point.
using RowMatrixF = Eigen::Matrix<float, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;

// A method reports the fraction of its own work done, in [0,1].
using StageProgress = std::function<void(const char* stage, double fraction)>;

// The graph methods' neighbourhood size K must be at least 1 and less than the number of
// reference points n: empty when it is, else the error, named after `method`.
inline std::string neighboursError(const char* method, int K, std::size_t n)
{
  if (K >= 1 && static_cast<std::size_t>(K) < n)
  {
    return std::string();
  }
  return std::string(method) + ": the number of neighbours (" + std::to_string(K) +
    ") must be at least 1 and less than the number of reference points (" + std::to_string(n) + ").";
}

// Reports a stage's progress to `progress` when one is set (the fits' progress is optional).
inline void reportStage(const StageProgress& progress, const char* stage, double fraction)
{
  if (progress)
  {
    progress(stage, fraction);
  }
}

struct Embedding
{
  std::string error;                 // non-empty: nothing else is meaningful
  std::vector<std::string> warnings; // one line each
  RowMatrixF coordinates;            // n x d, one row per reference point
  std::vector<double> eigenvalues;   // the method's spectrum (see ReductionResult)
  double varianceRetained = 0.0;     // top-d / sum of positive eigenvalues (PCA, Isomap)
  // referenceRadius(X) (ModelDistance.h), where the method found it on the way (UMAP's exact
  // kNN graph holds every point's 3 nearest others), so it need not be searched again; -1
  // when not computed.
  double referenceRadius = -1.0;
};

// Makes each column's largest-magnitude entry positive: eigenvectors come with an
// arbitrary sign, and the same data should give the same picture.
void fixColumnSigns(Eigen::MatrixXd& columns);

// Centres the n x d points and rotates them to their principal axes (largest spread first),
// signs as fixColumnSigns: a rigid motion, so distances (and trustworthiness) stay.
void toPrincipalAxes(Eigen::MatrixXd& points);

} // namespace mcv
