#include "errors.h"
#include "geometry/obb.h"
#include "geometry/convex_hull.h"
#include "mesh/generators.h"
#include <Eigen/Geometry>
#include <gtest/gtest.h>
#include <random>

namespace hb {
namespace {

TEST(ObbFitTest, RotatedBoxIsRecoveredTightly) {
  TriangleMesh cube = make_cube(Vec3(2.f, 1.f, 0.5f), 2);
  const Eigen::Matrix3f rot = (Eigen::AngleAxisf(0.5f, Vec3(1, 2, 3).normalized())).toRotationMatrix();
  for (auto& p : cube.positions) p = rot * p + Vec3(1.f, -2.f, 3.f);
  ObbOptions options;
  options.padding = 0.f;
  const Obb box = fit_obb(cube, {}, options);
  EXPECT_NEAR(box.volume(), 8.f, 0.08f);
  EXPECT_NEAR((box.center - Vec3(1.f, -2.f, 3.f)).norm(), 0.f, 1e-3f);
}

TEST(ObbFitTest, PaddedBoxContainsEveryVertexStrictly) {
  const TriangleMesh torus = make_torus(1.f, 0.3f, 24, 12);
  const Obb box = fit_obb(torus);
  for (const Vec3& p : torus.positions) {
    const Vec3 q = box.to_local(p);
    for (int a = 0; a < 3; ++a) EXPECT_LT(std::fabs(q[a]), box.half[a]);
  }
  EXPECT_NEAR(box.axes.determinant(), 1.f, 1e-4f);
}

TEST(ObbFitTest, EmptySelectionIsRejected) {
  EXPECT_THROW(fit_obb(TriangleMesh{}), InvalidInput);
}

TEST(LineObbTest, EntryFaceAndParametersAreCorrect) {
  Obb box;
  box.half = Vec3(1.f, 2.f, 3.f);
  LineBoxHit hit;
  ASSERT_TRUE(intersect_line_obb(box, Vec3(0.f, 0.f, 10.f), Vec3(0.f, 0.f, -1.f), hit));
  EXPECT_EQ(hit.enter_face, 5);
  EXPECT_FLOAT_EQ(hit.t_enter, 7.f);
  EXPECT_FLOAT_EQ(hit.t_exit, 13.f);
  EXPECT_FALSE(intersect_line_obb(box, Vec3(5.f, 0.f, 10.f), Vec3(0.f, 0.f, -1.f), hit));
}

// The hull's candidates hold the extreme point of a large set along every direction tried
// (so fit_obb's search over them sees the extents it would over all points), and far fewer
// points; a flat set (no hull in 3D) and a small one come back whole.
TEST(ConvexHullTest, HullCandidatesHoldEveryExtremePointOfTheSet) {
  std::mt19937 rng(5);
  std::normal_distribution<float> g(0.f, 1.f);
  std::uniform_real_distribution<float> u(0.f, 1.f);
  std::vector<Vec3> points;
  for (int i = 0; i < 20000; ++i) {
    const Vec3 d = Vec3(g(rng), g(rng), g(rng)).normalized();
    points.push_back(d.cwiseProduct(Vec3(3.f, 2.f, 1.f)) * std::cbrt(u(rng)));  // a solid ellipsoid
  }
  const std::vector<Vec3> hull = hull_candidates(points);
  EXPECT_LT(hull.size(), points.size() / 4);
  for (int k = 0; k < 2000; ++k) {
    const Vec3 d = Vec3(g(rng), g(rng), g(rng)).normalized();
    float all = -1e30f, some = -1e30f;
    for (const Vec3& p : points) all = std::max(all, p.dot(d));
    for (const Vec3& p : hull) some = std::max(some, p.dot(d));
    ASSERT_EQ(some, all) << k;
  }
  std::vector<Vec3> flat;
  for (int i = 0; i < 5000; ++i) flat.push_back(Vec3(u(rng), u(rng), 0.5f));
  EXPECT_EQ(hull_candidates(flat).size(), flat.size());
  const std::vector<Vec3> few(points.begin(), points.begin() + 100);
  EXPECT_EQ(hull_candidates(few).size(), few.size());
}

// A box fitted through the hull (a mesh of more than 4096 vertices) holds every vertex.
TEST(ObbTest, ABoxFittedThroughTheHullHoldsEveryVertex) {
  const TriangleMesh mesh = make_sphere(1.f, 5);
  ASSERT_GT(mesh.vertex_count(), 4096u);
  const Obb box = fit_obb(mesh, {});
  for (const Vec3& p : mesh.positions) {
    const Vec3 q = box.to_local(p);
    for (int a = 0; a < 3; ++a) EXPECT_LE(std::fabs(q[a]), box.half[a] * (1.f + 1e-5f));
  }
}

} // namespace
} // namespace hb
