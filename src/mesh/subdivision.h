#pragma once
#include "mesh/triangle_mesh.h"

namespace hb {

/// Flat midpoint subdivision: each triangle into four through its edge midpoints (shared
/// between neighbours, so the mesh stays watertight); the shape is unchanged. Vertex normals
/// of new vertices are interpolated from the edge ends (the surface and its shading stay
/// the same). `levels` >= 0; 52K triangles at level 8 would be 3.4G: the caller chooses.
TriangleMesh subdivide_midpoint(const TriangleMesh& mesh, int levels = 1);

} // namespace hb
