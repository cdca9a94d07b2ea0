// Edge adjacency: sort (edge key, triangle) pairs, then link the triangles of each run.
#include "mesh/triangle_adjacency.h"
#include <tbb/parallel_sort.h>
#include <algorithm>

namespace hb {

TriangleAdjacency triangle_adjacency(const TriangleMesh& mesh) {
  const std::size_t count = mesh.triangle_count();
  std::vector<std::pair<std::uint64_t, std::uint32_t>> edges;
  edges.reserve(3 * count);
  for (std::uint32_t t = 0; t < count; ++t) {
    const Triangle& tri = mesh.triangles[t];
    for (int c = 0; c < 3; ++c) {
      std::uint64_t a = tri[c], b = tri[(c + 1) % 3];
      if (a == b) continue;
      if (a > b) std::swap(a, b);
      edges.emplace_back((a << 32) | b, t);
    }
  }
  // Parallel sorts: the pairs are distinct, so any sort gives the same order (13M triangles:
  // two sorts of 40M pairs were most of the decomposition's serial start).
  tbb::parallel_sort(edges.begin(), edges.end());
  std::vector<std::pair<std::uint32_t, std::uint32_t>> links;
  links.reserve(edges.size());  // two links per interior edge, one use each: about as many
  for (std::size_t i = 0; i < edges.size();) {
    std::size_t j = i;
    while (j < edges.size() && edges[j].first == edges[i].first) ++j;
    for (std::size_t a = i; a < j; ++a)
      for (std::size_t b = i; b < j; ++b)
        if (edges[a].second != edges[b].second) links.emplace_back(edges[a].second, edges[b].second);
    i = j;
  }
  tbb::parallel_sort(links.begin(), links.end());
  links.erase(std::unique(links.begin(), links.end()), links.end());
  TriangleAdjacency adj;
  adj.offsets.assign(count + 1, 0);
  for (const auto& l : links) ++adj.offsets[l.first + 1];
  for (std::size_t t = 0; t < count; ++t) adj.offsets[t + 1] += adj.offsets[t];
  adj.neighbours.resize(links.size());
  for (std::size_t k = 0; k < links.size(); ++k) adj.neighbours[k] = links[k].second;
  return adj;
}

} // namespace hb
