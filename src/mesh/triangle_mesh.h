#pragma once
// The core's mesh: an indexed triangle list with per-vertex (shaded) normals.
#include "math/bounds.h"
#include "math/vec3.h"
#include <array>
#include <cstdint>
#include <vector>

namespace hb {

using Triangle = std::array<std::uint32_t, 3>;

/// Largest |coordinate| a mesh may have, in model units. Readers and the Embree scene refuse
/// anything beyond it (hb::InvalidInput): the rays of a bake start on boxes around the mesh
/// and must stay well inside Embree's valid range (|origin|, |direction| < 1.8e19; beyond it
/// Embree aborts the process).
constexpr float kMaxCoordinate = 1e15f;

/// Indexed triangle mesh in model units. `normals` holds one unit vertex normal per
/// position (area-weighted average of the incident face normals), used for shaded
/// normals at ray hits so forces vary smoothly across triangles.
struct TriangleMesh {
  std::vector<Vec3> positions;
  std::vector<Triangle> triangles;
  std::vector<Vec3> normals;

  std::size_t vertex_count() const { return positions.size(); }
  std::size_t triangle_count() const { return triangles.size(); }
  Bounds bounds() const;
  /// Recomputes `normals` from the triangles (area-weighted, unit length; zero-area
  /// neighbourhoods get +Z).
  void compute_vertex_normals();
  /// Total surface area in model units squared.
  double area() const;
};

/// Keeps the triangles whose ids are in `keep` (all vertices kept; unused ones harmless).
TriangleMesh select_triangles(const TriangleMesh& mesh, const std::vector<std::uint32_t>& keep);

} // namespace hb
