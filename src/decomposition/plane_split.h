#pragma once
// Manual decomposition by user planes.
#include "mesh/triangle_mesh.h"
#include <cstdint>
#include <vector>

namespace hb {

/// A cutting plane through `point` with normal `normal` (model units; need not be unit).
struct CutPlane {
  Vec3 point{Vec3::Zero()};
  Vec3 normal{Vec3::UnitZ()};
};

/// Splits the triangles by the side of every plane their centroid lies on: two triangles
/// share a piece when they had the same id in `base` (empty: all one piece) and lie on the
/// same side of every plane. Ids are renumbered 0..K-1 in order of each piece's lowest
/// triangle id. Throws hb::InvalidInput on a zero or non-finite normal or when `base` has
/// the wrong size.
std::vector<std::uint32_t> split_by_planes(const TriangleMesh& mesh, const std::vector<CutPlane>& planes,
                                           const std::vector<std::uint32_t>& base = {});

/// Renumbers piece ids to 0..K-1 in order of first appearance; returns K.
std::size_t compact_piece_ids(std::vector<std::uint32_t>& piece_of_triangle);

} // namespace hb
