// Mesh reading and writing (OFF, OBJ, PLY, STL, OM) and file hashing.
//
// Reading, in order:
//  1. Check the extension (case-insensitive) and the file itself: missing, directory, empty.
//  2. Load a polygon soup (positions + index lists), not a half-edge mesh, so nothing is lost:
//     - OFF (the main dataset format) with a strict parser of our own: comments, blank lines,
//       "OFF" alone or followed by the counts, colours after face indices; the declared counts
//       are checked against the lines actually present before anything is reserved.
//     - the other formats through OpenMesh's readers feeding a recording importer
//       (SoupImporter). OpenMesh's own ImporterT silently drops faces with bad or repeated
//       indices and detaches "complex edge" faces; recording the raw faces lets us validate
//       and report instead. OpenMesh's std::cerr chatter is captured and becomes warnings.
//       OBJ: OpenMesh skips unparsable "v" lines (NaN) silently, so their count is checked.
//       OM stores half-edge topology and is read into a PolyMesh, then flattened.
//  3. Validate: finite coordinates, indices in range (else hb::InvalidInput).
//  4. Fan-triangulate polygons, drop and count degenerate triangles (repeated index, zero area).
//  5. Edge analysis on sorted undirected edges: boundary edges (open), edges with more than
//     two faces (non-manifold), edges used twice in the same direction (inconsistent orientation).
//  6. Compute vertex normals.
//
// Writing: OFF directly (exact shortest float text); other formats through an OpenMesh TriMesh.
#include <OpenMesh/Core/IO/MeshIO.hh>  // must precede the mesh kernel headers
#include <OpenMesh/Core/IO/importer/BaseImporter.hh>
#include <OpenMesh/Core/Mesh/PolyMesh_ArrayKernelT.hh>
#include <OpenMesh/Core/Mesh/TriMesh_ArrayKernelT.hh>
#include <OpenMesh/Core/System/omstream.hh>

#include "mesh/mesh_io.h"

#include "errors.h"

#include <tbb/parallel_sort.h>
#include <xxhash.h>

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <limits>
#include <memory>
#include <mutex>
#include <sstream>
#include <string_view>

namespace hb {
namespace {

namespace fs = std::filesystem;

/// Faces as flat index lists: face f has corners indices[offsets[f] .. offsets[f+1]).
struct PolygonSoup {
  std::vector<Vec3> positions;
  std::vector<std::int64_t> indices;
  std::vector<std::size_t> offsets{0};
  std::size_t short_faces = 0;  ///< faces with fewer than 3 corners (skipped).

  std::size_t face_count() const { return offsets.size() - 1; }
};

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

// ---------------------------------------------------------------------------------------
// OFF: strict line-based parser.

/// Cursor over the non-blank, comment-stripped lines of a text buffer.
class LineReader {
public:
  explicit LineReader(std::string_view text) : text_(text) {}

  /// Next line with content (comments after '#' removed, trimmed); false at the end.
  bool next(std::string_view& line) {
    while (pos_ < text_.size()) {
      std::size_t end = text_.find('\n', pos_);
      if (end == std::string_view::npos) end = text_.size();
      std::string_view l = text_.substr(pos_, end - pos_);
      pos_ = end + 1;
      ++line_number_;
      const std::size_t hash = l.find('#');
      if (hash != std::string_view::npos) l = l.substr(0, hash);
      l = trim(l);
      if (!l.empty()) {
        line = l;
        return true;
      }
    }
    return false;
  }
  std::size_t line_number() const { return line_number_; }

  static std::string_view trim(std::string_view s) {
    const auto ws = [](char c) { return c == ' ' || c == '\t' || c == '\r' || c == '\f' || c == '\v'; };
    while (!s.empty() && ws(s.front())) s.remove_prefix(1);
    while (!s.empty() && ws(s.back())) s.remove_suffix(1);
    return s;
  }

private:
  std::string_view text_;
  std::size_t pos_ = 0;
  std::size_t line_number_ = 0;
};

/// Splits a line into whitespace-separated tokens, one at a time.
class Tokens {
public:
  explicit Tokens(std::string_view line) : s_(line) {}
  bool next(std::string_view& tok) {
    while (i_ < s_.size() && is_space(s_[i_])) ++i_;
    if (i_ >= s_.size()) return false;
    const std::size_t b = i_;
    while (i_ < s_.size() && !is_space(s_[i_])) ++i_;
    tok = s_.substr(b, i_ - b);
    return true;
  }

private:
  static bool is_space(char c) { return c == ' ' || c == '\t' || c == '\r' || c == '\f' || c == '\v'; }
  std::string_view s_;
  std::size_t i_ = 0;
};

template <typename T>
bool parse_number(std::string_view tok, T& value) {
  const char* b = tok.data();
  const char* e = b + tok.size();
  if (b != e && *b == '+') ++b;  // from_chars rejects a leading '+'
  const auto r = std::from_chars(b, e, value);
  return r.ec == std::errc() && r.ptr == e;
}

/// Counts the remaining content lines without consuming them (to check declared counts).
std::size_t count_content_lines(LineReader reader) {
  std::size_t n = 0;
  std::string_view l;
  while (reader.next(l)) ++n;
  return n;
}

PolygonSoup read_off(const std::string& path, const std::string& text, MeshReadReport& report) {
  const auto invalid = [&](std::size_t line, const std::string& cause) {
    return InvalidInput(path + ":" + std::to_string(line) + ": " + cause);
  };
  if (text.find('\0') != std::string::npos)
    throw InvalidInput(path + ": not a text OFF file (contains NUL bytes; binary OFF is not supported)");

  LineReader lines(text);
  std::string_view line;
  if (!lines.next(line)) throw IoError(path + ": file has no content (only blanks or comments)");

  // Header keyword: [ST][C][N]OFF; "4OFF"/"nOFF" (other dimensions) and binary are refused.
  Tokens head(line);
  std::string_view tok;
  head.next(tok);
  std::vector<long long> counts;
  const std::string key(tok);
  const bool keyword = key.size() >= 3 && key.compare(key.size() - 3, 3, "OFF") == 0;
  if (keyword) {
    const std::string prefix = key.substr(0, key.size() - 3);
    if (prefix.find('4') != std::string::npos || prefix.find('n') != std::string::npos)
      throw invalid(lines.line_number(), "OFF variant '" + key + "' (not 3D) is not supported");
    for (char c : prefix)
      if (c != 'S' && c != 'T' && c != 'C' && c != 'N')
        throw invalid(lines.line_number(), "unrecognised OFF header '" + key + "'");
  } else {
    // Some writers omit the keyword; then the first line must be the counts.
    long long v;
    if (!parse_number(tok, v))
      throw invalid(lines.line_number(), "not an OFF file (header '" + key.substr(0, 40) + "')");
    counts.push_back(v);
  }
  while (head.next(tok)) {
    long long v;
    if (tok == "BINARY") throw invalid(lines.line_number(), "binary OFF is not supported");
    if (!parse_number(tok, v)) throw invalid(lines.line_number(), "bad count '" + std::string(tok) + "'");
    counts.push_back(v);
  }
  if (counts.empty()) {  // counts on their own line
    if (!lines.next(line)) throw IoError(path + ": truncated after the OFF header (no counts)");
    Tokens t(line);
    while (t.next(tok)) {
      long long v;
      if (!parse_number(tok, v)) throw invalid(lines.line_number(), "bad count '" + std::string(tok) + "'");
      counts.push_back(v);
    }
  }
  if (counts.size() < 2 || counts.size() > 3)
    throw invalid(lines.line_number(), "expected 'vertices faces [edges]' counts");
  if (counts[0] < 0 || counts[1] < 0) throw invalid(lines.line_number(), "negative vertex or face count");

  // Check the declared counts against the lines present before reserving anything, so an
  // absurd header cannot trigger a huge allocation or a long loop.
  const std::size_t available = count_content_lines(lines);
  const auto n_vertices = static_cast<std::size_t>(counts[0]);
  const auto n_faces = static_cast<std::size_t>(counts[1]);
  if (n_vertices > std::numeric_limits<std::uint32_t>::max())
    throw invalid(lines.line_number(), "vertex count " + std::to_string(n_vertices) + " is too large");
  if (n_vertices > available || n_faces > available - n_vertices)
    throw IoError(path + ": truncated: header declares " + std::to_string(n_vertices) + " vertices and " +
                  std::to_string(n_faces) + " faces but only " + std::to_string(available) +
                  " data lines follow");
  report.input_vertices = n_vertices;
  report.input_faces = n_faces;

  PolygonSoup soup;
  soup.positions.reserve(n_vertices);
  for (std::size_t v = 0; v < n_vertices; ++v) {
    lines.next(line);
    Tokens t(line);
    double c[3];
    for (double& x : c) {
      if (!t.next(tok) || !parse_number(tok, x))
        throw invalid(lines.line_number(), "vertex " + std::to_string(v) + ": expected 3 numeric coordinates");
    }
    // Extra values (normals, colours, texture coordinates) are ignored.
    soup.positions.emplace_back(float(c[0]), float(c[1]), float(c[2]));
  }

  soup.offsets.reserve(n_faces + 1);
  soup.indices.reserve(3 * n_faces);
  for (std::size_t f = 0; f < n_faces; ++f) {
    lines.next(line);
    Tokens t(line);
    long long k;
    if (!t.next(tok) || !parse_number(tok, k) || k < 0)
      throw invalid(lines.line_number(), "face " + std::to_string(f) + ": expected a corner count");
    if (static_cast<unsigned long long>(k) > line.size())  // each index needs >= 2 characters
      throw invalid(lines.line_number(), "face " + std::to_string(f) + ": corner count " + std::to_string(k) +
                                             " exceeds the line");
    for (long long i = 0; i < k; ++i) {
      long long idx;
      if (!t.next(tok) || !parse_number(tok, idx))
        throw invalid(lines.line_number(), "face " + std::to_string(f) + ": expected " + std::to_string(k) +
                                               " integer vertex indices");
      if (idx < 0 || idx >= static_cast<long long>(n_vertices))
        throw invalid(lines.line_number(), "face " + std::to_string(f) + ": vertex index " +
                                               std::to_string(idx) + " out of range [0, " +
                                               std::to_string(n_vertices) + ")");
      soup.indices.push_back(idx);
    }
    // Anything after the indices is a face colour: ignored.
    if (k < 3) {
      soup.indices.resize(soup.offsets.back());
      ++soup.short_faces;
      continue;
    }
    soup.offsets.push_back(soup.indices.size());
  }
  return soup;
}

// ---------------------------------------------------------------------------------------
// Other formats: OpenMesh readers into a recording importer.

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

/// OpenMesh's log streams are process-global: one OpenMesh call at a time.
std::mutex& openmesh_mutex() {
  static std::mutex m;
  return m;
}

/// While alive, routes omerr() into a string instead of std::cerr and mutes omout()/omlog();
/// restores the previous state on destruction. Hold openmesh_mutex() around it.
class OpenMeshChatterCapture {
public:
  OpenMeshChatterCapture() {
    err_was_enabled_ = omerr().is_enabled();
    out_was_enabled_ = omout().is_enabled();
    log_was_enabled_ = omlog().is_enabled();
    had_cerr_ = omerr().disconnect(std::cerr);
    omerr().connect(captured_);
    omerr().enable();
    omout().disable();
    omlog().disable();
  }
  ~OpenMeshChatterCapture() {
    omerr().flush();
    omerr().disconnect(captured_);
    if (had_cerr_) omerr().connect(std::cerr);
    if (!err_was_enabled_) omerr().disable();
    if (out_was_enabled_) omout().enable();
    if (log_was_enabled_) omlog().enable();
  }
  OpenMeshChatterCapture(const OpenMeshChatterCapture&) = delete;
  OpenMeshChatterCapture& operator=(const OpenMeshChatterCapture&) = delete;

  /// Distinct non-empty lines written so far, with a repeat count.
  std::vector<std::string> lines() {
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

private:
  std::ostringstream captured_;
  bool had_cerr_ = false;
  bool err_was_enabled_ = true, out_was_enabled_ = true, log_was_enabled_ = true;
};

/// Number of "v x y z" lines of an OBJ file. OpenMesh's OBJ reader silently skips vertex
/// lines it cannot parse (e.g. "nan"), shifting every later index: we compare the counts.
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

/// OM files store half-edge topology and need a real OpenMesh kernel; a PolyMesh is read and
/// flattened. (OpenMesh's ImporterT may detach non-manifold faces: geometry is unchanged.)
bool read_om(const std::string& path, PolygonSoup& soup) {
  OpenMesh::PolyMesh_ArrayKernelT<> om;
  OpenMesh::IO::Options options;
  if (!OpenMesh::IO::read_mesh(om, path, options)) return false;
  soup.positions.reserve(om.n_vertices());
  for (const auto v : om.vertices()) {
    const auto& p = om.point(v);
    soup.positions.emplace_back(p[0], p[1], p[2]);
  }
  for (const auto f : om.faces()) {
    for (const auto v : om.fv_range(f)) soup.indices.push_back(v.idx());
    soup.offsets.push_back(soup.indices.size());
  }
  return true;
}

PolygonSoup read_with_openmesh(const std::string& path, Format format, MeshReadReport& report) {
  SoupImporter importer;
  bool ok = false;
  std::vector<std::string> chatter;
  {
    std::lock_guard<std::mutex> lock(openmesh_mutex());
    OpenMeshChatterCapture capture;
    OpenMesh::IO::Options options;
    try {
      ok = format == Format::Om ? read_om(path, importer.soup)
                                : OpenMesh::IO::IOManager().read(path, importer, options);
    } catch (const std::exception& e) {
      throw InvalidInput(path + ": OpenMesh reader failed: " + e.what());
    }
    chatter = capture.lines();
  }
  if (ok && format == Format::Obj) {
    const std::size_t declared = count_obj_vertex_lines(path);
    if (declared != importer.soup.positions.size())
      throw InvalidInput(path + ": " + std::to_string(declared) + " vertex lines but only " +
                         std::to_string(importer.soup.positions.size()) +
                         " could be parsed (non-finite (NaN or Inf) or malformed coordinates)");
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

std::string read_whole_file(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw IoError(path + ": cannot open for reading");
  std::string text;
  in.seekg(0, std::ios::end);
  const auto size = in.tellg();
  if (size < 0) throw IoError(path + ": cannot determine the file size");
  text.resize(static_cast<std::size_t>(size));
  in.seekg(0, std::ios::beg);
  in.read(text.data(), size);
  if (!in) throw IoError(path + ": read error");
  return text;
}

// ---------------------------------------------------------------------------------------
// Validation, triangulation, edge analysis.

TriangleMesh triangulate(const std::string& path, PolygonSoup& soup, MeshReadReport& report) {
  for (std::size_t v = 0; v < soup.positions.size(); ++v) {
    if (!soup.positions[v].allFinite())
      throw InvalidInput(path + ": vertex " + std::to_string(v) + " has a non-finite (NaN or Inf) coordinate");
  }
  if (soup.positions.size() >= (std::size_t(1) << 31))
    throw InvalidInput(path + ": too many vertices (" + std::to_string(soup.positions.size()) + ")");
  const auto n = static_cast<std::int64_t>(soup.positions.size());
  for (std::size_t f = 0; f < soup.face_count(); ++f) {
    for (std::size_t c = soup.offsets[f]; c < soup.offsets[f + 1]; ++c) {
      const std::int64_t idx = soup.indices[c];
      if (idx < 0 || idx >= n)
        throw InvalidInput(path + ": face " + std::to_string(f) + ": vertex index " + std::to_string(idx) +
                           " out of range [0, " + std::to_string(n) + ")");
    }
  }
  if (soup.short_faces > 0) {
    report.faces_rejected += soup.short_faces;
    report.warnings.push_back(path + ": " + std::to_string(soup.short_faces) +
                              " faces with fewer than 3 corners skipped");
  }

  TriangleMesh mesh;
  mesh.positions = std::move(soup.positions);
  mesh.triangles.reserve(soup.indices.size() - 2 * soup.face_count());
  const auto& P = mesh.positions;
  for (std::size_t f = 0; f < soup.face_count(); ++f) {
    const std::size_t b = soup.offsets[f], e = soup.offsets[f + 1];
    if (e - b > 3) ++report.polygons_triangulated;
    for (std::size_t c = b + 1; c + 1 < e; ++c) {  // fan from the first corner
      const Triangle t{std::uint32_t(soup.indices[b]), std::uint32_t(soup.indices[c]),
                       std::uint32_t(soup.indices[c + 1])};
      const bool repeated = t[0] == t[1] || t[1] == t[2] || t[0] == t[2];
      // Exact zero test in double: only truly collinear corners count as degenerate.
      const Eigen::Vector3d a = P[t[0]].cast<double>();
      const double area2 = (P[t[1]].cast<double>() - a).cross(P[t[2]].cast<double>() - a).squaredNorm();
      if (repeated || area2 == 0.0) {
        ++report.degenerate_dropped;
        continue;
      }
      mesh.triangles.push_back(t);
    }
  }
  if (report.degenerate_dropped > 0)
    report.warnings.push_back(path + ": " + std::to_string(report.degenerate_dropped) +
                              " degenerate triangles (repeated index or zero area) dropped");
  if (mesh.triangles.empty()) {
    // OpenMesh's readers often "succeed" with nothing: pass on what they complained about.
    std::string hint;
    for (const std::string& w : report.warnings)
      if (w.find(": OpenMesh: ") != std::string::npos) {
        hint = " (" + w.substr(w.find(": OpenMesh: ") + 2) + ")";
        break;
      }
    throw InvalidInput(path + ": no (non-degenerate) triangles in the mesh" + hint);
  }
  return mesh;
}

/// Marks open / non-manifold / inconsistently oriented edges in the report.
void analyse_edges(const std::string& path, const TriangleMesh& mesh, MeshReadReport& report) {
  // Key: undirected edge (lo << 32 | hi); low bit of the payload: direction.
  std::vector<std::uint64_t> edges;
  edges.reserve(3 * mesh.triangles.size());
  for (const Triangle& t : mesh.triangles) {
    for (int k = 0; k < 3; ++k) {
      const std::uint32_t a = t[k], b = t[(k + 1) % 3];
      const std::uint64_t lo = std::min(a, b), hi = std::max(a, b);
      // 63 bits of key are enough for < 2^31 vertices; the lowest bit says a > b.
      edges.push_back(((lo << 32 | hi) << 1) | (a > b ? 1u : 0u));
    }
  }
  tbb::parallel_sort(edges.begin(), edges.end());
  std::size_t boundary = 0, non_manifold = 0, misoriented = 0;
  for (std::size_t i = 0; i < edges.size();) {
    std::size_t j = i;
    std::size_t forward = 0;
    while (j < edges.size() && (edges[j] >> 1) == (edges[i] >> 1)) {
      forward += (edges[j] & 1u) ? 0 : 1;
      ++j;
    }
    const std::size_t count = j - i;
    if (count == 1) ++boundary;
    else if (count > 2) ++non_manifold;
    else if (forward != 1) ++misoriented;
    i = j;
  }
  if (boundary > 0) {
    report.open = true;
    report.warnings.push_back(path + ": open mesh: " + std::to_string(boundary) + " boundary edges");
  }
  if (non_manifold > 0) {
    report.non_manifold = true;
    report.warnings.push_back(path + ": non-manifold: " + std::to_string(non_manifold) +
                              " edges shared by more than two faces (kept)");
  }
  if (misoriented > 0) {
    report.inconsistent_orientation = true;
    report.warnings.push_back(path + ": " + std::to_string(misoriented) +
                              " edges whose two faces have inconsistent orientation");
  }
}

void check_readable_file(const std::string& path) {
  std::error_code ec;
  const fs::file_status st = fs::status(path, ec);
  if (ec || !fs::exists(st)) throw IoError(path + ": no such file");
  if (fs::is_directory(st)) throw IoError(path + ": is a directory, not a mesh file");
  if (!fs::is_regular_file(st)) throw IoError(path + ": not a regular file");
  const auto size = fs::file_size(path, ec);
  if (ec) throw IoError(path + ": cannot read the file size (" + ec.message() + ")");
  if (size == 0) throw IoError(path + ": file is empty");
  std::ifstream probe(path, std::ios::binary);
  if (!probe) throw IoError(path + ": cannot open for reading (permission?)");
}

// ---------------------------------------------------------------------------------------
// Writing.

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

void write_with_openmesh(const TriangleMesh& mesh, const std::string& path, Format format) {
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
  if (format == Format::Stl || format == Format::Ply || format == Format::Om)
    options += OpenMesh::IO::Options::Binary;
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

} // namespace

TriangleMesh read_mesh(const std::string& path, MeshReadReport* report_out) {
  const Format format = format_of(path);
  check_readable_file(path);
  MeshReadReport report;
  PolygonSoup soup = format == Format::Off ? read_off(path, read_whole_file(path), report)
                                           : read_with_openmesh(path, format, report);
  TriangleMesh mesh = triangulate(path, soup, report);
  analyse_edges(path, mesh, report);
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
  if (format == Format::Off) write_off(mesh, path);
  else write_with_openmesh(mesh, path, format);
}

std::uint64_t hash_file(const std::string& path) {
  std::error_code ec;
  if (fs::is_directory(path, ec)) throw IoError(path + ": is a directory, cannot hash");
  std::ifstream in(path, std::ios::binary);
  if (!in) throw IoError(path + ": cannot open for hashing");
  std::unique_ptr<XXH64_state_t, XXH_errorcode (*)(XXH64_state_t*)> state(XXH64_createState(), &XXH64_freeState);
  if (!state || XXH64_reset(state.get(), 0) != XXH_OK) throw IoError(path + ": cannot initialise xxHash");
  std::vector<char> buf(1 << 20);
  while (in) {
    in.read(buf.data(), std::streamsize(buf.size()));
    const auto got = in.gcount();
    if (got > 0) XXH64_update(state.get(), buf.data(), std::size_t(got));
  }
  if (in.bad()) throw IoError(path + ": read error while hashing");
  return XXH64_digest(state.get());
}

} // namespace hb
