#pragma once
// Reading and writing meshes (OFF, OBJ, PLY, STL, OM): one reader per format under src/mesh/.
#include "mesh/file_hash.h"  // hash_file, declared here before it had its own file
#include "mesh/triangle_mesh.h"
#include <string>
#include <vector>

namespace hb {

/// What a read found and fixed. Warnings are human-readable and name the file.
struct MeshReadReport {
  std::size_t input_vertices = 0;
  std::size_t input_faces = 0;             ///< faces in the file, before triangulation.
  std::size_t polygons_triangulated = 0;   ///< faces with more than 3 corners.
  std::size_t degenerate_dropped = 0;      ///< zero-area or repeated-index triangles dropped.
  std::size_t faces_rejected = 0;          ///< faces skipped: fewer than 3 corners. Non-manifold
                                           ///< faces are kept (see non_manifold), never detached.
  bool open = false;                       ///< has boundary edges.
  bool non_manifold = false;               ///< has edges shared by more than two faces.
  bool inconsistent_orientation = false;   ///< has edges its two faces traverse the same way.
  std::vector<std::string> warnings;
};

/// Reads a mesh; the format follows the extension (.off .obj .ply .stl .om, any case).
/// Polygons are triangulated, degenerate triangles dropped and counted, vertex normals
/// computed. Open, non-manifold or inconsistently oriented meshes load with a warning in
/// `report`. OFF, OBJ, STL (ASCII and binary) and PLY (ASCII and binary) are parsed by strict
/// readers of our own: every declared count is checked against the file's size before
/// anything is reserved, every value must parse, errors name the line; an OBJ's mtllib is
/// never opened. OM goes through OpenMesh, whose messages are captured into
/// `report.warnings` instead of std::cerr.
/// Throws hb::IoError (missing, unreadable or empty file) or hb::InvalidInput (unknown
/// extension, garbage, NaN/Inf coordinates or |x| > kMaxCoordinate, out-of-range indices, no
/// triangles left); the message names the file and the cause. Never hangs on garbage input
/// and never allocates much more than the file's size.
TriangleMesh read_mesh(const std::string& path, MeshReadReport* report = nullptr);

/// Writes a mesh (format from the extension, as read_mesh). Throws hb::IoError.
void write_mesh(const TriangleMesh& mesh, const std::string& path);

} // namespace hb
