// Checks shared by every mesh reader.
//
//  1. The file: exists, regular, not empty, readable (before any parser runs).
//  2. The soup: finite coordinates within kMaxCoordinate, vertex count < 2^31, indices in
//     range (else hb::InvalidInput).
//  3. Fan-triangulate polygons, drop and count degenerate triangles (repeated index, zero area).
//  4. Edge analysis on undirected edges grouped by their lower vertex (a counting sort into a
//     bucket per vertex): boundary edges (open), edges with more than two faces (non-manifold),
//     edges used twice in the same direction (inconsistent orientation).
// Steps 2-4 run in parallel (TBB) and give what a sequential pass gives: the same first
// error, the same triangles in the same order, the same counts.
#include "mesh/mesh_validation.h"

#include "errors.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_reduce.h>
#include <tbb/task_arena.h>

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

namespace {

/// Faces (or vertices) per task of the parallel loops below.
constexpr std::size_t kGrain = std::size_t(1) << 16;

/// Smallest i in [0, n) with bad(i), or n: what a sequential scan would stop at first.
template <typename Bad>
std::size_t first_bad(std::size_t n, const Bad& bad) {
  return tbb::parallel_reduce(
      tbb::blocked_range<std::size_t>(0, n, kGrain), n,
      [&](const tbb::blocked_range<std::size_t>& r, std::size_t found) {
        for (std::size_t i = r.begin(); i != r.end() && i < found; ++i)
          if (bad(i)) return i;
        return found;
      },
      [](std::size_t a, std::size_t b) { return std::min(a, b); });
}

} // namespace

TriangleMesh triangulate(const std::string& path, PolygonSoup& soup, MeshReadReport& report) {
  // The checks run in parallel but report what the sequential scan met first: the lowest
  // vertex, then the lowest corner in file order.
  const auto& positions = soup.positions;
  const std::size_t bad_vertex = first_bad(positions.size(), [&](std::size_t v) {
    return !positions[v].allFinite() || positions[v].cwiseAbs().maxCoeff() > kMaxCoordinate;
  });
  if (bad_vertex < positions.size()) {
    const std::size_t v = bad_vertex;
    if (!soup.positions[v].allFinite())
      throw InvalidInput(path + ": vertex " + std::to_string(v) + " has a non-finite (NaN or Inf) coordinate");
    char value[32];
    std::snprintf(value, sizeof value, "%g", double(soup.positions[v].cwiseAbs().maxCoeff()));
    throw InvalidInput(path + ": vertex " + std::to_string(v) + " has a coordinate of magnitude " + value +
                       ", beyond the supported range (|x| <= 1e15)");
  }
  if (soup.positions.size() >= (std::size_t(1) << 31))
    throw InvalidInput(path + ": too many vertices (" + std::to_string(soup.positions.size()) + ")");
  const auto n = static_cast<std::int64_t>(soup.positions.size());
  const std::size_t corners = soup.offsets.back();
  const std::size_t bad_corner =
      first_bad(corners, [&](std::size_t c) { return soup.indices[c] < 0 || soup.indices[c] >= n; });
  if (bad_corner < corners) {
    // The face holding that corner: the last whose first corner is at or before it.
    const std::size_t f =
        std::size_t(std::upper_bound(soup.offsets.begin(), soup.offsets.end(), bad_corner) - soup.offsets.begin()) - 1;
    throw InvalidInput(path + ": face " + std::to_string(f) + ": vertex index " + std::to_string(soup.indices[bad_corner]) +
                       " out of range [0, " + std::to_string(n) + ")");
  }
  // The fan below places face f's triangles from its corner offset: it relies on the readers'
  // promise (polygon_soup.h) that a listed face has 3 or more corners.
  const std::size_t faces = soup.face_count();
  const std::size_t short_face =
      first_bad(faces, [&](std::size_t f) { return soup.offsets[f + 1] < soup.offsets[f] + 3; });
  if (short_face < faces)
    throw std::logic_error(path + ": face " + std::to_string(short_face) + " reached triangulation with fewer than 3 corners");
  if (soup.short_faces > 0) {
    report.faces_rejected += soup.short_faces;
    report.warnings.push_back(path + ": " + std::to_string(soup.short_faces) +
                              " faces with fewer than 3 corners skipped");
  }

  TriangleMesh mesh;
  mesh.positions = std::move(soup.positions);
  // Fan triangulation in parallel: face f's triangles start at offsets[f] - 2 f in the list
  // with nothing dropped; each block of faces writes there, counts what it kept, and the
  // blocks are then moved together in order (nothing moves when nothing was dropped), so the
  // triangles come out in the sequential order.
  mesh.triangles.resize(corners - 2 * faces);
  struct Block {
    std::size_t kept = 0, dropped = 0, polygons = 0;
  };
  const std::size_t n_blocks = (faces + kGrain - 1) / kGrain;
  std::vector<Block> blocks(n_blocks);
  const auto& P = mesh.positions;
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, n_blocks), [&](const tbb::blocked_range<std::size_t>& r) {
    for (std::size_t k = r.begin(); k != r.end(); ++k) {
      Block& block = blocks[k];
      const std::size_t f0 = k * kGrain, f1 = std::min(faces, f0 + kGrain);
      Triangle* out = mesh.triangles.data() + (soup.offsets[f0] - 2 * f0);
      for (std::size_t f = f0; f < f1; ++f) {
        const std::size_t b = soup.offsets[f], e = soup.offsets[f + 1];
        if (e - b > 3) ++block.polygons;
        for (std::size_t c = b + 1; c + 1 < e; ++c) {  // fan from the first corner
          const Triangle t{std::uint32_t(soup.indices[b]), std::uint32_t(soup.indices[c]),
                           std::uint32_t(soup.indices[c + 1])};
          const bool repeated = t[0] == t[1] || t[1] == t[2] || t[0] == t[2];
          // Exact zero test in double: only truly collinear corners count as degenerate.
          const Eigen::Vector3d a = P[t[0]].cast<double>();
          const double area2 = (P[t[1]].cast<double>() - a).cross(P[t[2]].cast<double>() - a).squaredNorm();
          if (repeated || area2 == 0.0) {
            ++block.dropped;
            continue;
          }
          out[block.kept++] = t;
        }
      }
    }
  });
  std::size_t kept = 0;
  for (std::size_t k = 0; k < n_blocks; ++k) {
    const std::size_t f0 = k * kGrain;
    const std::size_t from = soup.offsets[f0] - 2 * f0;
    if (from != kept)  // to the left, blocks in order: never over what is still to move
      std::copy(mesh.triangles.begin() + std::ptrdiff_t(from), mesh.triangles.begin() + std::ptrdiff_t(from + blocks[k].kept),
                mesh.triangles.begin() + std::ptrdiff_t(kept));
    kept += blocks[k].kept;
    report.degenerate_dropped += blocks[k].dropped;
    report.polygons_triangulated += blocks[k].polygons;
  }
  mesh.triangles.resize(kept);
  // The soup has served: free its indices before the edge analysis needs memory.
  soup = PolygonSoup();
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
  // Every triangle edge filed under its lower vertex (a bucket per vertex, counting sort),
  // as (higher vertex << 1 | direction): the same undirected keys as one global sort of
  // edges would group, for about half its memory and without its n log n. Each task owns a
  // range of vertices and scans all triangles for the edges it owns: the triangle list is
  // read a few times in order, but no two tasks write the same counter, so there are no
  // atomics (which would serialise the cache misses of the scattered writes).
  const std::size_t nv = mesh.positions.size();
  const auto& T = mesh.triangles;
  const std::size_t parts =
      std::max<std::size_t>(1, std::min<std::size_t>(2 * std::size_t(tbb::this_task_arena::max_concurrency()), nv / 4096));
  const auto for_owned_edges = [&](const auto& edge) {
    tbb::parallel_for(std::size_t(0), parts, [&](std::size_t part) {
      const std::uint32_t v0 = std::uint32_t(nv * part / parts), v1 = std::uint32_t(nv * (part + 1) / parts);
      for (const Triangle& t : T)
        for (int k = 0; k < 3; ++k) {
          const std::uint32_t a = t[k], b = t[(k + 1) % 3], lo = std::min(a, b);
          if (lo >= v0 && lo < v1) edge(a, b, lo);
        }
    });
  };
  std::vector<std::uint32_t> fill(nv, 0);
  for_owned_edges([&](std::uint32_t, std::uint32_t, std::uint32_t lo) { ++fill[lo]; });
  std::vector<std::size_t> start(nv + 1);
  start[0] = 0;
  for (std::size_t v = 0; v < nv; ++v) {
    start[v + 1] = start[v] + fill[v];
    fill[v] = 0;
  }
  // < 2^31 vertices (triangulate), so (hi << 1 | direction) fits 32 bits; the bit says a > b.
  std::vector<std::uint32_t> edges(start[nv]);
  for_owned_edges([&](std::uint32_t a, std::uint32_t b, std::uint32_t lo) {
    edges[start[lo] + fill[lo]++] = (std::max(a, b) << 1) | (a > b ? 1u : 0u);
  });
  fill = std::vector<std::uint32_t>();
  struct Counts {
    std::size_t boundary = 0, non_manifold = 0, misoriented = 0;
  };
  const Counts counts = tbb::parallel_reduce(
      tbb::blocked_range<std::size_t>(0, nv, kGrain), Counts{},
      [&](const tbb::blocked_range<std::size_t>& r, Counts c) {
        for (std::size_t v = r.begin(); v != r.end(); ++v) {
          const auto b = edges.begin() + std::ptrdiff_t(start[v]), e = edges.begin() + std::ptrdiff_t(start[v + 1]);
          std::sort(b, e);
          for (auto i = b; i != e;) {
            auto j = i;
            std::size_t forward = 0;
            while (j != e && (*j >> 1) == (*i >> 1)) {
              forward += (*j & 1u) ? 0 : 1;
              ++j;
            }
            const auto count = j - i;
            if (count == 1) ++c.boundary;
            else if (count > 2) ++c.non_manifold;
            else if (forward != 1) ++c.misoriented;
            i = j;
          }
        }
        return c;
      },
      [](Counts a, const Counts& b) {
        a.boundary += b.boundary;
        a.non_manifold += b.non_manifold;
        a.misoriented += b.misoriented;
        return a;
      });
  const std::size_t boundary = counts.boundary, non_manifold = counts.non_manifold, misoriented = counts.misoriented;
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
