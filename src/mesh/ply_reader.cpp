// PLY reader (ASCII and binary): OpenMesh's PLY reader into a raw soup.
#include "mesh/mesh_readers.h"
#include "mesh/openmesh_support.h"

namespace hb::detail {

PolygonSoup read_ply(const std::string& path, MeshReadReport& report) {
  return read_with_openmesh(path, report);
}

} // namespace hb::detail
