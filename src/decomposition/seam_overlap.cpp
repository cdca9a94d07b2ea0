// Seam overlap, per piece:
//  1. The piece's cell size h = largest PBB edge / (m - 1) of the box the bake fits to it
//     (PieceGridOf: the piece's own m when the bake picks m per box).
//  2. Breadth-first growth over edge adjacency; every grown triangle remembers the centroid
//     of the piece triangle its growth started from. A neighbour joins when it is within the
//     minimum ring count, or its centroid is within cells * h of that origin.
#include "decomposition/seam_overlap.h"
#include "errors.h"
#include "mesh/triangle_adjacency.h"
#include <algorithm>

namespace hb {

std::vector<std::vector<std::uint32_t>> piece_triangle_lists(const TriangleMesh& mesh,
                                                             const std::vector<std::uint32_t>& piece_of_triangle,
                                                             const SeamOptions& options,
                                                             const PieceGridOf& grid_of) {
  const std::size_t count = mesh.triangle_count();
  if (piece_of_triangle.empty()) {
    std::vector<std::uint32_t> all(count);
    for (std::uint32_t t = 0; t < count; ++t) all[t] = t;
    return {all};
  }
  if (piece_of_triangle.size() != count)
    throw InvalidInput("piece list has " + std::to_string(piece_of_triangle.size()) + " entries, the mesh has " +
                       std::to_string(count) + " triangles");
  if (options.rings < 0 || !(options.cells >= 0.f))
    throw InvalidInput("seam options: rings and cells must be >= 0");
  const std::uint32_t max_id = *std::max_element(piece_of_triangle.begin(), piece_of_triangle.end());
  std::vector<std::vector<std::uint32_t>> pieces(std::size_t(max_id) + 1);
  for (std::uint32_t t = 0; t < count; ++t) pieces[piece_of_triangle[t]].push_back(t);
  pieces.erase(std::remove_if(pieces.begin(), pieces.end(), [](const auto& p) { return p.empty(); }), pieces.end());
  if ((options.rings == 0 && options.cells == 0.f) || pieces.size() == 1) return pieces;
  if (options.cells > 0.f && !grid_of) throw InvalidInput("seam options: cells > 0 needs each piece's grid");
  const TriangleAdjacency adj = triangle_adjacency(mesh);
  std::vector<Vec3> centroid(count);
  for (std::size_t t = 0; t < count; ++t) {
    const Triangle& tri = mesh.triangles[t];
    centroid[t] = (mesh.positions[tri[0]] + mesh.positions[tri[1]] + mesh.positions[tri[2]]) / 3.f;
  }
  std::vector<std::uint32_t> stamp(count, UINT32_MAX), origin(count);
  for (std::uint32_t p = 0; p < pieces.size(); ++p) {
    auto& list = pieces[p];
    float width = 0.f;
    if (options.cells > 0.f) {
      const PieceGrid grid = grid_of(list);
      if (grid.m < 2) throw InvalidInput("seam options: a piece's m must be >= 2");
      width = options.cells * grid.largest_edge / float(grid.m - 1);
    }
    const float width_sq = width * width;
    for (std::uint32_t t : list) {
      stamp[t] = p;
      origin[t] = t;
    }
    std::size_t ring_begin = 0;
    for (int ring = 0; ring_begin < list.size(); ++ring) {
      const std::size_t ring_end = list.size();
      for (std::size_t k = ring_begin; k < ring_end; ++k) {
        const std::uint32_t t = list[k];
        for (const std::uint32_t* n = adj.begin(t); n != adj.end(t); ++n) {
          if (stamp[*n] == p) continue;
          if (ring >= options.rings && (centroid[*n] - centroid[origin[t]]).squaredNorm() > width_sq) continue;
          stamp[*n] = p;
          origin[*n] = origin[t];
          list.push_back(*n);
        }
      }
      ring_begin = ring_end;
    }
    std::sort(list.begin(), list.end());
  }
  return pieces;
}

} // namespace hb
