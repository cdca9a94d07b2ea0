#pragma once
// Simplifying a mesh within a deviation bound (OpenMesh's Decimater, quadric error), for
// surfaces that only need to be as fine as an error budget: the budgeted bake refines its
// boxes against such a surface, so its memory and bake time stop growing with
// the triangle count. Exact comparisons stay on the full mesh.
#include "mesh/triangle_mesh.h"
#include <cstddef>
#include <cstdint>

namespace hb {

/// Options of decimate().
struct DecimationOptions {
  /// The largest distance (model units) a collapse may move the surface from any original
  /// face plane it merged (quadric error, OpenMesh's ModQuadricT with max error bound^2;
  /// collapses are halfedge collapses, so the kept vertices are original vertices). With
  /// several chunks each of the two passes gets half of it.
  double max_deviation = 0.0;
  /// Largest change of a face normal a collapse may make (degrees; ModNormalFlippingT):
  /// keeps shaded normals close to the full mesh's.
  double max_normal_deviation_deg = 20.0;
  /// A vertex is removed only when the shaded (vertex) normals of its neighbours are within
  /// this of its own (degrees; 180: no such check): the normals interpolated across the
  /// faces that replace it then stay near the full mesh's shading, which exact answers use.
  double max_shading_deviation_deg = 180.0;
  /// How max_shading_deviation_deg is checked (both: no check at 180).
  enum class ShadingCheck {
    /// A vertex is removed only when its one-ring's shaded normals are within the bound of its
    /// own (the first check; conservative: a flat-subdivided mesh's faceted normals keep
    /// almost every vertex).
    ring,
    /// Every face keeps the removed vertices it covers (as OpenMesh's ModHausdorffT keeps
    /// points); a collapse is legal when each new face's corner normals can be fitted (least
    /// squares, corner normals of its own, as hb::fit_shading fits them afterwards) to the
    /// full mesh's shaded normals of those vertices and its corners within the bound. The
    /// vertices are carried from pass to pass.
    fit,
  };
  ShadingCheck shading_check = ShadingCheck::ring;
  /// Meshes of more triangles than this are cut into spatial chunks (Morton order of the
  /// centroids) decimated in parallel (TBB) with the vertices they share locked, then the
  /// joined mesh is decimated once more across the chunk borders. 0: never chunked.
  std::size_t chunk_triangles = 400000;
};

/// What decimate() produced.
struct DecimationResult {
  TriangleMesh mesh;                 ///< the simplified mesh (vertex normals recomputed).
  std::size_t chunks = 1;            ///< chunks of the first pass.
  std::size_t unmanifold_kept = 0;   ///< faces OpenMesh could not take (non-manifold): kept as they are.
  double seconds = 0.0;
};

/// Simplifies `mesh` (which needs triangles; its vertices should be shared by the faces that
/// meet there, as in OFF/PLY/OBJ files: unshared vertices stay where they are) within
/// options.max_deviation. Boundary vertices and those of faces OpenMesh refuses are locked.
/// Throws hb::InvalidInput on an empty mesh or a negative bound.
DecimationResult decimate(const TriangleMesh& mesh, const DecimationOptions& options);

} // namespace hb
