// OBJ reader: OpenMesh's OBJ reader into a raw soup, then a check OpenMesh does not make:
// it silently skips "v" lines it cannot parse (e.g. "nan"), shifting every later index, so
// the "v" lines of the file are counted and compared with the vertices read.
#include "mesh/mesh_readers.h"
#include "mesh/openmesh_support.h"
#include "mesh/text_tokens.h"

#include "errors.h"

#include <fstream>

namespace hb::detail {
namespace {

/// Number of "v x y z" lines of an OBJ file.
std::size_t count_obj_vertex_lines(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::string line;
  std::size_t n = 0;
  while (std::getline(in, line)) {
    const std::string_view l = LineReader::trim(line);
    if (l.size() > 2 && l[0] == 'v' && (l[1] == ' ' || l[1] == '\t')) ++n;
  }
  return n;
}

} // namespace

PolygonSoup read_obj(const std::string& path, MeshReadReport& report) {
  PolygonSoup soup = read_with_openmesh(path, report);
  const std::size_t declared = count_obj_vertex_lines(path);
  if (declared != soup.positions.size())
    throw InvalidInput(path + ": " + std::to_string(declared) + " vertex lines but only " +
                       std::to_string(soup.positions.size()) +
                       " could be parsed (non-finite (NaN or Inf) or malformed coordinates)");
  return soup;
}

} // namespace hb::detail
