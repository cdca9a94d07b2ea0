#pragma once
// Oriented bounding boxes: the PBB (positional bounding box) of a piece, paper section 3.
#include "mesh/triangle_mesh.h"
#include <Eigen/Core>
#include <cstdint>
#include <string>
#include <vector>

namespace hb {

/// An oriented box: centre, three unit axes (columns of `axes`, right-handed) and half
/// extents along them, model units.
struct Obb {
  Vec3 center{Vec3::Zero()};
  Eigen::Matrix3f axes{Eigen::Matrix3f::Identity()};
  Vec3 half{Vec3::Ones()};

  Vec3 to_local(const Vec3& p) const { return axes.transpose() * (p - center); }
  Vec3 to_world(const Vec3& q) const { return center + axes * q; }
  float diagonal() const { return 2.f * half.norm(); }
  float volume() const { return 8.f * half.x() * half.y() * half.z(); }
};

/// Why `box` cannot be queried, or an empty string when it can: every value finite, half
/// extents in [1e-30, 4 kMaxCoordinate], |centre| <= 4 kMaxCoordinate, axes orthonormal and
/// right-handed within 1e-3 (|A^T A - I| per entry, det > 0). Box files are checked with it
/// at load; a box that fails it would make the query's cell arithmetic meaningless.
std::string obb_problem(const Obb& box);

/// Options of fit_obb.
struct ObbOptions {
  /// Padding added to every half extent, as a fraction of the fitted box's diagonal, so no
  /// surface touches a face (rays from the face start outside the piece). >= 0.
  float padding = 0.01f;
  /// Rounds of the local rotation search that shrinks the PCA box's volume (0: plain PCA).
  int refine_iterations = 24;
};

/// Tight oriented box of the given triangles of `mesh` (all when `triangles` is empty).
/// Starts from the principal axes of the surface (area-weighted covariance of the triangles,
/// Gottschalk et al. 1996, which for a closed piece approximates that of its convex hull),
/// then rotates about each axis by shrinking steps while the volume drops, so the result is
/// never larger than the PCA box. Throws hb::InvalidInput on an empty selection.
Obb fit_obb(const TriangleMesh& mesh, const std::vector<std::uint32_t>& triangles = {},
            const ObbOptions& options = {});

/// Intersection of the infinite line p + t*dir (unit dir) with the box: the entry and exit
/// parameters and the entry face (0..5 = -x,+x,-y,+y,-z,+z in box axes). Returns false when
/// the line misses the box.
struct LineBoxHit {
  float t_enter = 0.f;
  float t_exit = 0.f;
  int enter_face = 0;
};
bool intersect_line_obb(const Obb& box, const Vec3& p, const Vec3& dir, LineBoxHit& hit) noexcept;

} // namespace hb
