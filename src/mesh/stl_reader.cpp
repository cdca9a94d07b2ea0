// STL reader (ASCII and binary): OpenMesh's STL reader into a raw soup.
#include "mesh/mesh_readers.h"
#include "mesh/openmesh_support.h"

namespace hb::detail {

PolygonSoup read_stl(const std::string& path, MeshReadReport& report) {
  return read_with_openmesh(path, report);
}

} // namespace hb::detail
