// Checks shared by every mesh reader.
//
//  1. The file: exists, regular, not empty, readable (before any parser runs).
//  2. The soup: finite coordinates within kMaxCoordinate, vertex count < 2^31, indices in
//     range (else hb::InvalidInput).
//  3. Fan-triangulate polygons, drop and count degenerate triangles (repeated index, zero area).
//  4. Edge analysis on sorted undirected edges: boundary edges (open), edges with more than
//     two faces (non-manifold), edges used twice in the same direction (inconsistent orientation).
#include "mesh/mesh_validation.h"

#include "errors.h"

#include <tbb/parallel_sort.h>

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <fstream>

namespace hb::detail {

namespace fs = std::filesystem;

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

TriangleMesh triangulate(const std::string& path, PolygonSoup& soup, MeshReadReport& report) {
  for (std::size_t v = 0; v < soup.positions.size(); ++v) {
    if (!soup.positions[v].allFinite())
      throw InvalidInput(path + ": vertex " + std::to_string(v) + " has a non-finite (NaN or Inf) coordinate");
    if (soup.positions[v].cwiseAbs().maxCoeff() > kMaxCoordinate) {
      char value[32];
      std::snprintf(value, sizeof value, "%g", double(soup.positions[v].cwiseAbs().maxCoeff()));
      throw InvalidInput(path + ": vertex " + std::to_string(v) + " has a coordinate of magnitude " + value +
                         ", beyond the supported range (|x| <= 1e15)");
    }
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

} // namespace hb::detail
