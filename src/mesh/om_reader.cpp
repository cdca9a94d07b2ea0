// OM reader: OpenMesh's own format stores half-edge topology and needs a real OpenMesh
// kernel, so a PolyMesh is read and flattened into a soup. (OpenMesh's ImporterT may detach
// non-manifold faces: the geometry is unchanged.)
#include <OpenMesh/Core/IO/MeshIO.hh>  // must precede the mesh kernel headers
#include <OpenMesh/Core/Mesh/PolyMesh_ArrayKernelT.hh>

#include "mesh/mesh_readers.h"
#include "mesh/openmesh_support.h"

#include "errors.h"

namespace hb::detail {

PolygonSoup read_om(const std::string& path, MeshReadReport& report) {
  PolygonSoup soup;
  bool ok = false;
  std::vector<std::string> chatter;
  {
    std::lock_guard<std::mutex> lock(openmesh_mutex());
    OpenMeshChatterCapture capture;
    try {
      OpenMesh::PolyMesh_ArrayKernelT<> om;
      OpenMesh::IO::Options options;
      ok = OpenMesh::IO::read_mesh(om, path, options);
      if (ok) {
        soup.positions.reserve(om.n_vertices());
        for (const auto v : om.vertices()) {
          const auto& p = om.point(v);
          soup.positions.emplace_back(p[0], p[1], p[2]);
        }
        for (const auto f : om.faces()) {
          for (const auto v : om.fv_range(f)) soup.indices.push_back(v.idx());
          soup.offsets.push_back(soup.indices.size());
        }
      }
    } catch (const std::exception& e) {
      throw InvalidInput(path + ": OpenMesh reader failed: " + e.what());
    }
    chatter = capture.lines();
  }
  for (const std::string& l : chatter) report.warnings.push_back(path + ": OpenMesh: " + l);
  if (!ok) {
    std::string cause = chatter.empty() ? std::string("unreadable or corrupt content") : chatter.front();
    throw InvalidInput(path + ": OpenMesh could not parse the file (" + cause + ")");
  }
  report.input_vertices = soup.positions.size();
  report.input_faces = soup.face_count() + soup.short_faces;
  return soup;
}

} // namespace hb::detail
