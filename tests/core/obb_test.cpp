#include "errors.h"
#include "geometry/obb.h"
#include "mesh/generators.h"
#include <Eigen/Geometry>
#include <gtest/gtest.h>

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

} // namespace
} // namespace hb
