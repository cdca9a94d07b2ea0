#include "mesh/triangle_mesh.h"
#include "mesh/generators.h"
#include "mesh/triangle_adjacency.h"
#include <gtest/gtest.h>
#include <algorithm>

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

namespace hb {
namespace {

// Edge adjacency: two triangles are neighbours when they hold two common vertices (a shared
// edge), every row sorted without repeats; a non-manifold edge links all its triangles and a
// triangle holding a vertex twice still joins through its one real edge. Against all pairs.
TEST(TriangleMeshTest, EdgeAdjacencyLinksTheTrianglesSharingAnEdgeAsAllPairsSay) {
  TriangleMesh fan;  // three triangles on edge 0-1, a degenerate one (2, 2, 3), one apart
  fan.positions = {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0), Vec3(0, 0, 1), Vec3(0, -1, 0), Vec3(5, 5, 5),
                   Vec3(6, 5, 5), Vec3(5, 6, 5)};
  fan.triangles = {{0, 1, 2}, {1, 0, 3}, {0, 1, 4}, {2, 2, 3}, {5, 6, 7}, {2, 3, 0}};
  for (const TriangleMesh& mesh : {make_sphere(1.f, 2), make_torus(1.f, 0.3f, 12, 8), fan}) {
    const TriangleAdjacency adj = triangle_adjacency(mesh);
    ASSERT_EQ(adj.offsets.size(), mesh.triangle_count() + 1);
    for (std::uint32_t t = 0; t < mesh.triangle_count(); ++t) {
      std::vector<std::uint32_t> expect;
      for (std::uint32_t u = 0; u < mesh.triangle_count(); ++u) {
        if (u == t) continue;
        int common = 0;
        for (int a = 0; a < 3; ++a) {
          const std::uint32_t v = mesh.triangles[t][a];
          if (std::find(mesh.triangles[t].begin(), mesh.triangles[t].begin() + a, v) != mesh.triangles[t].begin() + a) continue;
          common += std::find(mesh.triangles[u].begin(), mesh.triangles[u].end(), v) != mesh.triangles[u].end();
        }
        if (common >= 2) expect.push_back(u);
      }
      EXPECT_EQ(std::vector<std::uint32_t>(adj.begin(t), adj.end(t)), expect) << "triangle " << t;
    }
  }
}

} // namespace
} // namespace hb
