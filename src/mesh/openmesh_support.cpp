// OpenMesh glue shared by the readers and writers that use it.
//
//  1. SoupImporter: an OpenMesh importer that records raw vertices and polygons (OpenMesh's
//     own ImporterT silently drops faces with bad or repeated indices and detaches "complex
//     edge" faces; recording the raw faces lets mesh_validation.cpp validate and report).
//  2. OpenMeshChatterCapture: OpenMesh's omerr() text becomes warnings instead of std::cerr.
//  3. read_with_openmesh: the IOManager read under the process-wide OpenMesh lock.
#include <OpenMesh/Core/IO/MeshIO.hh>  // must precede the mesh kernel headers
#include <OpenMesh/Core/IO/importer/BaseImporter.hh>
#include <OpenMesh/Core/System/omstream.hh>

#include "mesh/openmesh_support.h"
#include "mesh/text_tokens.h"

#include "errors.h"

#include <algorithm>
#include <iostream>
#include <utility>

namespace hb::detail {
namespace {

/// An OpenMesh importer that records raw vertices and polygons and ignores attributes.
class SoupImporter : public OpenMesh::IO::BaseImporter {
public:
  using VertexHandle = OpenMesh::VertexHandle;
  using HalfedgeHandle = OpenMesh::HalfedgeHandle;
  using EdgeHandle = OpenMesh::EdgeHandle;
  using FaceHandle = OpenMesh::FaceHandle;
  using Vec2f = OpenMesh::Vec2f;
  using Vec3f = OpenMesh::Vec3f;
  using Vec3d = OpenMesh::Vec3d;
  using Vec4f = OpenMesh::Vec4f;
  using Vec3uc = OpenMesh::Vec3uc;
  using Vec4uc = OpenMesh::Vec4uc;
  using StatusInfo = OpenMesh::Attributes::StatusInfo;

  PolygonSoup soup;

  VertexHandle add_vertex(const Vec3f& p) override {
    soup.positions.emplace_back(p[0], p[1], p[2]);
    return VertexHandle(int(soup.positions.size()) - 1);
  }
  VertexHandle add_vertex(const Vec3d& p) override {
    soup.positions.emplace_back(float(p[0]), float(p[1]), float(p[2]));
    return VertexHandle(int(soup.positions.size()) - 1);
  }
  VertexHandle add_vertex() override { return add_vertex(Vec3f(0.f, 0.f, 0.f)); }
  HalfedgeHandle add_edge(VertexHandle, VertexHandle) override { return HalfedgeHandle(); }
  FaceHandle add_face(const VHandles& corners) override {
    if (corners.size() < 3) {
      ++soup.short_faces;
      return FaceHandle();
    }
    for (const VertexHandle& v : corners) soup.indices.push_back(v.idx());
    soup.offsets.push_back(soup.indices.size());
    return FaceHandle(int(soup.face_count()) - 1);
  }
  FaceHandle add_face(HalfedgeHandle) override { return FaceHandle(); }
  void add_face_texcoords(FaceHandle, VertexHandle, const std::vector<Vec2f>&) override {}
  void add_face_texcoords(FaceHandle, VertexHandle, const std::vector<Vec3f>&) override {}
  void set_face_texindex(FaceHandle, int) override {}
  void set_point(VertexHandle v, const Vec3f& p) override {
    if (v.idx() >= 0 && std::size_t(v.idx()) < soup.positions.size())
      soup.positions[std::size_t(v.idx())] = Vec3(p[0], p[1], p[2]);
  }
  void set_halfedge(VertexHandle, HalfedgeHandle) override {}
  void set_normal(VertexHandle, const Vec3f&) override {}
  void set_normal(VertexHandle, const Vec3d&) override {}
  void set_color(VertexHandle, const Vec3uc&) override {}
  void set_color(VertexHandle, const Vec4uc&) override {}
  void set_color(VertexHandle, const Vec3f&) override {}
  void set_color(VertexHandle, const Vec4f&) override {}
  void set_texcoord(VertexHandle, const Vec2f&) override {}
  void set_status(VertexHandle, const StatusInfo&) override {}
  void set_next(HalfedgeHandle, HalfedgeHandle) override {}
  void set_face(HalfedgeHandle, FaceHandle) override {}
  void request_face_texcoords2D() override {}
  void set_texcoord(HalfedgeHandle, const Vec2f&) override {}
  void set_texcoord(VertexHandle, const Vec3f&) override {}
  void set_texcoord(HalfedgeHandle, const Vec3f&) override {}
  void set_status(HalfedgeHandle, const StatusInfo&) override {}
  void set_color(EdgeHandle, const Vec3uc&) override {}
  void set_color(EdgeHandle, const Vec4uc&) override {}
  void set_color(EdgeHandle, const Vec3f&) override {}
  void set_color(EdgeHandle, const Vec4f&) override {}
  void set_status(EdgeHandle, const StatusInfo&) override {}
  void set_normal(FaceHandle, const Vec3f&) override {}
  void set_normal(FaceHandle, const Vec3d&) override {}
  void set_color(FaceHandle, const Vec3uc&) override {}
  void set_color(FaceHandle, const Vec4uc&) override {}
  void set_color(FaceHandle, const Vec3f&) override {}
  void set_color(FaceHandle, const Vec4f&) override {}
  void set_status(FaceHandle, const StatusInfo&) override {}
  void add_texture_information(int, std::string) override {}
  size_t n_vertices() const override { return soup.positions.size(); }
  size_t n_faces() const override { return soup.face_count(); }
  size_t n_edges() const override { return 0; }
};


} // namespace

std::mutex& openmesh_mutex() {
  static std::mutex m;
  return m;
}

OpenMeshChatterCapture::OpenMeshChatterCapture() {
  err_was_enabled_ = omerr().is_enabled();
  out_was_enabled_ = omout().is_enabled();
  log_was_enabled_ = omlog().is_enabled();
  had_cerr_ = omerr().disconnect(std::cerr);
  omerr().connect(captured_);
  omerr().enable();
  omout().disable();
  omlog().disable();
}

OpenMeshChatterCapture::~OpenMeshChatterCapture() {
  omerr().flush();
  omerr().disconnect(captured_);
  if (had_cerr_) omerr().connect(std::cerr);
  if (!err_was_enabled_) omerr().disable();
  if (out_was_enabled_) omout().enable();
  if (log_was_enabled_) omlog().enable();
}

std::vector<std::string> OpenMeshChatterCapture::lines() {
  omerr().flush();
  std::vector<std::pair<std::string, std::size_t>> seen;
  std::istringstream in(captured_.str());
  std::string l;
  while (std::getline(in, l)) {
    l = std::string(LineReader::trim(l));
    if (l.empty()) continue;
    auto it = std::find_if(seen.begin(), seen.end(), [&](const auto& p) { return p.first == l; });
    if (it == seen.end()) seen.emplace_back(l, 1);
    else ++it->second;
  }
  std::vector<std::string> out;
  for (const auto& [text, n] : seen)
    out.push_back(n > 1 ? text + " (x" + std::to_string(n) + ")" : text);
  return out;
}

PolygonSoup read_with_openmesh(const std::string& path, MeshReadReport& report) {
  SoupImporter importer;
  bool ok = false;
  std::vector<std::string> chatter;
  {
    std::lock_guard<std::mutex> lock(openmesh_mutex());
    OpenMeshChatterCapture capture;
    OpenMesh::IO::Options options;
    try {
      ok = OpenMesh::IO::IOManager().read(path, importer, options);
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
  report.input_vertices = importer.soup.positions.size();
  report.input_faces = importer.soup.face_count() + importer.soup.short_faces;
  return std::move(importer.soup);
}

} // namespace hb::detail
