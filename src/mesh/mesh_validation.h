#pragma once
// The checks every mesh read goes through, whatever the format: the file itself before
// parsing, then the parsed soup (coordinates, indices), triangulation with degenerate
// triangles dropped, and the edge analysis (open, non-manifold, orientation).
// Internal to src/mesh: read_mesh (mesh_io.h) runs them in order.
#include "mesh/mesh_io.h"
#include "mesh/polygon_soup.h"

#include <string>

namespace hb::detail {

/// Throws hb::IoError when `path` is missing, a directory, not a regular file, empty or
/// unreadable.
void check_readable_file(const std::string& path);

/// The whole file as bytes. Throws hb::IoError.
std::string read_whole_file(const std::string& path);

/// Validates the soup (finite coordinates, indices in range; else hb::InvalidInput), fan-
/// triangulates polygons and drops (and counts) degenerate triangles. Throws hb::InvalidInput
/// when no triangle is left. Consumes the soup (left empty: its memory is freed).
TriangleMesh triangulate(const std::string& path, PolygonSoup& soup, MeshReadReport& report);

/// Marks open / non-manifold / inconsistently oriented edges in the report (with warnings).
void analyse_edges(const std::string& path, const TriangleMesh& mesh, MeshReadReport& report);

} // namespace hb::detail
