#pragma once
// Two unit spheres on the x axis as one mesh, a piece id per triangle (0: the first, 1: the
// second): the smallest scene of several boxes.
#include "scene/bake.h"
#include "mesh/generators.h"
#include <cstdint>
#include <vector>

namespace hb::test {

struct TwoSpheres {
  TriangleMesh mesh;
  std::vector<std::uint32_t> piece;
};

/// The second sphere's centre at (dx, 0, 0); dx < 2 makes the pieces overlap.
inline TwoSpheres two_spheres(float dx) {
  TriangleMesh a = make_sphere(1.f, 4), b = make_sphere(1.f, 4);
  for (auto& p : b.positions) p.x() += dx;
  TwoSpheres out{a, {}};
  TriangleMesh& both = out.mesh;
  const auto offset = std::uint32_t(both.positions.size());
  both.positions.insert(both.positions.end(), b.positions.begin(), b.positions.end());
  both.normals.insert(both.normals.end(), b.normals.begin(), b.normals.end());
  for (auto t : b.triangles) both.triangles.push_back({t[0] + offset, t[1] + offset, t[2] + offset});
  out.piece.assign(both.triangle_count(), 0);
  for (std::size_t t = a.triangle_count(); t < both.triangle_count(); ++t) out.piece[t] = 1;
  return out;
}

/// The two spheres' scene baked refined (m 12, n 6): a scene grid, surface cells, the cells
/// route.
inline BoxScene refined_two_spheres(const TwoSpheres& two) {
  BakeOptions o;
  o.params = {12, 6};
  o.refine = true;
  return bake_scene(two.mesh, two.piece, o, SourceInfo{});
}

} // namespace hb::test
