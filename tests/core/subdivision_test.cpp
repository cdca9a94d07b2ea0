#include "mesh/subdivision.h"

#include "errors.h"
#include "mesh/generators.h"
#include "mesh_checks.h"

#include <gtest/gtest.h>

namespace hb {
namespace {

TEST(SubdivisionTest, QuadruplesTrianglesAndKeepsShape) {
  const TriangleMesh torus = make_torus(2.f, 0.5f, 24, 12);
  const TriangleMesh fine = subdivide_midpoint(torus, 2);
  EXPECT_EQ(fine.triangle_count(), 16u * torus.triangle_count());
  // Closed genus-1 mesh: V - E + F = 0, so V = F / 2.
  EXPECT_EQ(fine.vertex_count(), fine.triangle_count() / 2);
  EXPECT_TRUE(test::is_watertight(fine));
  EXPECT_NEAR(fine.area(), torus.area(), 1e-5 * torus.area());
  EXPECT_NEAR(test::signed_volume(fine), test::signed_volume(torus), 1e-5 * test::signed_volume(torus));
  EXPECT_TRUE(test::normals_are_unit(fine));
}

TEST(SubdivisionTest, MidpointNormalIsRenormalisedMean) {
  const TriangleMesh sphere = make_sphere(1.f, 1);
  const TriangleMesh fine = subdivide_midpoint(sphere, 1);
  for (std::size_t v = sphere.vertex_count(); v < fine.vertex_count(); ++v) {
    // On a sphere the mean of the end normals points along the midpoint.
    EXPECT_GT(fine.normals[v].dot(fine.positions[v].normalized()), 0.9999f);
  }
  for (std::size_t v = 0; v < sphere.vertex_count(); ++v) EXPECT_EQ(fine.normals[v], sphere.normals[v]);
}

TEST(SubdivisionTest, LevelZeroIsACopy) {
  const TriangleMesh cube = make_cube(Vec3(1, 1, 1));
  const TriangleMesh same = subdivide_midpoint(cube, 0);
  EXPECT_EQ(same.triangles, cube.triangles);
  EXPECT_EQ(same.positions.size(), cube.positions.size());
}

TEST(SubdivisionTest, OpenMeshStaysValid) {
  TriangleMesh strip;
  strip.positions = {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0), Vec3(1, 1, 0)};
  strip.triangles = {{0, 1, 2}, {1, 3, 2}};
  const TriangleMesh fine = subdivide_midpoint(strip, 1);
  EXPECT_EQ(fine.triangle_count(), 8u);
  EXPECT_EQ(fine.vertex_count(), 9u);  // 4 + 5 distinct edges
  EXPECT_TRUE(test::normals_are_unit(fine));  // normals computed when the input had none
  EXPECT_NEAR(fine.area(), 1.0, 1e-6);
}

TEST(SubdivisionTest, LargeMeshThreeLevels) {
  // 52K triangles -> 3.4M in three levels (the brief's 13M case is one level more).
  const TriangleMesh base = make_torus(2.f, 0.5f, 256, 102);
  ASSERT_GE(base.triangle_count(), 52000u);
  const TriangleMesh fine = subdivide_midpoint(base, 3);
  EXPECT_EQ(fine.triangle_count(), 64u * base.triangle_count());
  EXPECT_EQ(fine.vertex_count(), fine.triangle_count() / 2);
}

TEST(SubdivisionTest, BadArgumentsAreInvalidInput) {
  const TriangleMesh cube = make_cube(Vec3(1, 1, 1));
  EXPECT_THROW(subdivide_midpoint(cube, -1), InvalidInput);
  EXPECT_THROW(subdivide_midpoint(cube, 16), InvalidInput);  // 12 * 4^16 overflows 32-bit indices
  TriangleMesh broken = cube;
  broken.triangles[0][0] = 1000;
  EXPECT_THROW(subdivide_midpoint(broken, 1), InvalidInput);
}

} // namespace
} // namespace hb
