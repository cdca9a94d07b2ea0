#pragma once
// Topology and geometry checks shared by the mesh tests.
#include "mesh/triangle_mesh.h"

#include <algorithm>
#include <cstdint>
#include <utility>
#include <vector>

namespace hb::test {

/// True when every undirected edge has exactly two triangles and they traverse it in
/// opposite directions (closed, manifold along edges, consistently oriented).
inline bool is_watertight(const TriangleMesh& mesh) {
  std::vector<std::pair<std::uint32_t, std::uint32_t>> directed;
  directed.reserve(3 * mesh.triangle_count());
  for (const Triangle& t : mesh.triangles)
    for (int k = 0; k < 3; ++k) directed.emplace_back(t[k], t[(k + 1) % 3]);
  std::sort(directed.begin(), directed.end());
  if (std::adjacent_find(directed.begin(), directed.end()) != directed.end()) return false;  // same direction twice
  for (const auto& [a, b] : directed)
    if (!std::binary_search(directed.begin(), directed.end(), std::make_pair(b, a))) return false;  // boundary
  return true;
}

/// Signed enclosed volume (divergence theorem); > 0 for an outward-oriented closed mesh.
inline double signed_volume(const TriangleMesh& mesh) {
  double v = 0.0;
  for (const Triangle& t : mesh.triangles) {
    const Eigen::Vector3d a = mesh.positions[t[0]].cast<double>();
    const Eigen::Vector3d b = mesh.positions[t[1]].cast<double>();
    const Eigen::Vector3d c = mesh.positions[t[2]].cast<double>();
    v += a.dot(b.cross(c)) / 6.0;
  }
  return v;
}

/// True when every normal has unit length.
inline bool normals_are_unit(const TriangleMesh& mesh) {
  if (mesh.normals.size() != mesh.positions.size()) return false;
  return std::all_of(mesh.normals.begin(), mesh.normals.end(),
                     [](const Vec3& n) { return std::abs(n.norm() - 1.f) < 1e-4f; });
}

} // namespace hb::test
