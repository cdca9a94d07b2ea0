#pragma once
// Edge adjacency of the triangles of a mesh (triangles sharing an edge are neighbours).
#include "mesh/triangle_mesh.h"
#include <cstdint>
#include <vector>

namespace hb {

/// Neighbours of every triangle through shared edges, in compressed rows: the neighbours
/// of triangle t are `neighbours[offsets[t] .. offsets[t + 1])`, sorted, without repeats.
/// A non-manifold edge links all its triangles to each other. Deterministic.
struct TriangleAdjacency {
  std::vector<std::uint32_t> offsets;
  std::vector<std::uint32_t> neighbours;

  std::size_t degree(std::uint32_t t) const { return offsets[t + 1] - offsets[t]; }
  const std::uint32_t* begin(std::uint32_t t) const { return neighbours.data() + offsets[t]; }
  const std::uint32_t* end(std::uint32_t t) const { return neighbours.data() + offsets[t + 1]; }
};

/// Builds the edge adjacency in O(T) (through each vertex's triangles; vertex ids beyond the
/// mesh join nothing).
TriangleAdjacency triangle_adjacency(const TriangleMesh& mesh);

} // namespace hb
