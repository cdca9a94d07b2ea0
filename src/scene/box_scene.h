#pragma once
#include "scene/scene_parts.h"
#include "surface/surface_cells.h"
#include <memory>
#include <string>
#include <vector>

namespace hb {

/// One probe's memory between queries (a servo loop's ticks, a stroke), and counts of how
/// its queries were answered. Not shared between threads or probes; a default-constructed
/// state knows nothing.
struct SceneQueryState {
  static constexpr std::uint32_t kNone = 0xffffffffu;
  /// The boxes' route: the box and surface triangle of the last contact.
  std::uint32_t box = kNone;
  std::uint32_t triangle = kNone;
  /// The cells route: a segment walked from its handle, and how far along it the walk stayed
  /// at least a cell from every triangle (SurfaceCells::first_crossing_along's s_free), and
  /// the cells walked (a weak reference: a scene loaded later cannot take them for its own).
  std::weak_ptr<const SurfaceCells> walked_cells;
  Vec3 walked_start{Vec3::Zero()}, walked_end{Vec3::Zero()};
  float free_to = 0.f;
  /// A one-box scene's block-coded table: the last quads decoded (DecodedQuads) and the
  /// table's owner they belong to (a weak reference, as walked_cells).
  DecodedQuads quads;
  std::weak_ptr<const void> quads_owner;
  /// The cells route over a surface with a normal map: the last map cell's three decoded
  /// normals (SurfaceTriangles::LatticeCache; reset with walked_cells).
  SurfaceTriangles::LatticeCache lattice;
  std::uint64_t from_state = 0;  ///< queries answered from the state (see BoxScene::query).
  std::uint64_t full = 0;        ///< queries answered by the full query.
};

/// A scene of haptic boxes, one per piece, built once from its SceneParts and const after:
/// every query is safe from many threads, and what answers (SceneRoute) is decided when the
/// scene is built, never per query.
///
/// Routes. `cells` (the default): the triangles listed in the surface cells the segment
/// crosses answer, the first crossing from the handle, shaded as exact's. `embree`: exact
/// Embree over the scene's surface (the bake takes it where Embree measured faster). `boxes`:
/// the boxes answer (the paper's haptic box; refined from their triangle ids when they hold
/// them). The boxes route culls by PBB and the valid contact nearest the handle wins; with a
/// scene grid it walks the cells from the handle and asks only the boxes whose pieces have
/// surface in the cells it crosses (box_scene.cpp explains each step). A blended answer that
/// a refining box cannot confirm never answers (no force where no triangle is).
///
/// A probe's successive queries (a servo loop, a stroke) pass their own SceneQueryState; with
/// a stroke route (SceneParts::stroke) those are answered by exact Embree over the full mesh.
class BoxScene final : public ContactQuery {
public:
  BoxScene() = default;
  /// Builds the scene: checks the parts (throws hb::InvalidInput naming what is wrong: a
  /// grid or piece id naming a box the scene does not have, boxes refining against different
  /// surfaces than `parts.surface`, a route the parts cannot take), resolves the route and
  /// builds what it needs (the surface cells, Embree over the surface for SceneRoute::embree
  /// unless `parts.embree` already holds it).
  explicit BoxScene(SceneParts parts);

  Contact query(const Segment& segment, const ForceLaw& law) const noexcept override;
  /// The query of a probe that moves a little between calls, its memory in `state`: the
  /// same answers as query() (tests/core, strokes), found from where the last walk stayed
  /// clear of the surface; answered by the stroke route when the scene has one.
  Contact query(const Segment& segment, const ForceLaw& law, SceneQueryState& state) const noexcept;
  /// The same answers as query() one by one, several walks or fetches overlapped.
  void query_many(const Segment* segments, std::size_t count, const ForceLaw& law,
                  Contact* out) const noexcept override;
  /// A tool's segments from one handle: on the cells route only the segments whose
  /// direction meets a surface cell within their reach are walked; the same answers as
  /// query() (box_scene_star.cpp).
  void query_star(const Vec3& start, const Vec3* tips, std::size_t count, const ForceLaw& law, Contact* out,
                  StarScratch& scratch) const noexcept override;
  /// A tool's broad phase: the grid's clearance when the scene has one, else whether a box's
  /// axis-aligned bounds come within `radius` of `centre`.
  bool within_reach(const Vec3& centre, float radius) const noexcept override;
  /// Reads what a probe's next query reads (the stroke route's Embree when the scene has one)
  /// and discards it (ContactQuery::prime).
  void prime(const Segment& segment, const ForceLaw& law) const noexcept override;

  /// What the scene was built from (with the surface it resolved and the Embree trees it
  /// built: a scene built from a copy of these builds none again).
  const SceneParts& parts() const noexcept { return parts_; }
  /// What answers a query without a state.
  SceneRoute route() const noexcept { return route_; }
  /// What answers a query with a SceneQueryState: SceneRoute::embree over the full mesh
  /// when the scene has a stroke route and the cells answer it, route() otherwise.
  SceneRoute stroke_route() const noexcept { return stroke_route_; }
  /// The triangles below the grid's surface cells, or nullptr (no grid, or no shared surface).
  const std::shared_ptr<const SurfaceCells>& cells() const noexcept { return cells_; }
  /// Whether the scene answers exactly: a box refines, or the grid's surface cells answer.
  bool refines() const noexcept { return cells_ != nullptr || has_triangle_ids(parts_); }
  /// The scene's memory by part (SceneBytes).
  SceneBytes bytes() const noexcept;
  /// How many box queries query() runs for this segment (0 on the Embree and cells routes):
  /// what the boxes route's cost is made of.
  std::size_t box_queries(const Segment& segment, const ForceLaw& law) const noexcept;

private:
  // The boxes route through the grid; false when the handle's cell leaves it to query_met().
  // `box` and `triangle`, when given, receive the answering box and refined triangle.
  bool query_routed(const Segment& segment, const ForceLaw& law, Contact& out, std::size_t* asked,
                    std::uint32_t* box = nullptr, std::uint32_t* triangle = nullptr) const noexcept;
  // The boxes route without the grid: every box whose PBB the segment meets.
  Contact query_met(const Segment& segment, const ForceLaw& law, std::size_t* asked, std::uint32_t* box = nullptr,
                    std::uint32_t* triangle = nullptr, DecodedQuads* quads = nullptr) const noexcept;
  // query(segment, law, state) on the cells and boxes routes.
  Contact query_cells_stroke(const Segment& segment, const ForceLaw& law, SceneQueryState& state) const noexcept;
  Contact query_boxes_stroke(const Segment& segment, const ForceLaw& law, SceneQueryState& state) const noexcept;
  // Boxes in [first, last) whose axis-aligned bounds the segment meets, written into `out`.
  std::size_t cull(const Segment& segment, std::size_t first, std::size_t last, std::uint32_t* out) const noexcept;
  // The SceneRoute::cells answers of segments[0, count), their walks side by side.
  void query_many_cells(const Segment* segments, std::size_t count, const ForceLaw& law, Contact* out) const noexcept;

  // A probe's query on the boxes route walks at most this many triangle edges from the last
  // contact's triangle; on the cells route its walk resumes while both ends stay within this
  // many cells of the last full walk.
  static constexpr int kStateWalkSteps = 4;
  static constexpr float kFreeReach = 0.75f;
  // Two crossings of a segment closer than this fraction of its length are one (a triangle
  // tested from the handle and from a box's entry differ by rounding).
  static constexpr float kSameCrossing = 1e-5f;

  SceneParts parts_;
  SceneRoute route_ = SceneRoute::boxes;
  SceneRoute stroke_route_ = SceneRoute::boxes;
  // Axis-aligned bounds of each PBB, structure of arrays: lo x, y, z then hi x, y, z.
  std::vector<float> bounds_[6];
  std::shared_ptr<const SurfaceCells> cells_;
  // The surface cells a routed walk crossed (box_scene.cpp, step 7).
  struct Visited;
  // SceneRoute::cells: the contact of the segment's first crossing among the surface cells'
  // triangles (none when it leaves the object).
  Contact first_crossing_contact(const Segment& segment, float length, const ForceLaw& law) const noexcept;
  // The contact of the segment's first crossing `triangle` (kNoTriangle: none), found by the
  // surface cells' walk; `front`: it enters the object.
  Contact crossing_contact(const Segment& segment, float length, const ForceLaw& law, std::uint32_t triangle,
                           bool front, SurfaceTriangles::LatticeCache* lattice = nullptr) const noexcept;
  bool settle_first_crossing(const Segment& segment, const ForceLaw& law, const Visited& visited, Contact& best,
                             float& best_along, std::uint32_t& best_box, std::uint32_t& best_triangle,
                             std::size_t* asked_count) const noexcept;
};

/// Whether a probe's queries are answered by exact Embree over the full mesh (the scene has a
/// stroke route and the cells answer it).
inline bool strokes_by_full_mesh(const BoxScene& scene) noexcept {
  return scene.parts().stroke && scene.route() == SceneRoute::cells;
}
/// The stroke route's mesh, or nullptr.
inline const TriangleMesh* stroke_mesh(const BoxScene& scene) noexcept {
  return scene.parts().stroke ? &scene.parts().stroke->mesh : nullptr;
}
/// What answers `scene`'s queries, as its reports name it (Answerer::raw_box when boxes that
/// do not refine answer).
Answerer answerer(const BoxScene& scene) noexcept;
/// How many boxes' PBBs the segment meets.
std::size_t boxes_met(const BoxScene& scene, const Segment& segment) noexcept;
/// The parts of `scene` with no box holding triangle ids, the surface kept for the grid's
/// surface cells: what the cells route reads (the default bake stores this). The parts as
/// they are when the scene has no surface cells (its boxes' ids are what refines it).
SceneParts without_triangle_ids(const BoxScene& scene);
/// The parts of `scene` with every box a frame (its OBB and sampling, no table, no triangle
/// ids) answered by exact Embree over the surface: what a scene the bake routes to Embree
/// stores. Building them throws as SceneRoute::embree does.
SceneParts without_tables(const BoxScene& scene);
/// The parts of `scene` with every box's table compressed (HapticBox::compressed); throws
/// hb::InvalidInput when a box is already compressed or the options are out of range.
SceneParts compressed(const BoxScene& scene, const CodecOptions& options);
/// The same scene answered by `route` (a new scene: the parts with that route).
BoxScene with_route(const BoxScene& scene, SceneRoute route);
/// The same scene with `budget` as its bake's report (a new scene).
BoxScene with_budget(const BoxScene& scene, BudgetReport budget);

/// One probe querying a scene through its own SceneQueryState, as a ContactQuery (for timing
/// and for loops written against ContactQuery). Not safe from several threads.
class SceneProbe final : public ContactQuery {
public:
  explicit SceneProbe(const BoxScene& scene) : scene_(scene) {}
  Contact query(const Segment& segment, const ForceLaw& law) const noexcept override {
    return scene_.query(segment, law, state_);
  }
  /// The query the next tick takes, without the state (which stays the last tick's).
  void prime(const Segment& segment, const ForceLaw& law) const noexcept override { scene_.prime(segment, law); }
  const SceneQueryState& state() const { return state_; }
  void reset() { state_ = SceneQueryState{}; }

private:
  const BoxScene& scene_;
  mutable SceneQueryState state_;
};

} // namespace hb
