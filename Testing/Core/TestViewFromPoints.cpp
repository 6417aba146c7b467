// PCA of point positions: analytic cases with known principal axes.
#include "ViewFromPoints.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

namespace
{

using mcv::Vec3;

TEST(ViewFromPoints, PointsOnTiltedPlaneGiveItsNormal)
{
  const Vec3 normal = { 1 / std::sqrt(14.0), 2 / std::sqrt(14.0), 3 / std::sqrt(14.0) };
  // Two in-plane axes orthogonal to the normal.
  const Vec3 u = { 2 / std::sqrt(5.0), -1 / std::sqrt(5.0), 0 };
  const Vec3 w = { normal[1] * u[2] - normal[2] * u[1], normal[2] * u[0] - normal[0] * u[2],
    normal[0] * u[1] - normal[1] * u[0] };
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> coord(-10, 10);
  std::vector<Vec3> points;
  for (int i = 0; i < 500; ++i)
  {
    const double a = coord(rng), b = coord(rng);
    points.push_back({ 5 + a * u[0] + b * w[0], -3 + a * u[1] + b * w[1], 2 + a * u[2] + b * w[2] });
  }
  const mcv::ViewDirections view = mcv::computeViewDirections(points);
  ASSERT_TRUE(view.valid);
  EXPECT_LT(mcv::axisAngleDegrees(view.best, normal), 1e-6);
  EXPECT_NEAR(view.eigenvalues[2], 0.0, 1e-12);
  EXPECT_NEAR(view.eigenvalues[0] + view.eigenvalues[1] + view.eigenvalues[2], 1.0, 1e-12);
  EXPECT_NEAR(view.center[0], 5.0, 1.0);
}

TEST(ViewFromPoints, RodGivesWorstAlongRod)
{
  const Vec3 axis = { 0.0, 0.6, 0.8 };
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> along(-20, 20), across(-0.5, 0.5);
  std::vector<Vec3> points;
  for (int i = 0; i < 300; ++i)
  {
    const double t = along(rng);
    points.push_back({ t * axis[0] + across(rng), t * axis[1] + across(rng), t * axis[2] + across(rng) });
  }
  const mcv::ViewDirections view = mcv::computeViewDirections(points);
  ASSERT_TRUE(view.valid);
  EXPECT_LT(mcv::axisAngleDegrees(view.worst, axis), 1.0);
  EXPECT_GT(view.eigenvalues[0], 0.95);
}

TEST(ViewFromPoints, BoxCornersGiveEqualEigenvalues)
{
  std::vector<Vec3> points;
  for (int c = 0; c < 8; ++c)
  {
    points.push_back({ c & 1 ? 1.0 : -1.0, c & 2 ? 1.0 : -1.0, c & 4 ? 1.0 : -1.0 });
  }
  const mcv::ViewDirections view = mcv::computeViewDirections(points);
  ASSERT_TRUE(view.valid);
  for (int i = 0; i < 3; ++i)
  {
    EXPECT_NEAR(view.eigenvalues[i], 1.0 / 3.0, 1e-12);
  }
}

TEST(ViewFromPoints, DirectionsAreOrthonormalWithCanonicalSign)
{
  std::mt19937 rng(11);
  std::normal_distribution<double> g(0, 1);
  std::vector<Vec3> points;
  for (int i = 0; i < 100; ++i)
  {
    points.push_back({ 3 * g(rng), 2 * g(rng) + g(rng), g(rng) });
  }
  const mcv::ViewDirections view = mcv::computeViewDirections(points);
  ASSERT_TRUE(view.valid);
  const Vec3* axes[3] = { &view.best, &view.viewUp, &view.worst };
  for (int a = 0; a < 3; ++a)
  {
    const Vec3& v = *axes[a];
    EXPECT_NEAR(v[0] * v[0] + v[1] * v[1] + v[2] * v[2], 1.0, 1e-12);
    int largest = 0;
    for (int c = 1; c < 3; ++c)
    {
      largest = std::abs(v[c]) > std::abs(v[largest]) ? c : largest;
    }
    EXPECT_GT(v[largest], 0.0);
    for (int b = a + 1; b < 3; ++b)
    {
      const Vec3& w = *axes[b];
      EXPECT_NEAR(v[0] * w[0] + v[1] * w[1] + v[2] * w[2], 0.0, 1e-12);
    }
  }
  EXPECT_GE(view.eigenvalues[0], view.eigenvalues[1]);
  EXPECT_GE(view.eigenvalues[1], view.eigenvalues[2]);
}

TEST(ViewFromPoints, TooFewOrCoincidentPointsAreInvalid)
{
  EXPECT_FALSE(mcv::computeViewDirections({}).valid);
  EXPECT_FALSE(mcv::computeViewDirections({ { 1, 2, 3 }, { 4, 5, 6 } }).valid);
  const mcv::ViewDirections same = mcv::computeViewDirections({ { 1, 1, 1 }, { 1, 1, 1 }, { 1, 1, 1 } });
  EXPECT_FALSE(same.valid);
  EXPECT_FALSE(same.message.empty());
  for (double e : same.eigenvalues)
  {
    EXPECT_FALSE(std::isnan(e));
  }
}

} // namespace
