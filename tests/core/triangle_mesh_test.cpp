#include "mesh/triangle_mesh.h"
#include <gtest/gtest.h>

namespace hb {
namespace {

TriangleMesh unit_tetrahedron() {
  TriangleMesh m;
  m.positions = {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0), Vec3(0, 0, 1)};
  m.triangles = {{0, 2, 1}, {0, 1, 3}, {0, 3, 2}, {1, 2, 3}};
  m.compute_vertex_normals();
  return m;
}

TEST(TriangleMeshTest, VertexNormalsAreUnitAndPointOutward) {
  TriangleMesh m = unit_tetrahedron();
  const Vec3 centroid(0.25f, 0.25f, 0.25f);
  for (std::size_t i = 0; i < m.positions.size(); ++i) {
    EXPECT_NEAR(m.normals[i].norm(), 1.f, 1e-5f);
    EXPECT_GT(m.normals[i].dot(m.positions[i] - centroid), 0.f);
  }
}

TEST(TriangleMeshTest, AreaAndBoundsOfTetrahedron) {
  TriangleMesh m = unit_tetrahedron();
  EXPECT_NEAR(m.area(), 1.5 + std::sqrt(3.0) / 2.0, 1e-6);
  EXPECT_NEAR(m.bounds().diagonal(), std::sqrt(3.f), 1e-6f);
}

} // namespace
} // namespace hb
