#pragma once
// One reader per mesh format, each returning the raw polygon soup and filling the report's
// input counts; read_mesh (mesh_io.cpp) picks one by extension, then validates
// (mesh_validation.h). Internal to src/mesh: callers use mesh_io.h.
// Each throws hb::IoError or hb::InvalidInput naming the file (and line) and the cause.
#include "mesh/mesh_io.h"
#include "mesh/polygon_soup.h"

#include <string>

namespace hb::detail {

class MappedFile;

/// OFF, strict parser of our own, parallel over chunks of lines (off_reader.cpp). `file`: the
/// whole file; the pages of the parsed part are released from the resident set as it goes.
PolygonSoup read_off(const std::string& path, const MappedFile& file, MeshReadReport& report);
/// Wavefront OBJ, strict parser of our own (obj_reader.cpp).
PolygonSoup read_obj(const std::string& path, MeshReadReport& report);
/// PLY, ASCII or binary, strict parser of our own (ply_reader.cpp).
PolygonSoup read_ply(const std::string& path, MeshReadReport& report);
/// STL, ASCII or binary, strict parser of our own (stl_reader.cpp).
PolygonSoup read_stl(const std::string& path, MeshReadReport& report);
/// OpenMesh's own OM format (openmesh_reader.cpp).
PolygonSoup read_om(const std::string& path, MeshReadReport& report);

} // namespace hb::detail
