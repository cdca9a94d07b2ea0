#pragma once
// The raw result of a mesh reader, before validation: positions and polygons as read.
// Internal to src/mesh (the readers and mesh_validation.cpp); callers use mesh_io.h.
#include "mesh/triangle_mesh.h"

#include <cstddef>
#include <cstdint>
#include <vector>

namespace hb::detail {

/// Faces as flat index lists: face f has corners indices[offsets[f] .. offsets[f+1]).
/// Indices are kept as read (int64, possibly out of range): validation checks them. Every
/// face listed has 3 or more corners (readers count shorter ones in short_faces instead).
struct PolygonSoup {
  std::vector<Vec3> positions;
  std::vector<std::int64_t> indices;
  std::vector<std::size_t> offsets{0};
  std::size_t short_faces = 0;  ///< faces with fewer than 3 corners (skipped).

  std::size_t face_count() const { return offsets.size() - 1; }
};

} // namespace hb::detail
