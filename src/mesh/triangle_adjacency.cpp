// Edge adjacency through the vertices: each vertex's triangles (a counting sort, in triangle
// order), then per triangle and edge (a, b) the triangles of a that also hold b. No sort of
// the 3T edge uses (at 13M triangles two sorts of 40M pairs took about 4 s a call, and a bake
// made two calls); every triangle's row is found on its own, so the rows run in parallel.
#include "mesh/triangle_adjacency.h"
#include <tbb/parallel_for.h>
#include <algorithm>

namespace hb {

TriangleAdjacency triangle_adjacency(const TriangleMesh& mesh) {
  const std::size_t count = mesh.triangle_count(), vertices = mesh.vertex_count();
  // 1. Each vertex's triangles, ascending (a triangle holding a vertex twice is listed once).
  std::vector<std::uint32_t> first(vertices + 1, 0);
  const auto distinct = [&](const Triangle& t, int c) {
    for (int k = 0; k < c; ++k)
      if (t[k] == t[c]) return false;
    return t[c] < vertices;
  };
  for (std::size_t t = 0; t < count; ++t)
    for (int c = 0; c < 3; ++c)
      if (distinct(mesh.triangles[t], c)) ++first[mesh.triangles[t][c] + 1];
  for (std::size_t v = 0; v < vertices; ++v) first[v + 1] += first[v];
  std::vector<std::uint32_t> held(first.back()), fill(first.begin(), first.end() - 1);
  for (std::uint32_t t = 0; t < count; ++t)
    for (int c = 0; c < 3; ++c)
      if (distinct(mesh.triangles[t], c)) held[fill[mesh.triangles[t][c]]++] = t;
  // 2. Per triangle: the other triangles holding both ends of one of its edges, sorted,
  //    without repeats (the rows the sort of (edge, triangle) pairs gave).
  const auto row = [&](std::uint32_t t, std::vector<std::uint32_t>& out) {
    out.clear();
    const Triangle& tri = mesh.triangles[t];
    for (int c = 0; c < 3; ++c) {
      const std::uint32_t a = tri[c], b = tri[(c + 1) % 3];
      if (a == b || a >= vertices || b >= vertices) continue;
      const std::uint32_t *pa = held.data() + first[a], *ea = held.data() + first[a + 1];
      const std::uint32_t *pb = held.data() + first[b], *eb = held.data() + first[b + 1];
      while (pa != ea && pb != eb) {
        if (*pa < *pb) ++pa;
        else if (*pb < *pa) ++pb;
        else {
          if (*pa != t) out.push_back(*pa);
          ++pa, ++pb;
        }
      }
    }
    std::sort(out.begin(), out.end());
    out.erase(std::unique(out.begin(), out.end()), out.end());
  };
  // Fixed blocks of triangles, each block's rows found once into its own list, then joined
  // in block order: the same rows whatever the threads do.
  constexpr std::size_t kBlock = 16384;
  const std::size_t blocks = (count + kBlock - 1) / kBlock;
  std::vector<std::vector<std::uint32_t>> block_rows(blocks);
  TriangleAdjacency adj;
  adj.offsets.assign(count + 1, 0);
  tbb::parallel_for(std::size_t(0), blocks, [&](std::size_t k) {
    std::vector<std::uint32_t> out;
    std::vector<std::uint32_t>& rows = block_rows[k];
    for (std::size_t t = k * kBlock; t < std::min(count, (k + 1) * kBlock); ++t) {
      row(std::uint32_t(t), out);
      adj.offsets[t + 1] = std::uint32_t(out.size());
      rows.insert(rows.end(), out.begin(), out.end());
    }
  });
  for (std::size_t t = 0; t < count; ++t) adj.offsets[t + 1] += adj.offsets[t];
  adj.neighbours.reserve(adj.offsets.back());
  for (std::vector<std::uint32_t>& rows : block_rows) {
    adj.neighbours.insert(adj.neighbours.end(), rows.begin(), rows.end());
    std::vector<std::uint32_t>().swap(rows);
  }
  return adj;
}

} // namespace hb
