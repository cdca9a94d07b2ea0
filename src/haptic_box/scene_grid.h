#pragma once
// The scene grid: a uniform grid baked with a scene of several boxes, which routes a probe to
// the boxes whose pieces it can meet and answers "is the handle inside the object" in O(1).
#include "haptic_box/surface_subcells.h"
#include "haptic_box/surface_triangles.h"
#include "mesh/triangle_mesh.h"
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <memory>
#include <type_traits>
#include <vector>

namespace hb {

class EmbreeScene;

/// Options of build_scene_grid.
struct SceneGridOptions {
  /// Cell edge as a fraction of the mesh's bounding-box diagonal, in (0, 1].
  float cell = 1.f / 128.f;
  /// Most cells the grid may have (the cell grows by 25% steps until it fits), >= 1.
  std::size_t max_cells = std::size_t(1) << 24;
};

/// A uniform grid of cubic cells over a scene's mesh (1 cell of padding on every side).
/// Each cell holds one code:
/// - a surface cell (code >= kFirstSurface) lists the boxes to ask about the surface in it
///   (triangles meeting the cell by the exact triangle-box overlap test): the one box that
///   holds all of them and whose piece goes on furthest around the cell (seams are in two
///   boxes), or, when no box holds them all, every box holding one;
/// - a cell without surface is all inside or all outside the object (no triangle separates
///   its points). Its state comes from Embree rays cast from one cell of each connected
///   region of such cells: inside when the first hits of all 6 axis rays are back faces,
///   outside when none is; otherwise (an open mesh) kUnknown.
/// Built once (build_scene_grid or from file bytes), then queried through const noexcept
/// methods, safe from many threads.
class SceneGrid {
public:
  enum : std::uint16_t { kOutside = 0, kInside = 1, kUnknown = 2, kFirstSurface = 3 };
  /// Most distinct box lists (codes are 16 bits).
  static constexpr std::size_t kMaxLists = 65535 - kFirstSurface;

  SceneGrid() = default;
  /// Validates and takes the parts; throws hb::InvalidInput naming the inconsistency.
  SceneGrid(const Vec3& origin, float cell, const std::array<int, 3>& dims, std::vector<std::uint16_t> codes,
            std::vector<std::uint32_t> list_offsets, std::vector<std::uint32_t> list_boxes);

  /// The code of the cell holding p (kOutside beyond the grid, which covers the mesh).
  std::uint16_t code_at(const Vec3& p) const noexcept {
    const Vec3 f = (p - origin_) * inv_cell_;
    if (!(f.x() >= 0.f && f.y() >= 0.f && f.z() >= 0.f)) return kOutside;  // also NaN
    const int x = int(f.x()), y = int(f.y()), z = int(f.z());
    if (x >= dims_[0] || y >= dims_[1] || z >= dims_[2]) return kOutside;
    // A brick without surface has one state (its cells are one connected region): no load
    // of the cell words, whose bytes are mostly out of cache (bricks_ stays in L1/L2).
    const std::uint8_t brick = bricks_[brick_index(x, y, z)];
    if ((brick & kBrickSurface) != kBrickSurface) return std::uint16_t(brick & kBrickSurface);
    return std::uint16_t(cells_[cell_index(x, y, z)]);
  }
  /// The boxes of surface code `code` (>= kFirstSurface): [first, last).
  const std::uint32_t* boxes_begin(std::uint16_t code) const noexcept {
    return list_boxes_.data() + list_offsets_[code - kFirstSurface];
  }
  const std::uint32_t* boxes_end(std::uint16_t code) const noexcept {
    return list_boxes_.data() + list_offsets_[code - kFirstSurface + 1];
  }

  /// Visits the cells the segment a -> b crosses, in order from a: visit(code, s) with s in
  /// [0, 1] the segment parameter where the segment enters the cell (0 for a's cell); stops
  /// when visit returns false, after b's cell, or at the grid's end. Bounded by the sum of
  /// the dimensions. Cells beyond the grid are outside and not visited.
  template <class Visit>
  void walk(const Vec3& a, const Vec3& b, Visit&& visit) const noexcept;

  /// As walk(), but visits only the surface cells (codes >= kFirstSurface), in the same
  /// order and with the same s (a visitor taking a third argument, const int cell[3], also
  /// receives the cell's coordinates): runs of cells without surface are crossed in jumps as long as
  /// their clearance (clearance()) allows, instead of cell by cell. BoxScene's routing.
  template <class Visit>
  void walk_surface(const Vec3& a, const Vec3& b, Visit&& visit) const noexcept;

  /// Per cell (x fastest, as codes()), the chessboard distance in cells to the nearest
  /// surface cell (0 for one), capped at 255; computed from the codes when the grid is made.
  std::vector<std::uint8_t> clearance() const;

  bool empty() const { return codes_.empty(); }
  const Vec3& origin() const { return origin_; }
  float cell() const { return cell_; }
  const std::array<int, 3>& dims() const { return dims_; }
  const std::vector<std::uint16_t>& codes() const { return codes_; }
  std::size_t list_count() const { return list_offsets_.empty() ? 0 : list_offsets_.size() - 1; }
  /// The largest box index named (for checking against a scene), 0 when none.
  std::uint32_t max_box() const;
  /// Bytes in memory (and, to within 48, in a file).
  std::size_t bytes() const {
    return codes_.size() * 2 + (list_offsets_.size() + list_boxes_.size()) * 4;
  }
  /// Bytes in memory beyond bytes(): the cell words the queries read (cells_).
  std::size_t query_bytes() const { return cells_.size() * 4; }
  /// Per 4 x 4 x 4 brick of cells (x fastest): the state shared by all its cells when none
  /// has surface (kOutside, kInside, kUnknown; kBrickSurface when one has), and in bits 2-7
  /// the chessboard distance in bricks to the nearest brick with surface (capped at 63).
  /// Derived from the codes when the grid is made.
  const std::vector<std::uint8_t>& bricks() const { return bricks_; }
  static constexpr std::uint8_t kBrickSurface = 3;

  /// The file form (a section of the .hbox file, box_file_format.h): a small header, the codes, the lists.
  std::vector<std::uint8_t> serialize() const;
  /// Reads serialize()'s bytes; throws hb::InvalidInput (truncated, inconsistent).
  static SceneGrid deserialize(const std::uint8_t* data, std::size_t bytes);

private:
  /// Clips the segment a + s d, s in [0, 1], to the grid: [s0, s1] narrowed to the part
  /// inside; false when the segment misses the grid.
  bool clip(const Vec3& a, const Vec3& d, float& s0, float& s1) const noexcept;
  /// The walk's DDA state at parameter s: the cell holding a + s d, the step per axis, the
  /// parameter of the next boundary per axis and the parameter per cell.
  void dda_start(const Vec3& a, const Vec3& d, float s, int i[3], int step[3], float next[3],
                 float delta[3]) const noexcept;
  /// The walk of walk_surface: bricks far from the surface are jumped; in the others
  /// `on_cell(cell, s)` returns -1 (stop), 0 (the next cell) or the cells to jump (a
  /// clearance).
  template <class OnCell>
  void walk_bricks(const Vec3& a, const Vec3& b, OnCell&& on_cell) const noexcept;
  Vec3 origin_{Vec3::Zero()};
  float cell_ = 0.f, inv_cell_ = 0.f;
  std::array<int, 3> dims_{{0, 0, 0}};
  std::vector<std::uint16_t> codes_;
  std::vector<std::uint32_t> list_offsets_, list_boxes_;
  // What the queries read, one word a cell: the code (low 16 bits) and the clearance (bits
  // 16-23), in bricks of 4 x 4 x 4 cells (cell_index), so that a walk's next cell is mostly
  // in the same 256 bytes: one load a step, few of them misses (the codes in x-fastest
  // order and a separate clearance array cost two loads a step, one row apart in y and a
  // plane apart in z).
  std::vector<std::uint32_t> cells_;
  // One byte a brick (bricks()): a walk crosses empty space and a handle far from the
  // surface finds its state without touching cells_.
  std::vector<std::uint8_t> bricks_;
  int bricks_x_ = 0, bricks_y_ = 0;
  std::size_t brick_index(int x, int y, int z) const noexcept {
    return (std::size_t(z >> 2) * std::size_t(bricks_y_) + std::size_t(y >> 2)) * std::size_t(bricks_x_) + std::size_t(x >> 2);
  }
  std::size_t cell_index(int x, int y, int z) const noexcept {
    return brick_index(x, y, z) * 64 + std::size_t(((z & 3) << 4) | ((y & 3) << 2) | (x & 3));
  }
  void compute_clearance();
};

/// Below the grid's surface cells (issues 11 and 17): per surface cell, the surface slots of
/// the triangles meeting it (the grid's triangle-box test, on the triangles of the scene's
/// shared SurfaceTriangles) and the inside/outside state of its centre. Built from the grid
/// and the surface when a scene is made (bake or load: files need not store it, and files
/// of every version get it). It answers, exactly for a closed mesh:
/// - whether a point in a surface cell is inside the object (state_at): the crossing nearest
///   the point on the short segment to its cell's centre decides (a back face: inside, a
///   front face: outside), none gives the centre's state;
/// - the first triangle a segment crosses in given surface cells (first_crossing).
/// A centre's state comes from its 6 neighbours' in waves out from the grid's cells without
/// surface (inside or outside): the crossing nearest the centre on the segment to a decided
/// neighbour's centre (in the two cells), or that neighbour's state; neighbours that disagree
/// (an open mesh, a hole, a degenerate crossing) leave it kUnknown, and the scene then takes
/// its path without it. Immutable once built, queried through const noexcept methods.
class SurfaceCells {
public:
  /// The set bits of `mask` below bit `bit`: a cell's rank in its brick. Every step of a
  /// segment's walk asks it; the build targets plain x86-64 (no POPCNT instruction), where
  /// __builtin_popcountll is a call into libgcc, so without POPCNT this is the SWAR count
  /// inline (the same integer).
  static std::uint32_t cells_below(std::uint64_t mask, unsigned bit) noexcept {
    std::uint64_t m = mask & ((std::uint64_t(1) << bit) - 1);
#if defined(__POPCNT__)
    return std::uint32_t(__builtin_popcountll(m));
#else
    m = m - ((m >> 1) & 0x5555555555555555ull);
    m = (m & 0x3333333333333333ull) + ((m >> 2) & 0x3333333333333333ull);
    m = (m + (m >> 4)) & 0x0f0f0f0f0f0f0f0full;
    return std::uint32_t((m * 0x0101010101010101ull) >> 56);
#endif
  }
  static constexpr std::uint32_t kNone = 0xffffffffu;
  SurfaceCells() = default;
  /// Throws hb::InvalidInput when the grid is empty.
  SurfaceCells(const SceneGrid& grid, std::shared_ptr<const SurfaceTriangles> surface);

  bool empty() const { return offsets_.empty(); }
  /// The surface cell index of cell (x, y, z), kNone for a cell without surface or beyond
  /// the grid.
  std::uint32_t index(int x, int y, int z) const noexcept {
    if (x < 0 || y < 0 || z < 0 || x >= dims_[0] || y >= dims_[1] || z >= dims_[2]) return kNone;
    const std::size_t b = (std::size_t(z >> 2) * std::size_t(bricks_y_) + std::size_t(y >> 2)) * std::size_t(bricks_x_) +
                          std::size_t(x >> 2);
    const std::uint64_t mask = masks_[b];
    const unsigned bit = unsigned(((z & 3) << 4) | ((y & 3) << 2) | (x & 3));
    if (!((mask >> bit) & 1u)) return kNone;
    return base_[b] + std::uint32_t(cells_below(mask, bit));
  }
  /// The surface cell index of the cell holding p (kNone: none).
  std::uint32_t index_at(const Vec3& p) const noexcept {
    const Vec3 f = (p - origin_) * inv_cell_;
    if (!(f.x() >= 0.f && f.y() >= 0.f && f.z() >= 0.f)) return kNone;
    return index(int(f.x()), int(f.y()), int(f.z()));
  }
  /// Whether p, in a surface cell, is inside the object: SceneGrid::kInside, kOutside, or
  /// kUnknown (the cell's centre is undecided, or p is in no surface cell).
  std::uint16_t state_at(const Vec3& p) const noexcept;
  /// The state of surface cell `index`'s centre (SceneGrid::kInside, kOutside, kUnknown).
  std::uint16_t centre_state(std::uint32_t index) const noexcept { return states_[index]; }
  /// The triangles (surface slots) of surface cell `index`.
  const std::uint32_t* begin(std::uint32_t index) const noexcept { return slots_.data() + offsets_[index]; }
  const std::uint32_t* end(std::uint32_t index) const noexcept { return slots_.data() + offsets_[index + 1]; }
  std::size_t cell_count() const { return states_.size(); }
  /// The crossing nearest the handle of segment a -> b, s in [0, s_max], among the triangles
  /// of the surface cells cells[0, count) (SurfaceTriangles::first_crossing).
  bool first_crossing(const std::uint32_t* cells, std::size_t count, const Vec3& a, const Vec3& b, float s_max,
                      float& s, bool& front, std::uint32_t& triangle) const noexcept;
  /// The crossing nearest a of segment a -> b, s in [0, s_max] (s_max <= 1), among the
  /// triangles of every surface cell the segment passes through, visited cell by cell from a
  /// (SceneGrid::walk's order) and stopping at the first cell entered beyond the nearest
  /// crossing; empty space is jumped by each cell's chessboard clearance (a byte a cell, in
  /// the masks' brick order), the DDA's divisions are done once (CellDda), and a crowded
  /// cell is walked through its sub-cells (SurfaceSubcells).
  /// The walk starts at s_start (its part before must cross no triangle). `s_free`, when
  /// given, receives how far the segment stays at least a cell from every triangle: the s
  /// of the first cell it enters whose chessboard clearance is below 2 (1: none), so a
  /// segment whose ends are less than a cell from a and b crosses none before it
  /// (BoxScene::query with a SceneQueryState).
  bool first_crossing_along(const Vec3& a, const Vec3& b, float s_max, float& s, bool& front,
                            std::uint32_t& triangle, float s_start = 0.f, float* s_free = nullptr) const noexcept;
  /// A segment a -> b set up for a walk through the cells: a, b - a (o, d), the same in cell
  /// units from the grid's origin (fa, fd), 1 / fd per axis (inv, 0 where fd is 0), its part
  /// in the grid, s in [s0, s1] (s1 <= s_max), and the s a chessboard cell takes.
  struct WalkStart {
    float o[3], d[3], fa[3], fd[3], inv[3];
    float s0, s1, s_per_cell;
  };
  /// false when the segment misses the grid (then no walk).
  bool walk_start(const Vec3& a, const Vec3& b, float s_max, WalkStart& w) const noexcept;
  /// One segment's answer of first_crossings_along (triangle kNoTriangle: no crossing).
  struct Crossing {
    bool front = false;
    float s = 0.f;
    std::uint32_t triangle = kNoTriangle;
  };
  /// first_crossing_along(a[i], b[i], 1, ...) of `count` segments, the same answers bit for
  /// bit, several walks in flight at a time (surface_cells_batch.cpp): each walk prefetches
  /// the clearance, cell, list and records its next step reads and yields to the others
  /// while they load, so a batch larger than the caches waits for memory once per step of
  /// many walks instead of once per step of each.
  void first_crossings_along(const Vec3* a, const Vec3* b, std::size_t count, Crossing* out) const noexcept;
  /// Whether walks side by side pay: the surface, its normal map and its cells exceed a fifth
  /// of the last-level cache (sysconf; 32 MB when it does not say), which a shared machine's
  /// neighbours also fill. Measured on a 2-core VM with 32 MB (docs/speed.md): 3-4% slower
  /// at 5.0 MB (armadillo 52K), even at 7.2 MB (bunny), 12% quicker at 8.2 MB (832K: 3.1 MB
  /// of it the normal map), 20% at 20 MB (the chess piece), 1.2-1.5x at 13M (38 MB).
  bool walks_side_by_side() const noexcept;
  const SurfaceTriangles& surface() const { return *surface_; }
  /// The sub-cells of the crowded cells.
  const SurfaceSubcells& subcells() const { return subcells_; }
  /// Where surface cell `index`'s triangles can be within it: between two parallel planes,
  /// n . p in [lo, hi] (n unit: the mean of their normals; lo, hi: their vertices' extent
  /// along n cut to the cell's, with a margin). A segment whose part in the cell stays on one
  /// side crosses none of them there, so the walks skip the cell's tests: a triangle crossed
  /// elsewhere is listed (and tested) in the cell holding that crossing. A cell whose
  /// normals cancel (two sheets facing away) has an unbounded slab: never skipped.
  struct Slab {
    float n[3];
    float lo, hi;
  };
  /// Whether the part s in [s_a, s_b] of segment o + s d may meet surface cell `index`'s
  /// triangles (its slab); true for an index out of range.
  bool slab_may_cross(std::uint32_t index, const float o[3], const float d[3], float s_a, float s_b) const noexcept {
    if (index >= slabs_.size()) return true;
    const Slab& c = slabs_[index];
    const float no = c.n[0] * o[0] + c.n[1] * o[1] + c.n[2] * o[2];
    const float nd = c.n[0] * d[0] + c.n[1] * d[1] + c.n[2] * d[2];
    const float da = no + s_a * nd, db = no + s_b * nd;
    return !(std::max(da, db) < c.lo || std::min(da, db) > c.hi);
  }
  /// Bytes in memory.
  std::size_t bytes() const {
    return masks_.size() * 8 + base_.size() * 4 + offsets_.size() * 4 + slots_.size() * 4 + states_.size() +
           clear_.size() + slabs_.size() * sizeof(Slab) + subcells_.bytes();
  }

private:
  Vec3 origin_{Vec3::Zero()};
  float cell_ = 0.f, inv_cell_ = 0.f;
  std::array<int, 3> dims_{{0, 0, 0}};
  int bricks_x_ = 0, bricks_y_ = 0, bricks_z_ = 0;
  std::vector<std::uint64_t> masks_;   // per 4 x 4 x 4 brick: its surface cells (bit z y x)
  std::vector<std::uint32_t> base_;    // per brick: the index of its first surface cell
  std::vector<std::uint32_t> offsets_, slots_;
  std::vector<std::uint8_t> states_;
  std::vector<std::uint8_t> clear_;    // per cell (brick order, as masks_): chessboard clearance
  SurfaceSubcells subcells_;           // the crowded cells' sub-cells
  std::vector<Slab> slabs_;            // per surface cell: where its triangles are (slab_may_cross)
  std::shared_ptr<const SurfaceTriangles> surface_;
};

/// Builds the grid of a scene whose box b was baked from `box_triangles[b]` (ids into
/// `mesh`; an empty list stands for all triangles). Throws hb::InvalidInput (no triangles,
/// out-of-range ids, options out of range); returns an empty grid when the scene needs more
/// than kMaxLists distinct box lists (the scene then queries every box it meets).
/// `scene`, when given, is an EmbreeScene of all of `mesh` the regions without surface are
/// classified with (a bake has one: at 13M triangles its build took most of the grid's time);
/// without it the grid builds its own.
SceneGrid build_scene_grid(const TriangleMesh& mesh, const std::vector<std::vector<std::uint32_t>>& box_triangles,
                           const SceneGridOptions& options = {}, const EmbreeScene* scene = nullptr);

inline bool SceneGrid::clip(const Vec3& a, const Vec3& d, float& s0, float& s1) const noexcept {
  for (int k = 0; k < 3; ++k) {
    const float lo = origin_[k], hi = origin_[k] + cell_ * float(dims_[k]);
    if (std::fabs(d[k]) < 1e-30f) {
      if (!(a[k] >= lo && a[k] <= hi)) return false;
      continue;
    }
    float u = (lo - a[k]) / d[k], v = (hi - a[k]) / d[k];
    if (u > v) std::swap(u, v);
    s0 = std::max(s0, u);
    s1 = std::min(s1, v);
  }
  return s0 <= s1;
}

inline void SceneGrid::dda_start(const Vec3& a, const Vec3& d, float s, int i[3], int step[3], float next[3],
                                 float delta[3]) const noexcept {
  const Vec3 p = a + s * d;
  for (int k = 0; k < 3; ++k) {
    const float f = (p[k] - origin_[k]) * inv_cell_;
    i[k] = std::min(std::max(int(std::floor(f)), 0), dims_[k] - 1);
    if (d[k] > 1e-30f) {
      step[k] = 1;
      next[k] = (origin_[k] + cell_ * float(i[k] + 1) - a[k]) / d[k];
      delta[k] = cell_ / d[k];
    } else if (d[k] < -1e-30f) {
      step[k] = -1;
      next[k] = (origin_[k] + cell_ * float(i[k]) - a[k]) / d[k];
      delta[k] = -cell_ / d[k];
    } else {
      step[k] = 0;
      next[k] = 2.f;  // never
      delta[k] = 0.f;
    }
  }
}

template <class Visit>
void SceneGrid::walk(const Vec3& a, const Vec3& b, Visit&& visit) const noexcept {
  if (codes_.empty()) return;
  const Vec3 d = b - a;
  float s0 = 0.f, s1 = 1.f;
  if (!clip(a, d, s0, s1)) return;
  int i[3], step[3];
  float next[3], delta[3];
  dda_start(a, d, s0, i, step, next, delta);
  float s = s0;
  const int limit = dims_[0] + dims_[1] + dims_[2];
  for (int it = 0; it < limit; ++it) {
    if (!visit(std::uint16_t(cells_[cell_index(i[0], i[1], i[2])]), s)) return;
    const int k = next[0] < next[1] ? (next[0] < next[2] ? 0 : 2) : (next[1] < next[2] ? 1 : 2);
    s = next[k];
    if (s > s1) return;
    i[k] += step[k];
    if (i[k] < 0 || i[k] >= dims_[k]) return;
    next[k] += delta[k];
  }
}

template <class OnCell>
void SceneGrid::walk_bricks(const Vec3& a, const Vec3& b, OnCell&& on_cell) const noexcept {
  if (codes_.empty()) return;
  const Vec3 d = b - a;
  float s0 = 0.f, s1 = 1.f;
  if (!clip(a, d, s0, s1)) return;
  // A jump of `cells` cells (in every axis at most) along the segment, in parameter s.
  const float max_d = std::max({std::fabs(d.x()), std::fabs(d.y()), std::fabs(d.z())});
  const float s_per_cell = max_d > 0.f ? cell_ / max_d : 2.f;
  int i[3], step[3];
  float next[3], delta[3];
  // The DDA state at parameter s: the cell holding a + s d and the next boundaries; the same
  // formulas as walk() (whose start this is for s = s0).
  const auto start_at = [&](float s) { dda_start(a, d, s, i, step, next, delta); };
  start_at(s0);
  float s = s0;
  const int limit = dims_[0] + dims_[1] + dims_[2];
  for (int it = 0; it < limit; ++it) {
    const std::uint8_t brick = bricks_[brick_index(i[0], i[1], i[2])];
    int jump_cells = 0;
    if ((brick & kBrickSurface) != kBrickSurface && (brick >> 2) >= 3) {
      // Every brick within (brick >> 2) - 1 of this one has no surface. The point lies in
      // this brick's closure widened by one cell (as below), so moving it at most
      // 4 * ((brick >> 2) - 1) - 2 cells in every axis keeps it inside those bricks: no
      // surface cell is skipped, and the landing cell has none either. No cell is read.
      jump_cells = 4 * (brick >> 2) - 6;
    } else {
      jump_cells = on_cell(static_cast<const int*>(i), s);
      if (jump_cells < 0) return;
    }
    if (jump_cells > 0) {
      const float jump = s + float(jump_cells) * s_per_cell;
      if (jump > s1) return;
      start_at(jump);
      // The landing cell is beyond the boundaries already crossed: keep s monotone.
      s = jump;
      continue;
    }
    const int k = next[0] < next[1] ? (next[0] < next[2] ? 0 : 2) : (next[1] < next[2] ? 1 : 2);
    s = next[k];
    if (s > s1) return;
    i[k] += step[k];
    if (i[k] < 0 || i[k] >= dims_[k]) return;
    next[k] += delta[k];
  }
}

template <class Visit>
void SceneGrid::walk_surface(const Vec3& a, const Vec3& b, Visit&& visit) const noexcept {
  walk_bricks(a, b, [&](const int* i, float s) {
    const std::uint32_t word = cells_[cell_index(i[0], i[1], i[2])];
    const std::uint16_t code = std::uint16_t(word);
    const int clearance = int(word >> 16);
    if (code >= kFirstSurface) {
      bool go_on = true;
      if constexpr (std::is_invocable_v<Visit&, std::uint16_t, float, const int*>) {
        go_on = visit(code, s, i);
      } else {
        go_on = visit(code, s);
      }
      return go_on ? 0 : -1;
    }
    // Every cell within clearance - 1 of this one has no surface. The point lies in this
    // cell's closure (at most one cell past its low corner in each axis), so moving it at
    // most clearance - 2 cells in every axis keeps it strictly within clearance - 1 cells:
    // no surface cell is skipped. The landing cell has no surface either, so its inexact
    // entry parameter is never reported.
    return clearance >= 4 ? clearance - 2 : 0;
  });
}

} // namespace hb
