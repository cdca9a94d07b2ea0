// Seam overlap: per piece, a breadth-first growth of `seam_rings` rings over edge adjacency.
#include "decomposition/seam_overlap.h"
#include "errors.h"
#include "mesh/triangle_adjacency.h"
#include <algorithm>

namespace hb {

std::vector<std::vector<std::uint32_t>> piece_triangle_lists(const TriangleMesh& mesh,
                                                             const std::vector<std::uint32_t>& piece_of_triangle,
                                                             int seam_rings) {
  const std::size_t count = mesh.triangle_count();
  if (piece_of_triangle.empty()) {
    std::vector<std::uint32_t> all(count);
    for (std::uint32_t t = 0; t < count; ++t) all[t] = t;
    return {all};
  }
  if (piece_of_triangle.size() != count)
    throw InvalidInput("piece list has " + std::to_string(piece_of_triangle.size()) + " entries, the mesh has " +
                       std::to_string(count) + " triangles");
  if (seam_rings < 0) throw InvalidInput("seam_rings must be >= 0");
  const std::uint32_t max_id = *std::max_element(piece_of_triangle.begin(), piece_of_triangle.end());
  std::vector<std::vector<std::uint32_t>> pieces(std::size_t(max_id) + 1);
  for (std::uint32_t t = 0; t < count; ++t) pieces[piece_of_triangle[t]].push_back(t);
  pieces.erase(std::remove_if(pieces.begin(), pieces.end(), [](const auto& p) { return p.empty(); }), pieces.end());
  if (seam_rings == 0 || pieces.size() == 1) return pieces;
  const TriangleAdjacency adj = triangle_adjacency(mesh);
  std::vector<std::uint32_t> stamp(count, UINT32_MAX);
  for (std::uint32_t p = 0; p < pieces.size(); ++p) {
    auto& list = pieces[p];
    for (std::uint32_t t : list) stamp[t] = p;
    std::size_t ring_begin = 0;
    for (int ring = 0; ring < seam_rings; ++ring) {
      const std::size_t ring_end = list.size();
      for (std::size_t k = ring_begin; k < ring_end; ++k)
        for (const std::uint32_t* n = adj.begin(list[k]); n != adj.end(list[k]); ++n)
          if (stamp[*n] != p) {
            stamp[*n] = p;
            list.push_back(*n);
          }
      ring_begin = ring_end;
    }
    std::sort(list.begin(), list.end());
  }
  return pieces;
}

} // namespace hb
