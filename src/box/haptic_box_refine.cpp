// Haptic box query, step 7: exact refinement (see the overview in haptic_box.cpp). The
// triangles hit by the 16 samples of the located cell are candidates; the line is intersected
// with each exactly, and when it crosses none a bounded walk over the surface's edges follows.
#include "box/haptic_box.h"
#include <algorithm>
#include <cmath>
#include <limits>

namespace hb {

// Most edges a refinement walk crosses. Measured (eval and bench, 20,000 probes): on the
// 31-box armadillo (52K triangles, cells 1.6% of the diagonal) 3 steps give p95 13.8%, 6 give
// 0.0033%, 12 give 0.0032%; on one m=32 box of armadillo subdivided twice (832K triangles,
// far smaller than a cell) 3 / 6 / 12 steps give median error 18.7% / 0.0044% / 0.0019% at
// 1.26 / 1.52 / 1.98 us a query. A walk is bounded, so the query cost stays bounded.
constexpr int kWalkSteps = 8;


// A refinement's best crossing so far (s: along l from P1).
struct HapticBox::RefineHit {
  float s = std::numeric_limits<float>::infinity();
  Vec3 normal = Vec3::Zero();
  bool front = false;
  std::uint32_t id = kNoTriangle;
};

// A crossing refine() takes: a front face within the tolerance of the blend (any, when the
// blend missed: t_blend < 0).
bool HapticBox::refine_accepts(float s, bool front, float t_blend) const noexcept {
  return s < std::numeric_limits<float>::infinity() && front &&
         (t_blend < 0.f || std::fabs(s - t_blend) <= refine_tolerance_);
}

// The 16 samples' ids (4 corners x the 2 x 2 quad), then the distinct ones in the order
// first seen (misses dropped), without a branch a sample: id k is kept when no id before it
// is equal (one 16-lane equality mask per id) and it is not a miss. Returns their count.
int HapticBox::refine_candidates(std::size_t p00, int a0, int b0, std::size_t sf,
                                 std::uint32_t candidates[16]) const noexcept {
  const std::size_t n = std::size_t(params_.n);
  alignas(16) std::uint32_t ids[16];
  for (int c = 0; c < 4; ++c) {
    const std::size_t first = layout_.first_sample(p00 + layout_.corner_step(c), sf, a0, b0);
    ids[4 * c] = triangle_ids_.at(first);
    ids[4 * c + 1] = triangle_ids_.at(first + 1);
    ids[4 * c + 2] = triangle_ids_.at(first + n);
    ids[4 * c + 3] = triangle_ids_.at(first + n + 1);
  }
  int count = 0;
  const __m128i i0 = _mm_load_si128(reinterpret_cast<const __m128i*>(ids));
  const __m128i i1 = _mm_load_si128(reinterpret_cast<const __m128i*>(ids + 4));
  const __m128i i2 = _mm_load_si128(reinterpret_cast<const __m128i*>(ids + 8));
  const __m128i i3 = _mm_load_si128(reinterpret_cast<const __m128i*>(ids + 12));
  for (int k = 0; k < 16; ++k) {
    const __m128i v = _mm_set1_epi32(int(ids[k]));
    const __m128i lo = _mm_packs_epi32(_mm_cmpeq_epi32(v, i0), _mm_cmpeq_epi32(v, i1));
    const __m128i hi = _mm_packs_epi32(_mm_cmpeq_epi32(v, i2), _mm_cmpeq_epi32(v, i3));
    const unsigned equal = unsigned(_mm_movemask_epi8(_mm_packs_epi16(lo, hi)));
    const bool keep = (equal & ((1u << k) - 1u)) == 0u && ids[k] != kNoTriangle;
    candidates[count] = ids[k];
    count += keep ? 1 : 0;
  }
  return count;
}

// No candidate crossed and accepted: the line passes between them. Walk from the candidate
// it passes nearest (`start`), across the edges it passes, to the triangle it crosses; when
// that walk ends at a crease, a border or a fold (it turned back), or crosses a surface the
// blend does not see, walk from every other candidate (at most 15 bounded walks, only here)
// and keep the nearest accepted crossing: at creases and grazing strokes the nearest
// candidate is often on the other face (walking from it alone, `reject` loses contacts on
// slides: on the fandisk 8.3% of the ticks instead of 3.5%). None accepted: the walk from the nearest
// candidate goes on (a surface far from the box face, where the samples' hits lie many
// triangles from the crossing: a handle deep in the PBB, a thin rim between samples). Rare
// (31-445 of 20,000 random probes on the default bakes); it cuts the slides' lost contacts
// 10-20x (docs/stability.md).
bool HapticBox::refine_walks(std::uint32_t start, const std::uint32_t* candidates, int count, const float p1[3],
                             const float l[3], float t_blend, RefineHit& best) const noexcept {
  if (start == kNoTriangle) return false;
  if (surface_->walk(start, p1, l, 0.f, kWalkSteps, best.s, best.normal, best.front, &best.id) &&
      refine_accepts(best.s, best.front, t_blend))
    return true;
  bool found = false;
  if (walk_from_all_ && count >= 2) {
    // The walks mostly run into each other's paths: a memo of the triangles walked (the
    // first walk's path recorded again) stops a walk where an earlier one went on with at
    // least its budget, with the same answer (SurfaceTriangles::WalkMemo).
    SurfaceTriangles::WalkMemo memo;
    {
      float s = 0.f;
      Vec3 nrm;
      bool front = false;
      surface_->walk(start, p1, l, 0.f, kWalkSteps, s, nrm, front, nullptr, &memo);
    }
    float nearest = std::numeric_limits<float>::infinity();
    for (int k = 0; k < count; ++k) {
      if (candidates[k] == start) continue;
      float s = 0.f;
      Vec3 nrm;
      bool front = false;
      std::uint32_t id = kNoTriangle;
      if (surface_->walk(candidates[k], p1, l, 0.f, kWalkSteps, s, nrm, front, &id, &memo) &&
          refine_accepts(s, front, t_blend) && s < nearest) {
        nearest = s;
        best.s = s, best.normal = nrm, best.front = front, best.id = id;
        found = true;
      }
    }
  }
  if (!found && long_walk_steps_ > kWalkSteps)
    found = surface_->walk(start, p1, l, 0.f, long_walk_steps_, best.s, best.normal, best.front, &best.id) &&
            refine_accepts(best.s, best.front, t_blend);
  return found;
}

// Step 7: the triangles the 16 blended samples hit are the candidates for the true contact.
// The line from P1 along l is tested against each (distinct) one exactly; the nearest hit,
// when it is a front face and agrees with the blend within the tolerance, replaces the blend.
bool HapticBox::refine(std::size_t p00, int a0, int b0, std::size_t sf, const float p1[3], const float l[3],
                       float t_blend, float& t0, Vec3& normal, std::uint32_t& triangle) const noexcept {
  std::uint32_t candidates[16];
  const int count = refine_candidates(p00, a0, b0, sf, candidates);
  for (int k = 0; k < count; ++k) surface_->prefetch(candidates[k]);
  // intersect() of every candidate, the plane crossings four at a time; the shading (three
  // normal decodes) only for a crossing nearer than the best so far, the only ones that can
  // change it. shade() fails only for s < 0, which is tested first, so a crossing skipped
  // that way counts as crossed exactly as intersect() would have it.
  float hu[16], hv[16], hs[16];
  const unsigned planes = surface_->plane_hits(candidates, count, p1, l, hu, hv, hs);
  if (nearest_first_) {
    // The common case first: the nearest crossing by the planes alone (first among equals),
    // shaded once. When its shading succeeds, the loop below would pick the same candidate
    // (every candidate before it is farther, or shaded and then farther), with the same s;
    // when it is also accepted, no walk runs and that is the answer, bit for bit. Otherwise
    // (a failed shading, a back face, beyond the tolerance) the loop below decides.
    int nearest = -1;
    float nearest_s = std::numeric_limits<float>::infinity();
    for (int k = 0; k < count; ++k) {
      const float u = hu[k], v = hv[k], sk = hs[k];
      const bool inside = ((planes >> k) & 1u) && std::min(std::min(u, v), 1.f - u - v) >= 0.f && sk >= 0.f;
      if (inside && sk < nearest_s) nearest_s = sk, nearest = k;
    }
    float s = 0.f;
    Vec3 nrm;
    bool front = false;
    if (nearest >= 0 && surface_->shade(candidates[nearest], l, hu[nearest], hv[nearest], hs[nearest], 0.f, s, nrm, front) &&
        refine_accepts(s, front, t_blend)) {
      t0 = s;
      normal = nrm;
      triangle = candidates[nearest];
      return true;
    }
  }
  RefineHit best;
  std::uint32_t start = kNoTriangle;  // the candidate the line passes nearest, when it crosses none
  float nearest_outside = std::numeric_limits<float>::infinity();
  for (int k = 0; k < count; ++k) {
    float s = 0.f, outside = std::numeric_limits<float>::infinity();
    Vec3 nrm = Vec3::Zero();
    bool front = false;
    bool crossed = false;
    if ((planes >> k) & 1u) {
      const float u = hu[k], v = hv[k];
      const float w = std::min(std::min(u, v), 1.f - u - v);
      if (w < 0.f) {
        outside = -w;
      } else {
        outside = 0.f;
        if (!(hs[k] >= 0.f)) crossed = false;
        else if (hs[k] < best.s) crossed = surface_->shade(candidates[k], l, u, v, hs[k], 0.f, s, nrm, front);
        else crossed = true, s = hs[k];
      }
    }
    if (!crossed && outside < nearest_outside) {
      nearest_outside = outside;
      start = candidates[k];
    }
    if (crossed && s < best.s) best = {s, nrm, front, candidates[k]};
  }
  if (!refine_accepts(best.s, best.front, t_blend) && !refine_walks(start, candidates, count, p1, l, t_blend, best))
    return false;
  t0 = best.s;
  normal = best.normal;
  triangle = best.id;
  return true;
}

} // namespace hb
