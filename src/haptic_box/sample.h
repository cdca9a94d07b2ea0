#pragma once
// The uncompressed sample record and the sampling densities of a haptic box, shared by the
// box, the bake and the codecs.
#include <cmath>
#include <cstddef>
#include <cstdint>

namespace hb {

/// Sampling densities (paper Figure 9: "m n").
struct BoxParams {
  int m = 32;  ///< position points per PBB face edge (m x m per face, edges included), >= 2.
  int n = 16;  ///< directional points per sub-block face edge (n x n, edges included), >= 2.
  std::size_t samples_per_position() const { return 12u * std::size_t(n) * std::size_t(n); }
  std::size_t position_count() const { return 6u * std::size_t(m) * std::size_t(m); }
  std::size_t sample_count() const { return position_count() * samples_per_position(); }
  /// Tiles: one n x n sub-block face at one position point (the unit the codecs work on).
  std::size_t tile_count() const { return position_count() * 12u; }
};

/// How a bake picks each box's position density m (per-piece densities, issue 4). A box's
/// accuracy is set by its cell size (largest PBB edge / (m - 1)): one m for all pieces gives a
/// large piece coarse cells and a small one needlessly fine cells. With `cell` > 0, every box
/// gets about the same cell size instead. Measured on the armadillo (6 automatic pieces, n=16,
/// 20K probes): one m=32 for all, 906 MB raw: median force error 12.7%, p95 72%, 96.4%
/// agreement; cell = 0.0125 (m from 12 to 64), 1155 MB raw: 9.6%, 53%, 97.1%; m=64 for all,
/// 3624 MB raw: 7.4%, 46%, 97.3%.
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

/// One directional sample: distance `t` from the position point to the first hit of the
/// piece along the sample's direction, and the shaded normal there in 32-bit octahedral
/// encoding. A ray that misses the piece stores `t = kMissT` (negative) and no normal;
/// see HapticBox::query for why interpolation behaves well next to misses.
struct Sample {
  float t;
  std::uint32_t normal;
};
static_assert(sizeof(Sample) == 8, "Sample is an 8-byte record");
constexpr float kMissT = -1.f;

} // namespace hb
