#pragma once
// The cell-by-cell walk (3D DDA, Amanatides and Woo 1987) of a segment through unit cells,
// shared by the surface cells' walk and their sub-cells' walk (SurfaceCells::
// first_crossing_along, SurfaceSubcells::first_crossing). Coordinates are in cell units.
// The state is named per axis (x, y, z), not arrays indexed by a run-time axis, so that the
// compiler keeps it in registers through a walk's loop instead of on the stack.
#include <algorithm>
#include <limits>

namespace hb {

/// The DDA state of segment a + s d (cell units) in a block of n[0] x n[1] x n[2] unit cells:
/// the cell, the step per axis, the s of the next boundary per axis and the s per cell.
/// `inv` is 1 / d per axis (0 where the segment does not move along it); the caller computes
/// it once, so starting again after a jump costs no division.
struct CellDda {
  int x = 0, y = 0, z = 0;
  int sx, sy, sz;
  float nx = 0.f, ny = 0.f, nz = 0.f;
  float dx, dy, dz;

  CellDda(const float inv[3]) noexcept
      : sx(inv[0] > 0.f ? 1 : inv[0] < 0.f ? -1 : 0), sy(inv[1] > 0.f ? 1 : inv[1] < 0.f ? -1 : 0),
        sz(inv[2] > 0.f ? 1 : inv[2] < 0.f ? -1 : 0), dx(inv[0] > 0.f ? inv[0] : -inv[0]),
        dy(inv[1] > 0.f ? inv[1] : -inv[1]), dz(inv[2] > 0.f ? inv[2] : -inv[2]) {}

  /// Starts at parameter s: the cell holding a + s d (clamped to the block: the point is in
  /// it up to rounding, so truncation is floor there) and its next boundaries.
  void start(const float a[3], const float d[3], const float inv[3], float s, const int n[3]) noexcept {
    x = std::min(std::max(int(a[0] + s * d[0]), 0), n[0] - 1);
    y = std::min(std::max(int(a[1] + s * d[1]), 0), n[1] - 1);
    z = std::min(std::max(int(a[2] + s * d[2]), 0), n[2] - 1);
    nx = boundary(x, sx, a[0], inv[0]);
    ny = boundary(y, sy, a[1], inv[1]);
    nz = boundary(z, sz, a[2], inv[2]);
  }
  /// The s where the segment leaves the current cell (its next boundary).
  float exit() const noexcept { return std::min(nx, std::min(ny, nz)); }
  /// Crosses that boundary (on a tie: x only when strictly first, else y when strictly before
  /// z, else z): returns the s where the segment enters the next cell, and `inside` false
  /// when that cell is beyond the block.
  float step(const int n[3], bool& inside) noexcept {
    float s;
    if (nx < ny ? nx < nz : false) {
      s = nx;
      x += sx;
      nx += dx;
      inside = x >= 0 && x < n[0];
    } else if (ny < nz) {
      s = ny;
      y += sy;
      ny += dy;
      inside = y >= 0 && y < n[1];
    } else {
      s = nz;
      z += sz;
      nz += dz;
      inside = z >= 0 && z < n[2];
    }
    return s;
  }

private:
  static float boundary(int i, int step, float a, float inv) noexcept {
    return step > 0   ? (float(i + 1) - a) * inv
           : step < 0 ? (float(i) - a) * inv
                      : std::numeric_limits<float>::infinity();
  }
};

} // namespace hb
