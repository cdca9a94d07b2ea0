#pragma once
// What a box scene is built from (SceneParts): its boxes, the mesh facts, the grid, the
// surface, the route asked for, the bake's report and the stroke route. A BoxScene takes them
// whole and is const after; a variant of a scene is a new scene from changed parts.
#include "perception/budget_report.h"
#include "box/haptic_box.h"
#include "scene/scene_route.h"
#include "mesh/triangle_mesh.h"
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

namespace hb {

class ExactQuery;
class SceneGrid;

/// Facts about the mesh a scene was baked from, stored in box files.
struct SourceInfo {
  std::string mesh_path;          ///< as given to the bake.
  std::uint64_t mesh_hash = 0;    ///< xxHash64 of the mesh file's bytes.
  std::uint64_t triangles = 0;
  float diagonal = 0.f;           ///< bounding-box diagonal of the whole mesh, model units.
};

/// A mesh and exact Embree over it: a scene's SceneRoute::embree (over its surface) or its
/// stroke route (over the full mesh).
struct SceneEmbree {
  TriangleMesh mesh;
  std::unique_ptr<ExactQuery> exact;
  std::shared_ptr<const SurfaceTriangles> over;  ///< the surface it was built from (nullptr: a mesh of its own).
  /// Over a surface's triangles (their corners and normals; equal corners one vertex).
  explicit SceneEmbree(std::shared_ptr<const SurfaceTriangles> surface);
  /// Over a mesh of its own, which needs a unit normal per vertex; throws hb::InvalidInput
  /// naming what is missing.
  explicit SceneEmbree(TriangleMesh full);
  ~SceneEmbree();
};

/// Everything a BoxScene is built from.
struct SceneParts {
  SceneParts() = default;
  /// The geometry; the route, report and stroke route keep their defaults.
  explicit SceneParts(std::vector<HapticBox> boxes_, SourceInfo source_ = {},
                      std::vector<std::uint32_t> piece_of_triangle_ = {},
                      std::shared_ptr<const SceneGrid> grid_ = nullptr,
                      std::shared_ptr<const SurfaceTriangles> surface_ = nullptr)
      : boxes(std::move(boxes_)), source(std::move(source_)), piece_of_triangle(std::move(piece_of_triangle_)),
        grid(std::move(grid_)), surface(std::move(surface_)) {}

  std::vector<HapticBox> boxes;
  SourceInfo source;
  /// The piece (box index) of each triangle of the source mesh before the seams were shared,
  /// as the bake cut it; empty for one box.
  std::vector<std::uint32_t> piece_of_triangle;
  /// The scene grid (scene_grid.h), or nullptr; names only boxes of `boxes`.
  std::shared_ptr<const SceneGrid> grid;
  /// The mesh the scene answers exactly from through the grid's surface cells when no box
  /// holds triangle ids; refining boxes must refine against it. The scene fills it from its
  /// refining boxes when they share one.
  std::shared_ptr<const SurfaceTriangles> surface;
  /// The route asked for: SceneRoute::cells falls back to the boxes when there are no surface
  /// cells; SceneRoute::embree needs a surface without a normal map.
  SceneRoute route = SceneRoute::cells;
  /// What a budgeted bake chose and achieved (BudgetReport::present false otherwise).
  BudgetReport budget;
  /// The stroke route: exact Embree over the full mesh answering a probe's successive queries
  /// (where the bake measured it faster along strokes than the cells); nullptr: none.
  std::shared_ptr<const SceneEmbree> stroke;
  /// Embree over `surface` for SceneRoute::embree; built by the scene when missing or over
  /// another surface, so that scenes made from one scene's parts share it.
  std::shared_ptr<const SceneEmbree> embree;
};

/// A scene's memory, bytes.
struct SceneBytes {
  std::size_t tables = 0;      ///< the boxes' sample tables.
  std::size_t refinement = 0;  ///< triangle ids and the surface the boxes share (once).
  std::size_t embree = 0;      ///< the Embree routes' meshes (the trees beside them are Embree's).
  /// What the queries read: tables, refinement, the surface's normal map, the grid, the
  /// surface cells and the Embree meshes (what `sweep` and `report` call its memory).
  std::size_t memory = 0;
};

/// Whether any box holds triangle ids (HapticBox::refines).
bool has_triangle_ids(const SceneParts& parts) noexcept;
/// Whether every box holds a table (false: frames, see without_tables()).
bool has_tables(const SceneParts& parts) noexcept;
/// The stroke route over `mesh` (SceneParts::stroke); throws hb::InvalidInput when it has no
/// triangles or no normal per vertex.
std::shared_ptr<const SceneEmbree> make_stroke_route(TriangleMesh mesh);

} // namespace hb
