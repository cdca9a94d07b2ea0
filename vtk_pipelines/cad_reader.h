#pragma once
// CAD solids (STEP, IGES) through OpenCASCADE, tessellated for haptics: no finer than the force
// budget can feel (see CadOptions in model_loader.h for the rule).
#include "model_loader.h"
#include "mesh/triangle_mesh.h"
#include <nlohmann/json.hpp>
#include <cstdint>
#include <string>
#include <vector>

namespace hb::vtk {

/// A tessellated CAD model in millimetres.
struct CadModel {
  TriangleMesh mesh;                    ///< faces merged at their shared edges (one watertight mesh per closed solid).
  std::vector<std::uint32_t> face_ids;  ///< the solid face each triangle comes from (0-based, file order).
  std::string format;                   ///< "STEP" or "IGES".
  /// solids, shells, faces (and by surface type), edges, bounding_box_mm, file_unit,
  /// chordal_deviation_mm and how it was chosen, tessellation_deflection_mm (the largest
  /// deflection OpenCASCADE reports for a face), triangles.
  nlohmann::json facts;
  std::vector<std::string> warnings;
};

/// Reads and tessellates a STEP (.step .stp) or IGES (.iges .igs) file with
/// BRepMesh_IncrementalMesh at the chordal deviation of `options`. OpenCASCADE converts the
/// file's length unit to millimetres. Throws hb::IoError (missing) or hb::InvalidInput naming
/// the file: unreadable, no solid and no surface, absurd size, or faces lost (the file defines
/// more faces than the transfer produced, or a face gave no triangles), counted, unless
/// options.accept_lost_faces (then a warning). Run it through load_model, which isolates it:
/// OpenCASCADE crashes on some damaged files.
CadModel read_cad(const std::string& path, const CadOptions& options);

/// Writes the solids used as a known reference (tests, datasets), as STEP: a cylinder of radius
/// `radius_mm` and height `height_mm` standing on the origin along z (3 faces), and a sphere of
/// radius `radius_mm` centred at (3 radius, 0, height / 2) (1 face). Throws hb::IoError when the
/// write fails.
void write_reference_solid_step(const std::string& path, double radius_mm, double height_mm);

/// The same two solids as IGES (BRep mode: a manifold solid of shells and faces, entity types
/// 186/514/510, in millimetres), the sphere's surface converted to a B-spline surface (entity
/// 128) so that the file exercises the B-spline reader. Throws hb::IoError when the write fails.
void write_reference_solid_iges(const std::string& path, double radius_mm, double height_mm);

/// Writes a STEP file holding only a vertex (no solid, no surface), for the bad-input tests.
void write_vertex_only_step(const std::string& path);

} // namespace hb::vtk
