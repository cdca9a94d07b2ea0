#pragma once
// The scene grid: a uniform grid baked with a scene of several boxes, which routes a probe to
// the boxes whose pieces it can meet and answers "is the handle inside the object" in O(1).
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
    // Compared as floats first: a point 1e30 away is no int.
    if (!(f.x() < float(dims_[0]) && f.y() < float(dims_[1]) && f.z() < float(dims_[2]))) return kOutside;
    const int x = int(f.x()), y = int(f.y()), z = int(f.z());
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

  /// A lower bound of the distance from p to the surface (model units): 0 in or next to a
  /// surface cell, otherwise what the clearance of p's cell (or brick) guarantees; beyond the
  /// grid, which covers the mesh, at least the distance to the grid. A tool's broad phase.
  float surface_distance_bound(const Vec3& p) const noexcept;

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
