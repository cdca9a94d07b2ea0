#pragma once
// The surface cells: per surface cell of a scene grid, the triangles of the scene's shared
// surface meeting it and the inside/outside state of its centre; the exact first crossing of
// a segment through them (surface_cells.cpp, and many segments at a time in
// surface_cells_batch.cpp). What answers a default scene's queries (SceneRoute::cells).
#include "surface/scene_grid.h"
#include "surface/surface_subcells.h"
#include "surface/surface_triangles.h"
#include <algorithm>
#include <array>
#include <cstdint>
#include <memory>
#include <vector>

namespace hb {

/// Below the grid's surface cells: per surface cell, the surface slots of
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
    if (!(f.x() < float(dims_[0]) && f.y() < float(dims_[1]) && f.z() < float(dims_[2]))) return kNone;  // no int overflow
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
  // The constructor's steps (surface_cells.cpp), in order; each returns or fills what the
  // next needs.
  std::uint32_t rank_cells(const SceneGrid& grid);
  void list_triangles(std::uint32_t total);
  std::vector<std::array<int, 3>> cell_coordinates(std::uint32_t total) const;
  void fit_slabs(const std::vector<std::array<int, 3>>& cell_of);
  void decide_centre_states(const std::vector<std::uint16_t>& codes, const std::vector<std::array<int, 3>>& cell_of);
  // first_crossings_along's walks, a method a phase (surface_cells_batch.cpp).
  struct Walker;

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

} // namespace hb
