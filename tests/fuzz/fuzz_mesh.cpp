// libFuzzer target: one mesh reader (the format is HB_FUZZ_EXT, one executable per format).
// Invariants: a rejected file gives an hb::Error naming the file (never another exception, a
// crash or a hang); an accepted mesh has triangles, indices in range, no repeated corner,
// coordinates finite and within kMaxCoordinate, one unit (or +Z) normal a vertex.
#include "fuzz_support.h"
#include "mesh/mesh_io.h"

#include <cmath>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string path = hb::fuzz::write_scratch(HB_FUZZ_EXT, data, size);
  try {
    hb::MeshReadReport report;
    const hb::TriangleMesh mesh = hb::read_mesh(path, &report);
    if (mesh.triangles.empty()) hb::fuzz::fail("accepted a mesh without triangles");
    if (mesh.normals.size() != mesh.positions.size()) hb::fuzz::fail("normals do not match the vertices");
    for (const hb::Vec3& p : mesh.positions)
      if (!(p.cwiseAbs().maxCoeff() <= hb::kMaxCoordinate)) hb::fuzz::fail("accepted a coordinate out of range");
    for (const hb::Vec3& n : mesh.normals)
      if (!(std::fabs(n.norm() - 1.f) < 1e-3f)) hb::fuzz::fail("a vertex normal is not unit length");
    for (const hb::Triangle& t : mesh.triangles) {
      for (auto v : t)
        if (v >= mesh.positions.size()) hb::fuzz::fail("accepted a triangle index out of range");
      if (t[0] == t[1] || t[1] == t[2] || t[0] == t[2]) hb::fuzz::fail("accepted a triangle with a repeated corner");
    }
    if (report.input_vertices < mesh.positions.size() && report.input_vertices != 0)
      hb::fuzz::fail("the report counts fewer vertices than the mesh has");
  } catch (const hb::Error& e) {
    hb::fuzz::check_rejection(e, path);
  }
  return 0;
}
