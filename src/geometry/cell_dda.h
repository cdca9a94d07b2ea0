#pragma once
// The cell-by-cell walk (3D DDA, Amanatides and Woo 1987) of a segment through unit cells,
// shared by the surface cells' walk and their sub-cells' walk (SurfaceCells::
// first_crossing_along, SurfaceSubcells::first_crossing). Coordinates are in cell units.
#include <algorithm>
#include <limits>

namespace hb {

/// The DDA state of segment a + s d (cell units) in a block of n[0] x n[1] x n[2] unit cells:
/// the cell, the step per axis, the s of the next boundary per axis and the s per cell.
/// `inv` is 1 / d per axis (0 where the segment does not move along it); the caller computes
/// it once, so starting again after a jump costs no division.
struct CellDda {
  int i[3], step[3];
  float next[3], delta[3];

  CellDda(const float inv[3]) noexcept {
    for (int k = 0; k < 3; ++k) {
      step[k] = inv[k] > 0.f ? 1 : inv[k] < 0.f ? -1 : 0;
      delta[k] = inv[k] > 0.f ? inv[k] : -inv[k];
    }
  }
  /// Starts at parameter s: the cell holding a + s d (clamped to the block: the point is in
  /// it up to rounding, so truncation is floor there) and its next boundaries.
  void start(const float a[3], const float d[3], const float inv[3], float s, const int n[3]) noexcept {
    for (int k = 0; k < 3; ++k) {
      i[k] = std::min(std::max(int(a[k] + s * d[k]), 0), n[k] - 1);
      next[k] = step[k] > 0   ? (float(i[k] + 1) - a[k]) * inv[k]
                : step[k] < 0 ? (float(i[k]) - a[k]) * inv[k]
                              : std::numeric_limits<float>::infinity();
    }
  }
  /// The axis whose boundary comes next.
  int axis() const noexcept {
    return next[0] < next[1] ? (next[0] < next[2] ? 0 : 2) : (next[1] < next[2] ? 1 : 2);
  }
  /// Crosses that boundary along axis k: false when it leaves the block.
  bool advance(int k, const int n[3]) noexcept {
    i[k] += step[k];
    if (i[k] < 0 || i[k] >= n[k]) return false;
    next[k] += delta[k];
    return true;
  }
};

} // namespace hb
