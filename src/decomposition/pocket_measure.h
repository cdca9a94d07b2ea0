#pragma once
// Quasi-convexity of a piece as the haptic box sees it: how often, and how deeply, the box's
// stored first hit hides a contact (paper section 4.1; the "pocket" measure).
#include "exact/embree_scene.h"
#include "geometry/obb.h"
#include <algorithm>
#include <cstdint>
#include <vector>

namespace hb {

/// Options of measure_pockets.
struct PocketOptions {
  int lines = 8192;          ///< random lines through the piece's PBB, >= 1. Cost ~ lines x hits.
  std::uint64_t seed = 1;    ///< same seed, same piece: same score.
  ObbOptions obb;            ///< how the PBB is fitted (as the bake does).
};

/// The pocket score of a piece.
///
/// A haptic box stores, for every line through its PBB, the first surface of its piece met
/// from where the line enters the box. A probe whose handle S lies outside the piece but
/// behind that first surface (in a pocket of its own line: piece behind S and ahead of S)
/// loses the contact ahead of it. `probability` is the chance of exactly that event for a
/// point uniform in the PBB and a direction uniform on the sphere: the stored first hit is
/// behind the point and the first surface ahead of the point is an outside (front) face.
/// It is computed exactly along each sampled line (the pocket gaps between consecutive hits,
/// over the chord in the box, both orientations), so it has little variance.
///
/// Why not generic convex-decomposition concavity (volume or Hausdorff distance to the
/// hull): those measure how far the surface is from its hull, which is large for harmless
/// shapes (a shallow wide dent seen from any line crosses the surface once) and small for
/// harmful ones (a thin torus has a tiny hull gap but every line through its hole loses
/// contacts). The haptic box fails exactly on lines that cross the piece's surface more
/// than twice with a gap between, which is what this counts.
///
/// Units: probability in [0, 1]; depths are pocket gap lengths along the line (from the
/// surface behind the point to the hidden surface ahead) divided by the PBB diagonal.
struct PocketScore {
  double probability = 0.0;  ///< P(contact hidden) for a uniform point and direction in the PBB.
  double mean_depth = 0.0;   ///< mean gap around a hidden point (length-weighted), / diagonal.
  double max_depth = 0.0;    ///< largest gap met, / diagonal.
  std::size_t lines = 0;     ///< lines that met the PBB.
};

/// Measures the pocket score of the given triangles of `mesh` (all when empty) with Embree.
/// Deterministic for a given seed (parallel over lines, summed in order).
/// Throws hb::InvalidInput on an empty selection or options.lines < 1.
PocketScore measure_pockets(const TriangleMesh& mesh, const std::vector<std::uint32_t>& triangles = {},
                            const PocketOptions& options = {});

/// One surface crossing along a line: parameter, triangle id, and whether the line enters
/// the outside of the surface there (front face).
struct LineHit {
  float t;
  std::uint32_t triangle;
  bool front;
};

/// All crossings of origin + t dir (unit dir) with the scene for t in [0, t_far], sorted by t;
/// crossings closer than `merge_eps` to the previous one (a ray through a shared edge) count
/// once. At most `max_hits`. Appends to `out`.
void collect_line_hits(const EmbreeScene& scene, const Vec3& origin, const Vec3& dir, float t_far,
                       float merge_eps, std::vector<LineHit>& out, int max_hits = 256);

/// Pocket gaps along one line given one piece's crossings sorted by t, averaged over both
/// orientations of the line: `length` is the total hidden length (see PocketScore),
/// `gap_weighted` the sum of gap^2 (for the length-weighted mean), `max_gap` the largest gap.
struct LinePockets {
  double length = 0.0;
  double gap_weighted = 0.0;
  double max_gap = 0.0;
};
template <typename Hit, typename Keep>
LinePockets line_pockets(const Hit* hits, std::size_t count, Keep&& keep) noexcept {
  LinePockets out;
  const Hit* prev = nullptr;
  for (std::size_t k = 0; k < count; ++k) {
    if (!keep(hits[k])) continue;
    if (prev) {
      const double gap = double(hits[k].t) - double(prev->t);
      // Forward: the gap before a front face with a crossing behind it is hidden.
      // Backward: the same for the reversed line, where back faces become front faces.
      const double w = 0.5 * ((hits[k].front ? 1.0 : 0.0) + (prev->front ? 0.0 : 1.0));
      if (w > 0.0) {
        out.length += w * gap;
        out.gap_weighted += w * gap * gap;
        out.max_gap = std::max(out.max_gap, gap);
      }
    }
    prev = &hits[k];
  }
  return out;
}

} // namespace hb
