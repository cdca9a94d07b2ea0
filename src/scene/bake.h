#pragma once
// Baking haptic boxes: casting the directional samples with Embree.
#include "scene/box_scene.h"
#include "box/position_density.h"
#include "parallel/communicator.h"
#include "progress.h"
#include <vector>

namespace hb {

class EmbreeScene;

/// Options of bake_box / bake_scene.
struct BakeOptions {
  BoxParams params;           ///< densities m and n (m: see `density`).
  /// Per-box position density: with density.cell > 0 each box's m comes from its PBB's size
  /// (PositionDensity::m_for) instead of params.m; n is params.n for all boxes.
  PositionDensity density;
  ObbOptions obb;             ///< PBB fitting (padding).
  /// Also store, per sample, the triangle its ray hit, and the mesh's triangles, so queries
  /// refine the blended answer exactly (HapticBox::attach_surface): 2 or 4 bytes more per sample
  /// and 64 bytes per triangle.
  bool refine = false;
  /// With refine: the refinement surface to share (SurfaceTriangles of this mesh), so that
  /// boxes of several bakes form one scene (the budgeted bake); nullptr: built by the bake.
  std::shared_ptr<const SurfaceTriangles> surface;
  /// Scenes of several boxes: also bake a scene grid (scene_grid.h), which routes each
  /// probe to the boxes whose pieces it can meet and answers whether the handle is inside
  /// the object in O(1).
  bool scene_grid = true;
  SceneGridOptions grid;
  /// A BVH of the whole `mesh` already built (the budgeted bake's exact reference): a piece
  /// of all the mesh's triangles (one box over the model) casts its rays against it instead of
  /// building its own (the same nearest hits; a 13M-triangle build fewer). nullptr: built here.
  const EmbreeScene* whole_mesh_bvh = nullptr;
  /// Progress in [0, 1]; return false to cancel (the bake then throws hb::Cancelled, even
  /// when the cancel comes with the last call). Called on the calling thread only, about
  /// every 50 ms and at the end of each box. With several ranks, each rank reports its own
  /// share (rank 0's stands for the job: the shares are even).
  ProgressCallback progress;
  /// The ranks sharing a scene bake (nullptr: this process alone). Every rank calls
  /// bake_scene / bake_scene_from_lists with the same mesh, pieces and options. The position
  /// points of all boxes are cut into chunks dealt to the ranks in turn; each rank casts its
  /// chunks' rays; the tables (and triangle ids) travel once, to rank 0, which assembles the
  /// scene: the same bytes as one process. The other ranks return a scene with no boxes,
  /// unless `scene_on_every_rank` (then every rank receives every table: for a job that
  /// queries the scene on all ranks next, e.g. a report or a sweep).
  Communicator* communicator = nullptr;
  bool scene_on_every_rank = false;
};

/// Statistics of a bake.
struct BakeStats {
  double seconds = 0.0;
  std::uint64_t rays = 0;
  double rays_per_second = 0.0;
  std::uint64_t hits = 0;
  /// With several ranks, on rank 0 (the ranks that receive the scene): per rank, the rays it
  /// cast (`work`), the seconds its share took (scene builds and rays, before the gather) and
  /// the bytes it sent; one entry (rank 0) for a one-process bake.
  std::vector<RankWork> ranks;
  /// Bytes of the tables and triangle ids as held in memory (before any codec): what the
  /// gather moves, less rank 0's own share.
  std::uint64_t table_bytes = 0;
};

/// Bakes one box around the given triangles of `mesh` (all when empty): fits the PBB, then
/// for every position point of every face casts the 12 n^2 directional rays into the box
/// against those triangles only, on all cores (TBB). Each sample stores the first hit's
/// distance and shaded normal (outward); a miss, or a first hit on a back face (shaded normal
/// along the ray: the ray entered an open piece through its seam), stores kMissT.
/// Throws hb::InvalidInput (bad params, empty selection), hb::Cancelled, hb::LibraryError.
HapticBox bake_box(const TriangleMesh& mesh, const std::vector<std::uint32_t>& triangles,
                   const BakeOptions& options, BakeStats* stats = nullptr);

/// Bakes one box per piece: `piece_of_triangle[t]` is the piece id of triangle t (ids
/// 0..K-1; empty: one piece). Progress covers all pieces.
BoxScene bake_scene(const TriangleMesh& mesh, const std::vector<std::uint32_t>& piece_of_triangle,
                    const BakeOptions& options, const SourceInfo& source, BakeStats* stats = nullptr);

/// Bakes one box per triangle list (lists may overlap, e.g. pieces sharing seam triangles,
/// see hb::piece_triangle_lists); an empty list stands for all triangles. Throws
/// hb::InvalidInput on no lists or an out-of-range triangle id.
BoxScene bake_scene_from_lists(const TriangleMesh& mesh, const std::vector<std::vector<std::uint32_t>>& piece_triangles,
                    const BakeOptions& options, const SourceInfo& source, BakeStats* stats = nullptr);

} // namespace hb
