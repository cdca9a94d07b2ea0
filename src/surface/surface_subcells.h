#pragma once
// A second level below the surface cells: a crowded surface cell (more triangles
// listed than a probe should test) is cut into side^3 sub-cells (side 4, 8 or 16, from how
// crowded the cells are), each listing the
// triangles meeting it, so a segment through it tests the triangles of the sub-cells it
// passes, not all of the cell's. The grid's cells stay what the file stores (1/128 of the
// diagonal) while the triangles grow with the model: at 832K triangles a cell lists about
// 16 times more than at 52K.
#include "surface/surface_triangles.h"
#include "math/vec3.h"
#include "prefetch.h"
#include <array>
#include <cstdint>
#include <vector>

namespace hb {

/// Sub-cell lists of the crowded cells of one grid (origin, cell edge). Built once from the
/// cells' own lists (SurfaceCells), then queried through const noexcept methods, safe from
/// many threads.
class SurfaceSubcells {
public:
  static constexpr int kMaxSide = 16;
  static constexpr std::uint32_t kNone = 0xffffffffu;
  /// A cell with more triangles listed than this is cut (the default of SurfaceCells).
  static constexpr std::uint32_t kDefaultCrowded = 24;

  SurfaceSubcells() = default;
  /// `cell_of[i]` is surface cell i's grid coordinates, its triangles (surface slots)
  /// slots[offsets[i], offsets[i + 1]). Cells listing more than `crowded` triangles get
  /// sub-cells, each listing the triangles that meet it (the same padded triangle-box test
  /// as the cells', at the sub-cell's size). The side (4, 8 or 16 sub-cells an edge) is the
  /// smallest that brings the crowded cells' mean list to at most `crowded` a sub-cell (a
  /// surface's listings fall about with the square of the side; measured at 832K: side 8
  /// was slower than 4, its sub-cell steps cost more than the triangles it spares).
  SurfaceSubcells(const Vec3& origin, float cell, const std::vector<std::array<int, 3>>& cell_of,
                  const std::vector<std::uint32_t>& offsets, const std::vector<std::uint32_t>& slots,
                  const SurfaceTriangles& surface, std::uint32_t crowded = kDefaultCrowded);

  /// The crowded index of surface cell `cell` (kNone: not cut).
  std::uint32_t crowded(std::uint32_t cell) const noexcept { return cell < entry_.size() ? entry_[cell] : kNone; }
  /// Whether a cell listing `count` triangles may be cut (only then is crowded() asked: a
  /// walk's cells mostly list fewer, and skip that load).
  bool may_be_crowded(std::uint32_t count) const noexcept { return count > threshold_; }
  std::size_t crowded_count() const { return words_ > 0 ? mask_.size() / std::size_t(words_) : 0; }
  int side() const { return side_; }

  /// Within crowded cell `crowded` at grid coordinates `cell`: the crossing nearest the
  /// handle of segment o + s d, s in [0, min(best, s_cap)], among the triangles of the
  /// sub-cells the segment passes between s_enter and s_exit, visited in order (a sub-cell
  /// entered beyond the nearest crossing so far is not tested). `fa`, `fd` are the segment
  /// in cell units from the grid's origin, `inv` 1 / fd per axis (0 where fd is 0).
  /// Improves best / front / id when it finds a nearer crossing (and returns true then).
  bool first_crossing(std::uint32_t crowded, const int cell[3], const Vec3& fa, const Vec3& fd, const float inv[3],
                      float s_enter, float s_exit, float s_cap, const float o[3], const float d[3],
                      const SurfaceTriangles& surface, float& best, bool& front, std::uint32_t& id) const noexcept;

  /// For walks that prefetch ahead (SurfaceCells::first_crossings_along): starts loading
  /// what first_crossing() reads of crowded cell `crowded`, one stage a call, the second
  /// reading only what the first prefetched: 0 the cell's mask and rank words, 1 its lists'
  /// bounds (then lists_along names the lists the segment passes). No effect for an index
  /// out of range.
  void prefetch(std::uint32_t crowded, int stage) const noexcept;
  /// The lists of the sub-cells of crowded cell `crowded` (at grid coordinates `cell`) that
  /// segment fa + s fd (cell units, `inv` as first_crossing's) passes between s_enter and
  /// s_exit, in order, as slot ranges: list_slots()[first[k], first[k] + count[k]) for k < the
  /// number returned (at most `max`). What first_crossing() would test there, for a walk
  /// that prefetches them first; reads what prefetch() stages 0 and 1 load.
  int lists_along(std::uint32_t crowded, const int cell[3], const Vec3& fa, const Vec3& fd, const float inv[3],
                  float s_enter, float s_exit, std::uint32_t* first, std::uint32_t* count, int max) const noexcept;
  const std::uint32_t* list_slots() const noexcept { return slots_.data(); }
  /// Starts loading crowded(cell)'s entry.
  void prefetch_entry(std::uint32_t cell) const noexcept {
    if (cell < entry_.size()) hb::prefetch(entry_.data() + cell);
  }

  /// Bytes in memory.
  std::size_t bytes() const {
    return entry_.size() * 4 + mask_.size() * 8 + rank_.size() * 4 + offsets_.size() * 4 + slots_.size() * 4;
  }

private:
  std::vector<std::uint32_t> entry_;    // per surface cell: its crowded index, or kNone
  std::uint32_t threshold_ = 0xffffffffu;  // the cells listing more are cut (none: the largest)
  int side_ = 4, words_ = 1;            // sub-cells an edge; 64-bit mask words a crowded cell
  std::vector<std::uint64_t> mask_;     // per crowded cell, words_ words: its sub-cells with triangles (bit (z s + y) s + x)
  std::vector<std::uint32_t> rank_;     // per mask word: the list index of its first sub-cell
  std::vector<std::uint32_t> offsets_;  // per sub-cell list: where its slots begin (one past: the next)
  std::vector<std::uint32_t> slots_;
};

} // namespace hb
