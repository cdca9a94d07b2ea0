#pragma once
// The layout of a haptic box (paper sections 3-4): where its position points and directional
// samples are in space, and where each sample is in the table. One definition for the bake
// (a ray per sample), the query (the four corners' quads, haptic_box.cpp) and the batched
// kernel (query_lanes_kernel.inc):
//  - PBB face f (0..5) is normal to local axis a = f / 2, at -half[a] (even f) or +half[a]
//    (odd f); its in-face axes are u = (a + 1) % 3 and v = (a + 2) % 3 (face_axes()).
//  - Position point (i, j) of face f (m x m per face, edges included) lies at the face corner
//    (-half[u], -half[v]) plus i and j steps of 2 half / (m - 1) along u and v; its index is
//    p = (f m + i) m + j (position_index()).
//  - Each position point carries a directional hemi-cube (DHC) of 12 tiles: sub-block sub
//    (0..3: bit 0 the sign of the u component, bit 1 of v) x sub-block face sface (0..2: the
//    cube-map major axis, 0 into the box, 1 along u, 2 along v); tile = 12 p + 3 sub + sface
//    (tile_index()).
//  - A tile holds n x n directional samples (edges included), sample (a, b) at
//    tile n^2 + a n + b (first_sample(), sample_index()); a tile is the unit the codecs work on.
#include "geometry/obb.h"
#include "codec/sample.h"
#include "math/vec3.h"
#include <cstddef>

namespace hb {

/// Local axes of PBB face `face`: the axis it is normal to, its two in-face axes, its side.
struct FaceAxes {
  int a, u, v;
  float sign;  ///< -1: face at -half[a], +1: at +half[a].
};
inline FaceAxes face_axes(int face) noexcept {
  const int a = face / 2;
  return {a, (a + 1) % 3, (a + 2) % 3, (face & 1) ? 1.f : -1.f};
}

/// The layout of one box (its PBB and densities): sample indices, position points, sample
/// directions and the box-local constants the query runs on.
class BoxLayout {
public:
  /// Per face: world position of position point (0, 0) and the steps to (1, 0) and (0, 1).
  struct FaceFrame {
    Vec3 origin, step_i, step_j;
  };
  /// Query constants in box-local coordinates: rows of axes^T (local = rt (p - centre)),
  /// centre, half extents, and grid scales 0.5 (m - 1) / half per axis.
  struct Local {
    float rt[3][3];
    float center[3], half[3], grid_scale[3];
  };

  BoxLayout() = default;
  /// The layout of a box with this PBB and densities (m, n >= 2; the PBB valid, obb_problem).
  BoxLayout(const Obb& obb, const BoxParams& params) noexcept;

  const BoxParams& params() const noexcept { return params_; }
  const Obb& obb() const noexcept { return obb_; }
  const FaceFrame& frame(int face) const noexcept { return faces_[face]; }
  const Local& local() const noexcept { return local_; }

  /// Index of position point (i, j) of face `face`.
  std::size_t position_index(int face, int i, int j) const noexcept {
    const std::size_t m = std::size_t(params_.m);
    return (std::size_t(face) * m + std::size_t(i)) * m + std::size_t(j);
  }
  /// Position step from a cell's first corner (i0, j0) to its corner c, in the order the query
  /// blends them: (i0, j0), (i0 + 1, j0), (i0 + 1, j0 + 1), (i0, j0 + 1).
  std::size_t corner_step(int c) const noexcept {
    const std::size_t m = std::size_t(params_.m);
    return c == 0 ? 0u : c == 1 ? m : c == 2 ? m + 1u : 1u;
  }
  /// Tile of sub-block face `sface` of sub-block `sub` within a hemi-cube (0..11).
  static std::size_t sub_face(int sub, int sface) noexcept { return std::size_t(sub) * 3u + std::size_t(sface); }
  /// Index of tile `sf` (sub_face()) of position point `position`.
  static std::size_t tile_index(std::size_t position, std::size_t sf) noexcept { return position * 12u + sf; }
  /// Index of directional sample (a, b) of tile `sf` of position point `position`.
  std::size_t first_sample(std::size_t position, std::size_t sf, int a, int b) const noexcept {
    const std::size_t n = std::size_t(params_.n);
    return tile_index(position, sf) * n * n + std::size_t(a) * n + std::size_t(b);
  }
  /// Index of sample (a, b) of sub-block face `sface` of sub-block `sub` (0..3) at position
  /// point (i, j) of PBB face `face` (0..5).
  std::size_t sample_index(int face, int i, int j, int sub, int sface, int a, int b) const noexcept {
    return first_sample(position_index(face, i, j), sub_face(sub, sface), a, b);
  }

  /// World position of position point (i, j) of face `face`.
  Vec3 position_point(int face, int i, int j) const noexcept {
    const FaceFrame& f = faces_[face];
    return f.origin + float(i) * f.step_i + float(j) * f.step_j;
  }
  /// World unit direction of directional sample (sub, sface, a, b) at any point of `face`.
  Vec3 sample_direction(int face, int sub, int sface, int a, int b) const noexcept;

private:
  Obb obb_;
  BoxParams params_;
  FaceFrame faces_[6];
  Local local_;
};

} // namespace hb
