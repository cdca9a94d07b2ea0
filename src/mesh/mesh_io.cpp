// read_mesh / write_mesh: the format follows the extension; one file per format does the
// parsing, mesh_validation.cpp the checks every format shares.
//
// Reading, in order:
//  1. Check the extension (case-insensitive) and the file itself: missing, directory, empty.
//  2. Load a polygon soup (positions + index lists), not a half-edge mesh, so nothing is lost:
//     off_reader.cpp, obj_reader.cpp, stl_reader.cpp, ply_reader.cpp (strict parsers of our
//     own: declared counts checked against the file, every value parsed, lines named; OFF,
//     the format of big models here, is parsed in parallel from a mapped file) and
//     om_reader.cpp (OpenMesh's half-edge format, through OpenMesh).
//  3. Validate: finite coordinates within kMaxCoordinate, indices in range (else
//     hb::InvalidInput).
//  4. Fan-triangulate polygons, drop and count degenerate triangles (repeated index, zero area).
//  5. Edge analysis: open, non-manifold, inconsistent orientation (warnings in the report).
//  6. Compute vertex normals.
//
// Writing: mesh_writers.cpp (OFF directly, other formats through OpenMesh).
#include "mesh/mesh_io.h"

#include "mesh/mapped_file.h"
#include "mesh/mesh_readers.h"
#include "mesh/mesh_validation.h"
#include "mesh/mesh_writers.h"

#include "errors.h"

#include <algorithm>
#include <filesystem>
#include <fstream>

namespace hb {
namespace {

namespace fs = std::filesystem;

std::string lower(std::string s) {
  std::transform(s.begin(), s.end(), s.begin(), [](unsigned char c) { return char(std::tolower(c)); });
  return s;
}

enum class Format { Off, Obj, Ply, Stl, Om };

Format format_of(const std::string& path) {
  const std::string ext = lower(fs::path(path).extension().string());
  if (ext == ".off") return Format::Off;
  if (ext == ".obj") return Format::Obj;
  if (ext == ".ply") return Format::Ply;
  if (ext == ".stl") return Format::Stl;
  if (ext == ".om") return Format::Om;
  throw InvalidInput(path + ": unknown mesh extension '" + ext +
                     "' (expected .off, .obj, .ply, .stl or .om)");
}

detail::PolygonSoup read_soup(const std::string& path, Format format, MeshReadReport& report) {
  switch (format) {
  case Format::Off: return detail::read_off(path, detail::MappedFile(path), report);
  case Format::Obj: return detail::read_obj(path, report);
  case Format::Ply: return detail::read_ply(path, report);
  case Format::Stl: return detail::read_stl(path, report);
  case Format::Om: return detail::read_om(path, report);
  }
  throw InvalidInput(path + ": unknown mesh format");
}

} // namespace

TriangleMesh read_mesh(const std::string& path, MeshReadReport* report_out) {
  const Format format = format_of(path);
  detail::check_readable_file(path);
  MeshReadReport report;
  detail::PolygonSoup soup = read_soup(path, format, report);
  TriangleMesh mesh = detail::triangulate(path, soup, report);
  detail::analyse_edges(path, mesh, report);
  mesh.compute_vertex_normals();
  if (report_out) *report_out = std::move(report);
  return mesh;
}

void write_mesh(const TriangleMesh& mesh, const std::string& path) {
  Format format;
  try {
    format = format_of(path);
  } catch (const InvalidInput& e) {
    throw IoError(e.what());
  }
  // OpenMesh's STL writer reports success even when it cannot create the file: probe first.
  if (!std::ofstream(path, std::ios::binary | std::ios::trunc))
    throw IoError(path + ": cannot open for writing (missing folder or permission)");
  const auto n = mesh.positions.size();
  for (const Triangle& t : mesh.triangles)
    for (auto v : t)
      if (v >= n) throw InvalidInput(path + ": cannot write: triangle index " + std::to_string(v) + " out of range");
  if (format == Format::Off) detail::write_off(mesh, path);
  else detail::write_with_openmesh(mesh, path, format == Format::Stl || format == Format::Ply || format == Format::Om);
}

} // namespace hb
