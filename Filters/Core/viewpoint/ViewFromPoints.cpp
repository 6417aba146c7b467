#include "ViewFromPoints.h"

#include <Eigen/Dense>

#include <algorithm>
#include <cmath>

namespace mcv
{

namespace
{

// Flip so that the largest-magnitude component is positive: eigenvectors are only
// defined up to sign, and a fixed rule makes results reproducible across CPU and GPU.
Vec3 canonicalSign(const Eigen::Vector3d& v)
{
  int largest = 0;
  for (int a = 1; a < 3; ++a)
  {
    if (std::abs(v[a]) > std::abs(v[largest]))
    {
      largest = a;
    }
  }
  const double s = v[largest] < 0 ? -1.0 : 1.0;
  return { s * v[0], s * v[1], s * v[2] };
}

} // namespace

ViewDirections computeViewDirections(const std::vector<Vec3>& points)
{
  ViewDirections result;
  const std::size_t n = points.size();
  if (n < 3)
  {
    result.message = "at least 3 interest points are needed for a view direction, got " +
      std::to_string(n);
    return result;
  }
  Eigen::Vector3d mean = Eigen::Vector3d::Zero();
  for (const Vec3& p : points)
  {
    mean += Eigen::Vector3d(p[0], p[1], p[2]);
  }
  mean /= static_cast<double>(n);
  Eigen::Matrix3d covariance = Eigen::Matrix3d::Zero();
  for (const Vec3& p : points)
  {
    const Eigen::Vector3d d = Eigen::Vector3d(p[0], p[1], p[2]) - mean;
    covariance.noalias() += d * d.transpose();
  }
  covariance /= static_cast<double>(n);
  result.center = { mean[0], mean[1], mean[2] };

  // Eigen sorts eigenvalues ascending: column 0 is v3 (least variance), column 2 is v1.
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> solver(covariance);
  if (solver.info() != Eigen::Success)
  {
    result.message = "the eigen-decomposition of the interest points' covariance failed";
    return result;
  }
  const Eigen::Vector3d values = solver.eigenvalues().cwiseMax(0.0);
  const double total = values.sum();
  if (!(total > 0.0) || !std::isfinite(total))
  {
    result.message = "all interest points coincide: no direction is preferred";
    return result;
  }
  const Eigen::Matrix3d vectors = solver.eigenvectors();
  result.best = canonicalSign(vectors.col(0));
  result.viewUp = canonicalSign(vectors.col(1));
  result.worst = canonicalSign(vectors.col(2));
  result.eigenvalues = { values[2] / total, values[1] / total, values[0] / total };
  result.valid = true;
  if (values[1] <= 1e-12 * total)
  {
    result.message = "the interest points are collinear: every direction perpendicular to "
                     "the worst one is equally good";
  }
  return result;
}

std::vector<Vec3> worldPositions(const InterestPoints& points, const ImageGrid& grid)
{
  std::vector<Vec3> out;
  out.reserve(points.size());
  for (const std::int64_t index : points.indices)
  {
    out.push_back(grid.worldPosition(index));
  }
  return out;
}

double axisAngleDegrees(const Vec3& a, const Vec3& b)
{
  const double na = std::sqrt(a[0] * a[0] + a[1] * a[1] + a[2] * a[2]);
  const double nb = std::sqrt(b[0] * b[0] + b[1] * b[1] + b[2] * b[2]);
  if (!(na > 0.0) || !(nb > 0.0))
  {
    return 0.0;
  }
  const double c = std::abs(a[0] * b[0] + a[1] * b[1] + a[2] * b[2]) / (na * nb);
  return std::acos(std::min(1.0, c)) * 180.0 / 3.14159265358979323846;
}

} // namespace mcv
