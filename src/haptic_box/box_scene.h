#pragma once
#include "haptic_box/budget_report.h"
#include "haptic_box/haptic_box.h"
#include "haptic_box/surface_cells.h"
#include <memory>
#include <string>
#include <vector>

namespace hb {

/// Facts about the mesh a scene was baked from, stored in box files.
struct SourceInfo {
  std::string mesh_path;          ///< as given to the bake.
  std::uint64_t mesh_hash = 0;    ///< xxHash64 of the mesh file's bytes.
  std::uint64_t triangles = 0;
  float diagonal = 0.f;           ///< bounding-box diagonal of the whole mesh, model units.
};

/// How a routed query of a scene whose boxes refine finds the contact.
enum class SceneRoute : std::uint8_t {
  /// The boxes the grid names answer (their samples' triangle ids, refined exactly), then the
  /// triangles of the surface cells before the contact confirm it (the route until
  /// 2026-12-02; the per-probe query state resumes this route only).
  boxes,
  /// The triangles listed in the surface cells the segment crosses answer directly: the first
  /// crossing, cell by cell from the handle, shaded as exact's (no box is asked). The same
  /// contacts as `boxes` (both apply exact's first-crossing rule), 2.3-4.7x faster in random
  /// order on the default bakes (docs/speed.md). The default. Only with the surface cells (SurfaceCells)
  /// and UnconfirmedBlend::reject. Needs no handle state: a handle outside every box or in a
  /// surface cell is answered by the same walk (only a handle in an inside cell exits early).
  cells,
  /// Exact Embree over the scene's surface (the full mesh's triangles, as the surface cells
  /// hold them): the same contacts as `cells`, chosen at bake time where Embree answers faster
  /// than the surface cells (small and medium meshes: the budgeted bake times both on its
  /// tuning probes, BudgetReport::route). Needs a surface without a normal map.
  embree,
};

/// "boxes", "cells" or "embree".
inline const char* route_name(SceneRoute route) noexcept {
  return route == SceneRoute::cells ? "cells" : route == SceneRoute::embree ? "embree" : "boxes";
}

/// What a refining scene does with a blended answer its exact refinement cannot confirm
/// (the refinement finds no triangle of the box's samples near the blended surface).
enum class UnconfirmedBlend : std::uint8_t {
  /// Never answers with it: the next box's confirmed contact along the segment answers
  /// instead, or none. No force where no triangle is (the default; docs/stability.md).
  reject,
  /// The answer of the first refining scenes: the blend nearest the handle wins and keeps its
  /// blended answer when refinement fails (ghost surfaces up to 1 mm from any triangle).
  keep,
};

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

/// A scene of haptic boxes, one per piece. A query culls by PBB and the valid contact
/// nearest the handle wins, so its cost grows with the boxes the segment meets.
/// Culling: the segment is tested against the axis-aligned bounds of every PBB in one flat
/// loop over arrays of bounds; only the boxes it meets run their query (their own exact PBB
/// slab test first). Measured with 5, 20 and 100 boxes (random segments, half meeting no
/// box) this was 3-6x cheaper per query than letting every box run its OBB slab test; a
/// tree over the bounds was not needed at these counts (the boxes met dominate the cost).
///
/// With a scene grid (baked with the boxes, see scene_grid.h) a query first looks up the
/// handle's cell: inside the object, no contact (the first crossing leaves the object)
/// without a box query; outside, it walks the cells from the handle to the tip and asks
/// only the boxes whose pieces have surface in the cells it crosses, stopping one cell past
/// the nearest contact found: one box query in the common case. A handle in a cell with
/// surface is inside or outside by the triangles of its cell (SurfaceCells), and a box's
/// contact stands only when the segment crosses no other triangle of those cells nearer
/// (box_scene.cpp, step 7); a handle whose cell cannot tell (an open mesh) takes the path
/// without the grid.
class BoxScene final : public ContactQuery {
public:
  BoxScene() = default;
  /// `piece_of_triangle`: see piece_of_triangle(); empty when unknown or one box. `grid`,
  /// when given, must name only boxes of `boxes`. Throws hb::InvalidInput when either names a
  /// box the scene does not have.
  /// `surface`, when given, is the mesh the scene answers exactly from through the grid's
  /// surface cells (SceneRoute::cells) although no box holds triangle ids (see
  /// without_triangle_ids()); refining boxes must refine against it. Throws hb::InvalidInput
  /// when it differs from theirs.
  explicit BoxScene(std::vector<HapticBox> boxes, SourceInfo source = {},
                    std::vector<std::uint32_t> piece_of_triangle = {},
                    std::shared_ptr<const SceneGrid> grid = nullptr,
                    std::shared_ptr<const SurfaceTriangles> surface = nullptr);

  Contact query(const Segment& segment, const ForceLaw& law) const noexcept override;
  /// The query of a probe that moves a little between calls (see SceneQueryState).
  /// On the cells route: while both ends of the segment stay within kFreeReach cells of the
  /// last segment walked in full, no point of it up to that walk's free_to is on a triangle
  /// (each was at least a cell from all of them and moved less), so the walk starts there;
  /// otherwise the walk from the handle, which the state then remembers. The same crossings
  /// as the stateless walk (tests/core, strokes).
  /// On the boxes' route: when the
  /// last contact's box refines and the grid routes the handle (outside cell), the segment is
  /// first tried against the last contact's triangle with a walk of at most
  /// kStateWalkSteps edges (HapticBox::query_near); that answer stands when the crossing is a
  /// contact and every surface cell the segment crosses up to it names only that box (so
  /// the full query would ask that box alone). Otherwise, and for scenes without a grid, the
  /// full query, and the state learns its box and triangle. The answers are the full
  /// query's wherever that box's refinement finds the same triangle (tests/core, strokes).
  Contact query(const Segment& segment, const ForceLaw& law, SceneQueryState& state) const noexcept;
  static constexpr int kStateWalkSteps = 4;
  static constexpr float kFreeReach = 0.75f;
  /// Two crossings of a segment closer than this fraction of its length are one (a triangle
  /// tested from the handle and from a box's entry differ by rounding).
  static constexpr float kSameCrossing = 1e-5f;
  /// The same answers as query() one by one. A one-box scene runs HapticBox::query_many
  /// (fetches of a group of queries overlapped); the cells route on a surface larger than the
  /// last-level cache runs several queries' walks side by side (SurfaceCells::
  /// first_crossings_along); otherwise query() in a loop.
  void query_many(const Segment* segments, std::size_t count, const ForceLaw& law,
                  Contact* out) const noexcept override;

  /// The tool's broad phase (ContactQuery::within_reach): the grid's clearance when the scene
  /// has one, else whether a box's axis-aligned bounds come within `radius` of `centre`.
  bool within_reach(const Vec3& centre, float radius) const noexcept override;
  /// A tool's segments from one handle (ContactQuery::query_star): on the cells route, only
  /// the segments whose direction meets a surface cell within their reach are walked; the
  /// same answers as query() (box_scene_star.cpp).
  void query_star(const Vec3& start, const Vec3* tips, std::size_t count, const ForceLaw& law, Contact* out,
                  StarScratch& scratch) const noexcept override;

  /// How many boxes' PBBs the segment meets.
  std::size_t boxes_met(const Segment& segment) const noexcept;
  /// How many box queries query() runs for this segment (HapticBox::query_into calls,
  /// backward inside tests included): what its cost is made of.
  std::size_t box_queries(const Segment& segment, const ForceLaw& law) const noexcept;

  /// The scene grid, or nullptr (one box, or a file from before version 5).
  const std::shared_ptr<const SceneGrid>& grid() const { return grid_; }
  /// The same boxes without the grid (every query takes the path without it; for
  /// before/after measurements).
  BoxScene without_grid() const {
    BoxScene s(boxes_, source_, piece_of_triangle_, nullptr, surface_);
    s.budget_ = budget_;
    s.route_ = route_;
    s.embree_ = embree_;
    s.stroke_ = stroke_;
    return s;
  }
  /// The same scene with no box holding triangle ids, the surface kept for the grid's
  /// surface cells: what the cells route reads (the default bake stores this, issue 17: the
  /// ids were two thirds of a file and no default query read them). The cells route's
  /// answers are unchanged; `--route boxes` then has only the blends. A scene without
  /// surface cells is returned as it is (its boxes' ids are what refines it).
  BoxScene without_triangle_ids() const;
  /// Whether any box holds triangle ids (HapticBox::refines): what SceneRoute::boxes and the
  /// per-probe query state refine with.
  bool has_triangle_ids() const noexcept;
  /// The same scene with every box a frame (HapticBox::frame: its OBB and sampling, no table,
  /// no triangle ids), the surface, grid and piece ids kept, answered by exact Embree over the
  /// surface: what a scene the bake routes to Embree stores (its tables and ids were most of
  /// its file and that route never reads them). The window still draws the frames and the
  /// pieces; `--route cells` still answers where the grid has surface cells. Throws
  /// hb::InvalidInput as set_route(SceneRoute::embree).
  BoxScene without_tables() const;
  /// Whether every box holds a table (false: frames, see without_tables()).
  bool has_tables() const noexcept;

  /// A copy with every box's table compressed (see HapticBox::compressed); throws
  /// hb::InvalidInput when a box is already compressed or the options are out of range.
  BoxScene compressed(const CodecOptions& options) const;

  /// Policy for unconfirmed blends of refining boxes (no effect without refinement).
  void set_unconfirmed_blend(UnconfirmedBlend policy) noexcept { unconfirmed_ = policy; }
  UnconfirmedBlend unconfirmed_blend() const noexcept { return unconfirmed_; }
  /// Whether the routed query uses the triangles below the grid's surface cells
  /// (SurfaceCells; default true, only for scenes with a grid whose boxes refine against one
  /// shared surface and UnconfirmedBlend::reject): a handle in a surface cell is inside or
  /// outside by a test on its cell's triangles (no backward box queries), and a box's
  /// contact stands only when no triangle of the cells before it is crossed nearer (the
  /// first crossing decides, as exact's rule). False: the grid alone (the routing before
  /// 2026-12-02 noon, for before/after measurements).
  void set_cell_triangles(bool on) noexcept { use_cells_ = on; }
  bool cell_triangles() const noexcept { return use_cells_ && cells_ != nullptr; }
  /// See SceneRoute (no effect without surface cells). SceneRoute::embree builds an Embree
  /// tree over the surface (once; the copies of this scene share it) and throws
  /// hb::InvalidInput when the scene has no surface or its surface carries a normal map (a
  /// simplified stand-in that only the cells shade as the full mesh). Also throws when the
  /// route would leave the boxes to answer and they are frames (without_tables()).
  void set_route(SceneRoute route);
  SceneRoute route() const noexcept { return route_; }
  /// What answers, by name: "embree", "cells", "boxes" (boxes refining from their triangle
  /// ids) or "raw" (the paper's haptic box: boxes answering from their samples alone).
  const char* answering_name() const noexcept {
    const SceneRoute r = answering_route();
    return r == SceneRoute::boxes && !refines() ? "raw" : route_name(r);
  }
  /// Takes `other`'s Embree tree (built by its set_route(SceneRoute::embree)) when both
  /// scenes answer from the same surface, the same object: this scene's Embree route then
  /// builds none. For a search composing several scenes over one surface (the budgeted bake
  /// times Embree at its steps 2b and 5b). Returns whether it took it.
  bool take_embree_tree(const BoxScene& other) noexcept {
    if (!other.embree_ || !surface_ || other.surface_ != surface_) return false;
    embree_ = other.embree_;
    return true;
  }
  /// Whether query_many() on the cells route runs its walks side by side: when the surface
  /// exceeds the last-level cache (automatic, SurfaceCells::walks_side_by_side), always or
  /// never (for tests and before/after figures). The same answers either way.
  enum class SideBySide { automatic, always, never };
  void set_side_by_side(SideBySide mode) noexcept { side_by_side_ = mode; }
  /// The route the queries take: `route()` when the scene has what it needs (the cells route
  /// needs surface cells, set_cell_triangles and UnconfirmedBlend::reject), boxes otherwise.
  SceneRoute answering_route() const noexcept {
    if (route_ == SceneRoute::embree && embree_) return SceneRoute::embree;
    return route_ != SceneRoute::boxes && use_cells_ && cells_ && unconfirmed_ == UnconfirmedBlend::reject
               ? SceneRoute::cells
               : SceneRoute::boxes;
  }
  /// The triangles below the grid's surface cells, or nullptr (no grid, or no shared surface).
  const std::shared_ptr<const SurfaceCells>& surface_cells() const { return cells_; }
  /// Every box's refinement walk policy (HapticBox::set_walk_all_candidates; default true).
  void set_walk_all_candidates(bool on) noexcept {
    for (HapticBox& b : boxes_) b.set_walk_all_candidates(on);
  }
  /// Whether the scene answers exactly: a box refines (HapticBox::refines), or the grid's
  /// surface cells answer (a scene without triangle ids, see without_triangle_ids()).
  bool refines() const noexcept;
  /// The surface the scene refines against (its refining boxes' one, or the one given to
  /// the constructor), or nullptr.
  const std::shared_ptr<const SurfaceTriangles>& surface() const { return surface_; }

  const std::vector<HapticBox>& boxes() const { return boxes_; }
  const SourceInfo& source() const { return source_; }
  /// The piece (box index) of each triangle of the source mesh before the seams were shared,
  /// as the bake cut it (stored in the .hbox file since version 4); empty for one box, or when
  /// the file predates version 4.
  const std::vector<std::uint32_t>& piece_of_triangle() const { return piece_of_triangle_; }
  /// Replaces the piece ids (same checks as the constructor).
  void set_piece_of_triangle(std::vector<std::uint32_t> piece_of_triangle);
  std::size_t table_bytes() const;
  /// What a budgeted bake chose and achieved (BudgetReport::present false otherwise); stored
  /// in box files from version 6.
  const BudgetReport& budget_report() const { return budget_; }
  /// Also takes the route the report names (BudgetReport::answer "embree": the bake measured
  /// Embree faster than the surface cells on this scene), when the scene can take it.
  void set_budget_report(BudgetReport report) {
    budget_ = std::move(report);
    if (budget_.answer == "embree" && surface_ && surface_->normal_map_side() == 0) set_route(SceneRoute::embree);
  }
  /// Bytes the exact refinement adds (0 without it): every box's triangle ids and the
  /// surface the boxes share (once).
  std::size_t refinement_bytes() const;
  /// Bytes the scene's queries read: the tables, refinement_bytes(), the surface's normal map,
  /// the scene grid and the surface cells (what `sweep` and `report` call its memory).
  std::size_t memory_bytes() const;
  /// Bytes of the Embree routes' meshes (the scene route's vertices, three a triangle, and
  /// the stroke route's full mesh; the trees beside them are Embree's); 0 without either.
  std::size_t embree_bytes() const noexcept;

  /// The stroke route (issue 37: never slower than exact, along strokes too): a probe's
  /// successive queries (query() with a SceneQueryState: the servo loop, the window, bench's
  /// strokes) answered by exact Embree over the full mesh, where the bake measured that
  /// faster along strokes than the surface cells on a simplified surface (the armadillo at
  /// 832K triangles: the cells 2.2x faster than Embree in random order, 1.15x slower along
  /// strokes, whose successive rays find Embree's tree in cache). Queries without a state
  /// keep the cells. Builds Embree over `mesh` (which needs a vertex normal per vertex);
  /// throws hb::InvalidInput when it has no triangles or normals. Only a scene the cells
  /// answer takes it (the route of other scenes is unchanged; see stroke_route()).
  void set_stroke_mesh(TriangleMesh mesh);
  /// The stroke route's mesh, or nullptr.
  const TriangleMesh* stroke_mesh() const noexcept;
  /// What a probe's query takes, without a state: exact Embree over the stroke mesh when
  /// stroke_route() is it, query(segment, law) otherwise (a servo loop's cache priming,
  /// SceneProbe::prime, warms what the next tick reads).
  Contact query_as_stroke(const Segment& segment, const ForceLaw& law) const noexcept;
  /// Whether a query with a SceneQueryState is answered by Embree over the full mesh: the
  /// scene has a stroke mesh and the cells answer it (any other route keeps its own).
  bool strokes_by_full_mesh() const noexcept { return stroke_ && answering_route() == SceneRoute::cells; }
  /// What answers a query with a SceneQueryState: SceneRoute::embree over the full mesh when
  /// strokes_by_full_mesh(), answering_route() otherwise.
  SceneRoute stroke_route() const noexcept { return strokes_by_full_mesh() ? SceneRoute::embree : answering_route(); }
  /// The same scene without the stroke route (its probes walk the cells: before/after figures).
  BoxScene without_stroke_mesh() const {
    BoxScene s = *this;
    s.stroke_.reset();
    return s;
  }

private:
  // The query through the grid; false when the handle's cell leaves it to query_met().
  // `box` and `triangle`, when given, receive the answering box and refined triangle.
  bool query_routed(const Segment& segment, const ForceLaw& law, Contact& out, std::size_t* asked,
                    std::uint32_t* box = nullptr, std::uint32_t* triangle = nullptr) const noexcept;
  // The query without the grid: every box whose PBB the segment meets.
  Contact query_met(const Segment& segment, const ForceLaw& law, std::size_t* asked, std::uint32_t* box = nullptr,
                    std::uint32_t* triangle = nullptr, DecodedQuads* quads = nullptr) const noexcept;
  // A scene of `boxes` (this scene's, each changed alike) with this scene's source, piece ids,
  // grid, surface, route, Embree tree and settings.
  BoxScene with_boxes(std::vector<HapticBox> boxes) const;
  // Boxes in [first, last) whose axis-aligned bounds the segment meets, written into `out`.
  std::size_t cull(const Segment& segment, std::size_t first, std::size_t last, std::uint32_t* out) const noexcept;

  std::vector<HapticBox> boxes_;
  SourceInfo source_;
  std::vector<std::uint32_t> piece_of_triangle_;
  UnconfirmedBlend unconfirmed_ = UnconfirmedBlend::reject;
  // Axis-aligned bounds of each PBB, structure of arrays: lo x, y, z then hi x, y, z.
  std::vector<float> bounds_[6];
  std::shared_ptr<const SceneGrid> grid_;
  std::shared_ptr<const SurfaceTriangles> surface_;
  std::shared_ptr<const SurfaceCells> cells_;
  bool use_cells_ = true;
  SceneRoute route_ = SceneRoute::cells;
  SideBySide side_by_side_ = SideBySide::automatic;
  BudgetReport budget_;
  // SceneRoute::embree: the surface as a mesh and Embree over it (box_scene_parts.h, box_scene_build.cpp).
  struct EmbreeRoute;
  std::shared_ptr<const EmbreeRoute> embree_;
  // The stroke route: Embree over the full mesh (set_stroke_mesh).
  std::shared_ptr<const EmbreeRoute> stroke_;
  // The routed query's cell-triangle steps (box_scene.cpp, step 7).
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

/// One probe querying a scene through its own SceneQueryState, as a ContactQuery (for timing
/// and for loops written against ContactQuery). Not safe from several threads.
class SceneProbe final : public ContactQuery {
public:
  explicit SceneProbe(const BoxScene& scene) : scene_(scene) {}
  Contact query(const Segment& segment, const ForceLaw& law) const noexcept override {
    return scene_.query(segment, law, state_);
  }
  /// The query the next tick takes, without the state (which stays the last tick's): the
  /// stroke route's Embree when the scene has one, the stateless query otherwise.
  void prime(const Segment& segment, const ForceLaw& law) const noexcept override {
    const Contact c = scene_.query_as_stroke(segment, law);
    asm volatile("" : : "r"(&c) : "memory");
  }
  const SceneQueryState& state() const { return state_; }
  void reset() { state_ = SceneQueryState{}; }

private:
  const BoxScene& scene_;
  mutable SceneQueryState state_;
};

} // namespace hb
