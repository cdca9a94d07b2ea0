#include "geometry/surface_fit.h"
#include <gtest/gtest.h>
#include <cmath>
#include <random>

namespace hb {
namespace {

// Points of a sphere (centre c, radius r) scattered around the direction d, with their normals.
int sphere_points(const Vec3& c, float r, const Vec3& d, float spread, int count, std::mt19937& rng,
                  OrientedPoint* out) {
  std::uniform_real_distribution<float> u(-1.f, 1.f);
  const Vec3 e1 = d.unitOrthogonal(), e2 = d.cross(e1);
  for (int i = 0; i < count; ++i) {
    const Vec3 n = (d + spread * (u(rng) * e1 + u(rng) * e2)).normalized();
    out[i] = {c + r * n, n, 0.5f + 0.5f * u(rng)};
  }
  return count;
}

TEST(SurfaceFitTest, APlaneAndAParaboloidAreFittedExactly) {
  // z = 0.3 + 0.2 x - 0.1 y - 0.5 x^2 + 0.25 x y - 0.75 y^2: a quadric, so the fit has no error.
  const auto height = [](float x, float y) { return 0.3f + 0.2f * x - 0.1f * y - 0.5f * x * x + 0.25f * x * y - 0.75f * y * y; };
  OrientedPoint points[16];
  int k = 0;
  for (int i = 0; i < 4; ++i)
    for (int j = 0; j < 4; ++j) {
      const float x = -0.3f + 0.2f * float(i), y = -0.3f + 0.2f * float(j);
      const Vec3 n = Vec3(-(0.2f - x + 0.25f * y), -(-0.1f + 0.25f * x - 1.5f * y), 1.f).normalized();
      points[k++] = {Vec3(x, y, height(x, y)), n, 1.f};
    }
  LocalQuadric q;
  ASSERT_TRUE(fit_local_quadric(points, 16, Vec3(0.05f, -0.02f, 0.f), Vec3::UnitZ(), 0.2f, 0.1f, q));
  // The line down through (0.05, -0.02) meets it at its height there.
  EXPECT_NEAR(q.c[0], height(0.05f, -0.02f), 2e-6);
  // A line descending at 80 degrees from the axis enters it where the height matches.
  const Vec3 l = Vec3(std::sin(1.4f), 0.f, -std::cos(1.4f)).normalized();
  const Vec3 start(-0.2f, 0.1f, 0.3f);  // 0.08 above the surface
  float s = 0.f;
  ASSERT_TRUE(q.entry(start, l, s));
  const Vec3 p = start + s * l;
  EXPECT_NEAR(p.z(), height(p.x(), p.y()), 2e-5f);
  const Vec3 n_at = q.normal_at(p);
  const Vec3 n_true = Vec3(-(0.2f - p.x() + 0.25f * p.y()), -(-0.1f + 0.25f * p.x() - 1.5f * p.y()), 1.f).normalized();
  EXPECT_LT(n_at.cross(n_true).norm(), 1.8e-4f);  // within 0.01 degrees
  EXPECT_LT(n_at.dot(l), 0.f);  // entering: against the line
}

TEST(SurfaceFitTest, ASphereSampledACellApartIsMetWithinAThousandthOfTheCell) {
  // Samples a cell (0.05 of the radius) apart: a blend of them is off by the sagitta, about
  // cell^2 / 8 r; the fit by the third-order terms only.
  std::mt19937 rng(7);
  const Vec3 c(1.f, -2.f, 0.5f);
  const float r = 2.f, cell = 0.1f;
  double worst = 0.0;
  for (int trial = 0; trial < 200; ++trial) {
    std::uniform_real_distribution<float> u(-1.f, 1.f);
    const Vec3 d = Vec3(u(rng), u(rng), u(rng)).normalized();
    OrientedPoint points[16];
    const int k = sphere_points(c, r, d, cell / r, 16, rng, points);
    // The line along -d from just outside, tilted by a few degrees.
    const Vec3 axis = (d + 0.05f * Vec3(u(rng), u(rng), u(rng))).normalized();
    const Vec3 origin = c + (r + 0.3f * cell) * d;
    LocalQuadric q;
    ASSERT_TRUE(fit_local_quadric(points, k, origin, axis, 0.4f * cell, 0.1f, q));
    // The line origin + z axis meets the sphere's near side at z = -b + sqrt(b^2 - |o|^2 + r^2).
    const Vec3 o = origin - c;
    const double b = double(o.dot(axis)), disc = b * b - double(o.squaredNorm()) + double(r) * double(r);
    ASSERT_GT(disc, 0.0);
    worst = std::max(worst, std::fabs(q.c[0] - (-b + std::sqrt(disc))));
  }
  EXPECT_LT(worst, 1e-3 * cell) << "worst " << worst;
}

TEST(SurfaceFitTest, ALinePassingAboveTheSurfaceDoesNotEnterIt) {
  LocalQuadric q;  // z = -x^2 - y^2 (a cap, outside +z)
  q.c[3] = q.c[5] = -1.0;
  float s = 0.f;
  // Horizontal at height 0.01: above the cap everywhere.
  EXPECT_FALSE(q.entry(Vec3(-1.f, 0.f, 0.01f), Vec3::UnitX(), s));
  // Its closest approach is above the apex.
  const LocalQuadric::Height h = q.height_along(Vec3(-1.f, 0.f, 0.01f), Vec3::UnitX());
  EXPECT_NEAR(-h.b / (2.0 * h.a), 1.0, 1e-9);
  // At height -0.01 it enters where x^2 = 0.01, going in (the first root).
  ASSERT_TRUE(q.entry(Vec3(-1.f, 0.f, -0.01f), Vec3::UnitX(), s));
  EXPECT_NEAR(s, 0.9f, 1e-5f);
  // From the other side, going -x: the same entry, mirrored.
  ASSERT_TRUE(q.entry(Vec3(1.f, 0.f, -0.01f), -Vec3::UnitX(), s));
  EXPECT_NEAR(s, 0.9f, 1e-5f);
  // Straight down: enters at the apex.
  ASSERT_TRUE(q.entry(Vec3(0.f, 0.f, 1.f), -Vec3::UnitZ(), s));
  EXPECT_NEAR(s, 1.f, 1e-6f);
  // Straight up from below: it only leaves.
  EXPECT_FALSE(q.entry(Vec3(0.f, 0.f, -1.f), Vec3::UnitZ(), s));
}

TEST(SurfaceFitTest, PointsOfAnotherWallAcrossACreaseAreLeftOutAndCounted) {
  // A 60 degree V: eight points on each wall. Seen along the right wall's normal the left
  // wall faces away (n . axis = -0.5): its points are left out, and `used` says so (a box's
  // refit refuses such a fit: step 6b).
  const Vec3 right(-0.866025f, 0.f, 0.5f), left(0.866025f, 0.f, 0.5f);
  const Vec3 up_right(0.5f, 0.f, 0.866025f), up_left(-0.5f, 0.f, 0.866025f);
  OrientedPoint points[16];
  for (int i = 0; i < 8; ++i) {
    const float d = 0.05f + 0.1f * float(i % 4), y = i < 4 ? -0.1f : 0.1f;
    points[i] = {d * up_right + Vec3(0.f, y, 0.f), right, 1.f};
    points[8 + i] = {d * up_left + Vec3(0.f, y, 0.f), left, 1.f};
  }
  LocalQuadric q;
  ASSERT_TRUE(fit_local_quadric(points, 16, 0.2f * up_right, right, 0.2f, 0.1f, q));
  EXPECT_EQ(q.used, 8);
  EXPECT_NEAR(q.c[0], 0.0, 1e-6);  // the right wall's plane through the origin
  ASSERT_TRUE(fit_local_quadric(points, 8, 0.2f * up_right, right, 0.2f, 0.1f, q));
  EXPECT_EQ(q.used, 8);
}

TEST(SurfaceFitTest, TooFewPointsOrABadScaleGiveNoFit) {
  OrientedPoint points[3] = {{Vec3(0, 0, 0), Vec3::UnitZ(), 1.f}, {Vec3(1, 0, 0), Vec3::UnitZ(), 1.f},
                             {Vec3(0, 1, 0), -Vec3::UnitZ(), 1.f}};  // the third faces away
  LocalQuadric q;
  EXPECT_FALSE(fit_local_quadric(points, 3, Vec3::Zero(), Vec3::UnitZ(), 1.f, 0.1f, q));
  points[2].normal = Vec3::UnitZ();
  EXPECT_TRUE(fit_local_quadric(points, 3, Vec3::Zero(), Vec3::UnitZ(), 1.f, 0.1f, q));
  EXPECT_FALSE(fit_local_quadric(points, 3, Vec3::Zero(), Vec3::UnitZ(), 0.f, 0.1f, q));
  EXPECT_FALSE(fit_local_quadric(points, 2, Vec3::Zero(), Vec3::UnitZ(), 1.f, 0.1f, q));
  points[1].point.x() = std::nanf("");
  EXPECT_FALSE(fit_local_quadric(points, 3, Vec3::Zero(), Vec3::UnitZ(), 1.f, 0.1f, q));
}

}  // namespace
}  // namespace hb
