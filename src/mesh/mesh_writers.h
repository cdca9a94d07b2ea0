#pragma once
// Mesh writers, one per target: OFF directly, the other formats through OpenMesh.
// Internal to src/mesh: callers use write_mesh (mesh_io.h).
#include "mesh/triangle_mesh.h"

#include <string>

namespace hb::detail {

/// OFF with the shortest text that reads back to the same floats. Throws hb::IoError.
void write_off(const TriangleMesh& mesh, const std::string& path);

/// OBJ, PLY, STL or OM (from the extension) through an OpenMesh TriMesh; `binary` for the
/// formats that have a binary form. Non-manifold triangles get their own corner copies.
/// Throws hb::IoError.
void write_with_openmesh(const TriangleMesh& mesh, const std::string& path, bool binary);

} // namespace hb::detail
