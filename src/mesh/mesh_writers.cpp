// Mesh writers: OFF directly (exact shortest float text); other formats through an OpenMesh
// TriMesh (non-manifold triangles get their own copies of their corners, since OpenMesh's
// half-edge mesh refuses them).
#include <OpenMesh/Core/IO/MeshIO.hh>  // must precede the mesh kernel headers
#include <OpenMesh/Core/Mesh/TriMesh_ArrayKernelT.hh>

#include "mesh/mesh_writers.h"
#include "mesh/openmesh_support.h"

#include "errors.h"

#include <charconv>
#include <cstdio>
#include <limits>
#include <memory>

namespace hb::detail {

void write_off(const TriangleMesh& mesh, const std::string& path) {
  std::FILE* f = std::fopen(path.c_str(), "wb");
  if (!f) throw IoError(path + ": cannot open for writing");
  std::unique_ptr<std::FILE, int (*)(std::FILE*)> guard(f, &std::fclose);
  std::string buf;
  buf.reserve(1 << 20);
  const auto flush = [&] {
    if (std::fwrite(buf.data(), 1, buf.size(), f) != buf.size()) throw IoError(path + ": write error");
    buf.clear();
  };
  buf += "OFF\n" + std::to_string(mesh.vertex_count()) + " " + std::to_string(mesh.triangle_count()) + " 0\n";
  char num[64];
  for (const Vec3& p : mesh.positions) {
    for (int k = 0; k < 3; ++k) {
      const auto r = std::to_chars(num, num + sizeof num, p[k]);  // shortest exact round trip
      buf.append(num, r.ptr);
      buf += k < 2 ? ' ' : '\n';
    }
    if (buf.size() > (1 << 20) - 256) flush();
  }
  for (const Triangle& t : mesh.triangles) {
    buf += "3";
    for (auto v : t) {
      buf += ' ';
      const auto r = std::to_chars(num, num + sizeof num, v);
      buf.append(num, r.ptr);
    }
    buf += '\n';
    if (buf.size() > (1 << 20) - 256) flush();
  }
  flush();
  if (std::fclose(guard.release()) != 0) throw IoError(path + ": write error on close");
}

void write_with_openmesh(const TriangleMesh& mesh, const std::string& path, bool binary) {
  using OmMesh = OpenMesh::TriMesh_ArrayKernelT<>;
  OmMesh om;
  om.reserve(mesh.vertex_count(), 3 * mesh.triangle_count() / 2, mesh.triangle_count());
  std::vector<OmMesh::VertexHandle> vh;
  vh.reserve(mesh.vertex_count());
  for (const Vec3& p : mesh.positions) vh.push_back(om.add_vertex(OmMesh::Point(p[0], p[1], p[2])));
  std::lock_guard<std::mutex> lock(openmesh_mutex());
  OpenMeshChatterCapture capture;  // add_face complains about complex edges
  for (const Triangle& t : mesh.triangles) {
    if (!om.add_face(vh[t[0]], vh[t[1]], vh[t[2]]).is_valid()) {
      // Non-manifold here: write the triangle with its own copies of the corners.
      om.add_face(om.add_vertex(om.point(vh[t[0]])), om.add_vertex(om.point(vh[t[1]])),
                  om.add_vertex(om.point(vh[t[2]])));
    }
  }
  OpenMesh::IO::Options options;
  if (binary) options += OpenMesh::IO::Options::Binary;
  bool ok = false;
  try {
    ok = OpenMesh::IO::write_mesh(om, path, options, std::numeric_limits<float>::max_digits10);
  } catch (const std::exception& e) {
    throw IoError(path + ": OpenMesh writer failed: " + e.what());
  }
  if (!ok) {
    const auto chatter = capture.lines();
    throw IoError(path + ": cannot write" + (chatter.empty() ? std::string() : " (" + chatter.front() + ")"));
  }
}

} // namespace hb::detail
