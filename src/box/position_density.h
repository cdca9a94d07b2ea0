#pragma once
// How a bake picks each box's position density m (one density per piece).
#include <cmath>

namespace hb {

/// A box's accuracy is set by its cell size (largest PBB edge / (m - 1)): one m for all pieces
/// gives a large piece coarse cells and a small one needlessly fine cells. With `cell` > 0,
/// every box gets about the same cell size instead. Measured on the armadillo (6 automatic
/// pieces, n=16, 20K probes): one m=32 for all, 906 MB raw: median force error 12.7%, p95 72%,
/// 96.4% agreement; cell = 0.0125 (m from 12 to 64), 1155 MB raw: 9.6%, 53%, 97.1%; m=64 for
/// all, 3624 MB raw: 7.4%, 46%, 97.3%.
struct PositionDensity {
  /// Target position-cell size as a fraction of the whole mesh's bounding-box diagonal, >= 0;
  /// 0: every box uses the fixed m (BoxParams::m).
  float cell = 0.f;
  int min_m = 8;   ///< smallest m a box gets with `cell` > 0, >= 2.
  int max_m = 64;  ///< largest m a box gets with `cell` > 0 (bounds a box's memory), >= min_m.
  /// The m of a box whose PBB's largest edge is `largest_edge`, on a mesh of bounding-box
  /// diagonal `mesh_diagonal`: `fixed_m` when cell is 0, else the least m with
  /// largest_edge / (m - 1) <= cell * mesh_diagonal, clamped to [min_m, max_m].
  int m_for(int fixed_m, float largest_edge, float mesh_diagonal) const noexcept {
    if (!(cell > 0.f) || !(mesh_diagonal > 0.f)) return fixed_m;
    const float cells = largest_edge / (cell * mesh_diagonal);
    const int m = cells < float(max_m) ? int(std::ceil(cells - 1e-4f)) + 1 : max_m;  // (rounding slack)
    return m < min_m ? min_m : (m > max_m ? max_m : m);
  }
};

} // namespace hb
