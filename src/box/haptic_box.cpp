// Haptic box query (paper section 5).
//  1. Intersect the segment's line with the PBB (slab test). The entry point P1 is where the
//     line enters from outside; when the handle is inside the box the line is extended
//     backwards (paper Figure 5a). No box hit, or an entry beyond the tip: no contact.
//  2. The entry face and P1's grid coordinates give the cell (four position points) and the
//     positional weights (d1, d2) of eq. 1.
//  3. The direction l, seen in the face's hemi-cube frame, gives the sub-block (signs of the
//     in-face components), the sub-block face (cube-map major axis) and the directional
//     weights; the same for all four corners, so computed once.
//  4. At each corner, the four directional samples are blended (directional interpolation);
//     each corner's t is then corrected by half of its tangent-plane estimate at P1 (exact for
//     quadratic surfaces, see the reading notes); the four corners are blended (eq. 1).
//  5. Misses: a sample that missed the piece carries no t. Missed samples are dropped and the
//     remaining weights renormalised, but only when the hits carry at least half of the total
//     weight; otherwise the blend is a miss. This puts the silhouette half-way between a hit
//     and a miss sample (no invented surface beyond it, no lost surface before it) and never
//     blends a far exit distance into t0.
//  6a. Grazing (the raw box, no refinement): where the blended normal makes |n . l| below
//     kGrazingCosine, the blend of parallel rays is ill-conditioned and t0 strays; the
//     crossing is found on a quadric fitted to the samples across the surface instead
//     (settle_grazing() in haptic_box_settle.cpp, geometry/surface_fit.h), and a miss of
//     step 5 whose samples did hit is tried the same way.
//  6b. Below kRefitCosine (37-53 degrees off the normal) the crossing is met on a quadric of
//     the line's own samples (refit_on_own_samples(), the same file).
//  6. Contact test (Figure 7): the surface point P1 + t0 l must lie between the handle and
//     the tip, on the outside of the surface (n . l < 0); depth = d - t0; F = k depth n.
//     A refined answer (step 7) is a front-face crossing: only the range is tested, as
//     exact's rule does (a shaded normal can face along l at a thin sheet's rim).
//  7. Exact refinement (haptic_box_refine.cpp; optional, boxes baked with triangle ids;
//     before the contact test of step 6): the triangles hit by the 16 samples of step 4 are candidates; the line is
//     intersected with each exactly (when it crosses none, a walk from the candidate it
//     passes nearest follows at most kWalkSteps edges; when that walk fails, one from each
//     other candidate: set_walk_all_candidates; when every one fails, the nearest candidate's
//     walk goes on up to set_long_walk_steps edges), and the nearest front-face hit, when
//     it lies within two position cells of the blended t0 (or the blend was a miss), gives t0
//     and the shaded normal instead of the blend. Refine::misses limits this to answers that
//     could become contacts (scenes, see box_scene.cpp). The cost stays bounded whatever the
//     triangle count; docs/refinement.md has the measurements.
//  8. The samples are read through a fetch policy (raw records, block or Haar codec): the
//     codec is switched on once per query and the query body is instantiated per codec.
//     Every codec keeps hit/miss exact, so step 5 sees the same silhouettes on a compressed
//     table as on the raw one; only t and the normals move, within the codec's bound.
//  9. The body is split in two: locate() (steps 1-3 and the start of the fetches) and
//     finish() (the blends, steps 6 and 7). query() runs them back to back; query_many() runs
//     locate() for a group of queries before finishing any, so their DRAM misses overlap.
// 10. query_many() on a raw table without refinement runs 4 or 8 queries side by side in SIMD
//     lanes instead, with the same arithmetic bit for bit (query_lanes.cpp, docs/speed.md).
#include "box/haptic_box.h"
#include "box/haptic_box_located.h"
#include "box/sample_fetch.h"
#include "errors.h"
#include "geometry/octahedral.h"
#include "prefetch.h"
#include <algorithm>
#include <cmath>
#include <limits>
#include <type_traits>
#include <emmintrin.h>  // SSE2: the x86-64 baseline


namespace hb {

bool HapticBox::query_into(const Segment& segment, const ForceLaw& law, Contact& out,
                           float& distance_from_handle, Refine refine_hit, bool* refined,
                           std::uint32_t* triangle, DecodedQuads* quads) const noexcept {
  if (!has_table()) return out = Contact{}, false;  // a frame answers nothing
  switch (samples_.codec()) {
  case CodecId::block:
    return query_with(box_query::CodecFetch<BlockTable>{samples_.block(), quads}, segment, law, out, distance_from_handle,
                      refine_hit, refined, triangle);
  case CodecId::haar:
    return query_with(box_query::CodecFetch<HaarTable>{samples_.haar()}, segment, law, out, distance_from_handle, refine_hit,
                      refined, triangle);
  default:
    return query_with(box_query::RawFetch(table_, layout_), segment, law, out,
                      distance_from_handle, refine_hit, refined, triangle);
  }
}

// Whether locate() starts loading the four quads' triangle ids (every policy but the
// geometry-only one of query_near, which reads no ids).
template <class Fetch> struct prefetches_ids : std::true_type {};

template <class Fetch>
bool HapticBox::locate(const Fetch& fetch, const Segment& segment, Located<Fetch>& q) const noexcept {
  // All geometry up to the corner blend runs in box-local coordinates: one 3 x 3 transform
  // of the handle and of l, reciprocals instead of divisions, no Eigen temporaries.
  const float sx = segment.start.x(), sy = segment.start.y(), sz = segment.start.z();
  const float dx = segment.end.x() - sx, dy = segment.end.y() - sy, dz = segment.end.z() - sz;
  const float length = std::sqrt(dx * dx + dy * dy + dz * dz);
  if (!(length > 0.f && length <= std::numeric_limits<float>::max())) return false;
  const float inv_length = 1.f / length;
  const float lx = dx * inv_length, ly = dy * inv_length, lz = dz * inv_length;
  // 1. Entry into the PBB (slab test in local coordinates, as intersect_line_obb), along the
  // segment's own vector D = end - start (parameter s = t / length): it needs neither the
  // length nor l, so it runs beside their square root and division, and so do steps 2-3
  // (the cube-map projection is invariant to the scale of the direction).
  const BoxLayout::Local& L = layout_.local();
  const float px = sx - L.center[0], py = sy - L.center[1], pz = sz - L.center[2];
  float o[3], D[3];
  for (int a = 0; a < 3; ++a) {
    o[a] = L.rt[a][0] * px + L.rt[a][1] * py + L.rt[a][2] * pz;
    D[a] = L.rt[a][0] * dx + L.rt[a][1] * dy + L.rt[a][2] * dz;
  }
  float s_enter = -std::numeric_limits<float>::infinity();
  float s_exit = std::numeric_limits<float>::infinity();
  int face = 0;
  const float parallel = 1e-12f * length;  // |l . axis| < 1e-12: parallel to the slab
  for (int a = 0; a < 3; ++a) {
    if (std::fabs(D[a]) < parallel) {
      if (o[a] < -L.half[a] || o[a] > L.half[a]) return false;
      continue;
    }
    const float inv = 1.f / D[a];
    float s0 = (-L.half[a] - o[a]) * inv;
    float s1 = (L.half[a] - o[a]) * inv;
    int f0 = 2 * a;
    if (s0 > s1) {
      std::swap(s0, s1);
      f0 = 2 * a + 1;
    }
    if (s0 > s_enter) {
      s_enter = s0;
      face = f0;
    }
    s_exit = std::min(s_exit, s1);
  }
  if (!(s_enter <= s_exit) || !(std::fabs(s_enter) <= std::numeric_limits<float>::max())) return false;
  if (s_enter > 1.f || s_exit < 0.f) return false;
  const float t_enter = s_enter * length;
  const float d = length - t_enter;

  // 2. Cell and positional weights.
  const FaceAxes fa = face_axes(face);
  const int cells_m = params_.m - 1;
  const float half_cells = 0.5f * float(cells_m);
  int i0, j0;
  float d1, d2;
  box_query::split_cell((o[fa.u] + s_enter * D[fa.u]) * L.grid_scale[fa.u] + half_cells, cells_m, i0, d1);
  box_query::split_cell((o[fa.v] + s_enter * D[fa.v]) * L.grid_scale[fa.v] + half_cells, cells_m, j0, d2);

  // 3. Directional cell, once for all corners (cube-map projection with one reciprocal).
  const float x = D[fa.u], y = D[fa.v], z = -fa.sign * D[fa.a];
  const int sub = (x < 0.f ? 1 : 0) | (y < 0.f ? 2 : 0);
  const float X = std::fabs(x), Y = std::fabs(y), Z = std::max(z, 0.f);
  int sface;
  float num1, num2, den;
  if (Z >= X && Z >= Y) {
    sface = 0, num1 = X, num2 = Y, den = Z;
  } else if (X >= Y) {
    sface = 1, num1 = Y, num2 = Z, den = X;
  } else {
    sface = 2, num1 = X, num2 = Z, den = Y;
  }
  const int cells_n = params_.n - 1;
  const float dir_scale = float(cells_n) / den;
  int a0, b0;
  float wa, wb;
  box_query::split_cell(num1 * dir_scale, cells_n, a0, wa);
  box_query::split_cell(num2 * dir_scale, cells_n, b0, wb);
  const std::size_t sf = BoxLayout::sub_face(sub, sface);
  const float dir_w[4] = {(1.f - wa) * (1.f - wb), wa * (1.f - wb), wa * wb, (1.f - wa) * wb};

  // 4. Corners (P2..P5 of eq. 1): start all four corners' loads before using any
  // (memory-level parallelism instead of four serial misses).
  const std::size_t p00 = layout_.position_index(face, i0, j0);
  if (triangle_ids_.data && prefetches_ids<Fetch>::value) {
    // The triangle ids of the four quads (refinement), loaded now so they arrive with the samples.
    const std::size_t n = std::size_t(params_.n);
    for (int c = 0; c < 4; ++c) {
      const std::size_t first = layout_.first_sample(p00 + layout_.corner_step(c), sf, a0, b0);
      hb::prefetch(triangle_ids_.address(first));
      hb::prefetch(triangle_ids_.address(first + n + 1));
    }
  }
  for (int c = 0; c < 4; ++c) fetch.begin(p00 + layout_.corner_step(c), sf, a0, b0, q.corners[c]);
  q.sx = sx, q.sy = sy, q.sz = sz, q.lx = lx, q.ly = ly, q.lz = lz;
  q.t_enter = t_enter, q.d = d, q.d1 = d1, q.d2 = d2;
  q.face = face, q.i0 = i0, q.j0 = j0, q.a0 = a0, q.b0 = b0;
  q.p00 = p00, q.sf = sf;
  for (int k = 0; k < 4; ++k) q.dir_w[k] = dir_w[k];
  return true;
}

// The contact of an answer that passed step 6's test: surface point, depth, normal, force
// (finish() and refined_contact() share it, so both give the same bits).
static inline void write_contact(float sx, float sy, float sz, float lx, float ly, float lz, float t_enter,
                                 float d, float t0, float nx, float ny, float nz, const ForceLaw& law,
                                 Contact& out, float& distance_from_handle) noexcept {
  const float along = t_enter + t0;  // handle to surface point
  out.contact = true;
  out.depth = d - t0;
  out.point = Vec3(sx + along * lx, sy + along * ly, sz + along * lz);
  out.normal = Vec3(nx, ny, nz);
  apply_force_law(out, law);
  if (law.depth == DepthLaw::normal) out.force *= depth_law_scale(law, lx, ly, lz, out.normal);
  distance_from_handle = along;
}

// Steps 4-5: the corners' samples blended into t0 (along l from P1) and the unit normal;
// false for a blended miss. Bit c of `corners_hit`: corner c has a hit among its samples.
template <class Fetch>
inline bool HapticBox::blend(const Fetch& fetch, const Located<Fetch>& q, float& t0, float& nx, float& ny, float& nz,
                             int& corners_hit, bool any_hit) const noexcept {
  const float sx = q.sx, sy = q.sy, sz = q.sz, lx = q.lx, ly = q.ly, lz = q.lz;
  const float t_enter = q.t_enter, d1 = q.d1, d2 = q.d2;
  const int face = q.face, i0 = q.i0, j0 = q.j0;
  const box_query::Corners4 blended = fetch.blend4(q.corners, q.dir_w);

  // The four corners side by side (SSE2 lanes): miss rule, normalisation, half of the
  // tangent-plane correction from the corner to P1, positional blend.
  const float p1x = sx + t_enter * lx, p1y = sy + t_enter * ly, p1z = sz + t_enter * lz;
  const BoxLayout::FaceFrame& ff = layout_.frame(face);
  const __m128 zero = _mm_setzero_ps();
  const __m128 W = blended.w;
  const __m128 omd1 = _mm_setr_ps(1.f - d1, d1, d1, 1.f - d1);
  const __m128 omd2 = _mm_setr_ps(1.f - d2, 1.f - d2, d2, d2);
  const __m128 PW = _mm_mul_ps(omd1, omd2);
  const __m128 valid = _mm_and_ps(_mm_cmpgt_ps(PW, zero), any_hit ? _mm_cmpgt_ps(W, zero) : _mm_cmpge_ps(W, _mm_set1_ps(0.5f)));
  __m128 T = _mm_div_ps(blended.t, W);
  // The tangent-plane correction DN / LN is invariant to the scale of the corner normal, so
  // it uses the blended normal as summed; its normalisation runs beside it, off the
  // dependency chain from the loads to t0.
  const __m128 NXu = blended.nx, NYu = blended.ny, NZu = blended.nz;
  const __m128 sq = _mm_add_ps(_mm_add_ps(_mm_mul_ps(NXu, NXu), _mm_mul_ps(NYu, NYu)), _mm_mul_ps(NZu, NZu));
  const __m128 rn = _mm_and_ps(_mm_cmpgt_ps(sq, zero), _mm_div_ps(_mm_set1_ps(1.f), _mm_sqrt_ps(sq)));
  const __m128 NX = _mm_mul_ps(NXu, rn), NY = _mm_mul_ps(NYu, rn), NZ = _mm_mul_ps(NZu, rn);
  const __m128 CI = _mm_setr_ps(float(i0), float(i0 + 1), float(i0 + 1), float(i0));
  const __m128 CJ = _mm_setr_ps(float(j0), float(j0), float(j0 + 1), float(j0 + 1));
  const auto offset = [&](float origin, float p1, float si, float sj) {
    return _mm_add_ps(_mm_set1_ps(origin - p1),
                      _mm_add_ps(_mm_mul_ps(CI, _mm_set1_ps(si)), _mm_mul_ps(CJ, _mm_set1_ps(sj))));
  };
  const __m128 DX = offset(ff.origin.x(), p1x, ff.step_i.x(), ff.step_j.x());
  const __m128 DY = offset(ff.origin.y(), p1y, ff.step_i.y(), ff.step_j.y());
  const __m128 DZ = offset(ff.origin.z(), p1z, ff.step_i.z(), ff.step_j.z());
  const __m128 LNu = _mm_add_ps(_mm_add_ps(_mm_mul_ps(NXu, _mm_set1_ps(lx)), _mm_mul_ps(NYu, _mm_set1_ps(ly))),
                                _mm_mul_ps(NZu, _mm_set1_ps(lz)));
  const __m128 DNu = _mm_add_ps(_mm_add_ps(_mm_mul_ps(NXu, DX), _mm_mul_ps(NYu, DY)), _mm_mul_ps(NZu, DZ));
  const __m128 corrected = _mm_max_ps(zero, _mm_add_ps(T, _mm_mul_ps(_mm_set1_ps(0.5f), _mm_div_ps(DNu, LNu))));
  // Steep enough (unit n . l < -0.2) for the correction; a zero normal is never steep.
  const __m128 steep = _mm_cmplt_ps(_mm_mul_ps(LNu, rn), _mm_set1_ps(-0.2f));
  T = _mm_or_ps(_mm_and_ps(steep, corrected), _mm_andnot_ps(steep, T));
  const __m128 PWv = _mm_and_ps(valid, PW);
  __m128 s0 = PWv, s1 = _mm_and_ps(valid, _mm_mul_ps(PW, T));
  __m128 s2 = _mm_and_ps(valid, _mm_mul_ps(PW, NX)), s3 = _mm_and_ps(valid, _mm_mul_ps(PW, NY));
  __m128 wnz = _mm_and_ps(valid, _mm_mul_ps(PW, NZ));
  _MM_TRANSPOSE4_PS(s0, s1, s2, s3);
  alignas(16) float sums[4];
  _mm_store_ps(sums, _mm_add_ps(_mm_add_ps(s0, s1), _mm_add_ps(s2, s3)));
  wnz = _mm_add_ps(wnz, _mm_movehl_ps(wnz, wnz));
  wnz = _mm_add_ss(wnz, _mm_shuffle_ps(wnz, wnz, 1));
  const float corner_hit_weight = sums[0];
  const float nsx = sums[2], nsy = sums[3], nsz = _mm_cvtss_f32(wnz);
  const float nlen = std::sqrt(nsx * nsx + nsy * nsy + nsz * nsz);
  const bool blended_hit = (any_hit ? corner_hit_weight > 0.f : corner_hit_weight >= 0.5f) && nlen > 0.f;
  t0 = blended_hit ? sums[1] / corner_hit_weight : -1.f;
  nx = ny = nz = 0.f;
  corners_hit = _mm_movemask_ps(_mm_cmpgt_ps(W, zero));
  if (blended_hit) {
    const float inv_nlen = 1.f / nlen;
    nx = nsx * inv_nlen, ny = nsy * inv_nlen, nz = nsz * inv_nlen;
  }
  return blended_hit;
}

template <class Fetch>
bool HapticBox::finish(const Fetch& fetch, const Located<Fetch>& q, const ForceLaw& law, Contact& out,
                       float& distance_from_handle, Refine refine_hit, bool* refined,
                       std::uint32_t* triangle) const noexcept {
  if (refined) *refined = false;
  if (triangle) *triangle = kNoTriangle;
  const float sx = q.sx, sy = q.sy, sz = q.sz, lx = q.lx, ly = q.ly, lz = q.lz;
  const float t_enter = q.t_enter, d = q.d;
  const int a0 = q.a0, b0 = q.b0;
  const std::size_t p00 = q.p00, sf = q.sf;
  float t0, nx, ny, nz;
  int corners_hit = 0;
  bool blended_hit = blend(fetch, q, t0, nx, ny, nz, corners_hit, false);
  const float p1x = sx + t_enter * lx, p1y = sy + t_enter * ly, p1z = sz + t_enter * lz;
  // 6a, 6b. A blend more than 37 degrees off the normal is met on a fitted quadric
  // (settle_grazing(), refit_on_own_samples()).
  if (!surface_) {
    if (blended_hit) {
      // Only a crossing that could be the segment's: the blend's own error along l grows as
      // 1 / |n . l|, so one farther than kSettleReachCells / |n . l| position cells beyond
      // either end stays a miss however it settles (on 200,000 segments of each smooth model
      // placed from 6 mm before to 6 mm past the surface, the same answers bit for bit as
      // settling all; a reach of 1 / |n . l| cells changed 4). So a servo loop's handle
      // inside the object does not settle the entry behind it.
      const float c = -(nx * lx + ny * ly + nz * lz);
      const float reach = kSettleReachCells * position_cell() / std::max(std::fabs(c), 0.02f);
      if (t_enter + t0 >= -reach && t0 <= d + reach) {
        if (c < kGrazingCosine) settle_grazing(fetch, p1x, p1y, p1z, lx, ly, lz, t0, nx, ny, nz);
        else if (c < kRefitCosine)
          refit_on_own_samples(fetch, q, Vec3(p1x, p1y, p1z), Vec3(lx, ly, lz), t0, nx, ny, nz);
      }
    } else if (corners_hit != 0) {
      // A miss by the half-weight rule of step 5 whose samples did hit: at a grazing angle
      // the line runs along the silhouette its samples see. When the hits alone blend into a
      // grazing estimate that settles, the line does meet the surface there.
      float t1, mx, my, mz;
      int any = 0;
      if (blend(fetch, q, t1, mx, my, mz, any, true) && mx * lx + my * ly + mz * lz > -kGrazingCosine &&
          settle_grazing(fetch, p1x, p1y, p1z, lx, ly, lz, t1, mx, my, mz))
        blended_hit = true, t0 = t1, nx = mx, ny = my, nz = mz;
    }
  }
  // 6. Contact test (after the refinement of step 7 where it runs).
  const auto in_contact = [&](float t, float x, float y, float z) {
    return t_enter + t >= 0.f && t <= d && x * lx + y * ly + z * lz < 0.f;
  };
  bool contact = blended_hit && in_contact(t0, nx, ny, nz);
  // Refine::misses: only answers the refinement could turn into a contact (an accepted
  // refinement stays within refine_tolerance_ of a blended hit).
  std::uint32_t crossed_face = kNoTriangle;  // the triangle a refinement crossed
  const bool could_flip = !contact && (!blended_hit || (t0 <= d + refine_tolerance_ && t_enter + t0 >= -refine_tolerance_));
  if (surface_ && (refine_hit == Refine::all || (refine_hit == Refine::misses && could_flip)) &&
      corners_hit != 0) {
    const float p1[3] = {p1x, p1y, p1z}, l[3] = {lx, ly, lz};
    Vec3 refined_normal;
    float refined_t = 0.f;
    std::uint32_t refined_triangle = kNoTriangle;
    if (refine(p00, a0, b0, sf, p1, l, blended_hit ? t0 : -1.f, refined_t, refined_normal, refined_triangle)) {
      t0 = refined_t;
      nx = refined_normal.x(), ny = refined_normal.y(), nz = refined_normal.z();
      // A refined crossing is a front face (refine() accepts no other): the contact test is
      // exact's, the range only (the shaded normal may face along l at a thin sheet's rim).
      contact = t_enter + t0 >= 0.f && t0 <= d;
      if (refined) *refined = true;
      if (triangle) *triangle = refined_triangle;
      crossed_face = refined_triangle;
    }
  }
  if (!contact) return false;
  write_contact(sx, sy, sz, lx, ly, lz, t_enter, d, t0, nx, ny, nz, law, out, distance_from_handle);
  if (crossed_face != kNoTriangle) out.face_normal = surface_->face_normal(crossed_face);
  return true;
}

template <class Fetch>
bool HapticBox::query_with(const Fetch& fetch, const Segment& segment, const ForceLaw& law, Contact& out,
                           float& distance_from_handle, Refine refine, bool* refined,
                           std::uint32_t* triangle) const noexcept {
  out = Contact{};
  if (refined) *refined = false;
  if (triangle) *triangle = kNoTriangle;
  Located<Fetch> q;
  if (!locate(fetch, segment, q)) return false;
  fetch.resolve_all(q.corners);
  return finish(fetch, q, law, out, distance_from_handle, refine, refined, triangle);
}

// Batches: the geometry and the fetches of a group of queries start before any blend, so
// the DRAM misses of the whole group (8 cache lines a query) overlap instead of running in
// series query after query. Each query goes through the same locate() and finish() as
// query(), so the answers are the same bit for bit.
template <class Fetch>
void HapticBox::query_many_with(const Fetch& fetch, const Segment* segments, std::size_t count, const ForceLaw& law,
                                Contact* out) const noexcept {
  constexpr std::size_t kGroup = 8;
  Located<Fetch> q[kGroup];
  bool located[kGroup];
  for (std::size_t first = 0; first < count; first += kGroup) {
    const std::size_t size = std::min(kGroup, count - first);
    for (std::size_t i = 0; i < size; ++i) located[i] = locate(fetch, segments[first + i], q[i]);
    for (std::size_t i = 0; i < size; ++i)
      if (located[i])
        fetch.resolve_all(q[i].corners);
    for (std::size_t i = 0; i < size; ++i) {
      Contact& c = out[first + i];
      c = Contact{};
      float along = 0.f;
      if (located[i]) finish(fetch, q[i], law, c, along, Refine::all);
    }
  }
}

void HapticBox::query_many(const Segment* segments, std::size_t count, const ForceLaw& law,
                           Contact* out) const noexcept {
  if (!has_table()) return std::fill(out, out + count, Contact{});
  switch (samples_.codec()) {
  case CodecId::block:
    return query_many_with(box_query::CodecFetch<BlockTable>{samples_.block()}, segments, count, law, out);
  case CodecId::haar:
    return query_many_with(box_query::CodecFetch<HaarTable>{samples_.haar()}, segments, count, law, out);
  default:
    if (!surface_) return query_many_lanes(segments, count, law, out);
    return query_many_with(box_query::RawFetch(table_, layout_), segments, count,
                           law, out);
  }
}

namespace {
// A fetch policy that reads no samples (query_refined: the triangle ids alone).
struct NoFetch {
  struct Corner {};
  void begin(std::size_t, std::size_t, int, int, Corner&) const noexcept {}
  void resolve(Corner&) const noexcept {}
  void resolve_all(Corner*) const noexcept {}
};
// Nor triangle ids (query_near needs the geometry of locate() only).
struct GeometryOnly : NoFetch {};
} // namespace
template <> struct prefetches_ids<GeometryOnly> : std::false_type {};

// Step 6's contact on a refined answer: the same arithmetic as finish().
static bool refined_contact(float sx, float sy, float sz, float lx, float ly, float lz, float t_enter, float d,
                            float t0, const Vec3& normal, const ForceLaw& law, Contact& out,
                            float& distance_from_handle) noexcept {
  // The crossing is a front face (refine() and query_near accept no other); as exact's, the
  // contact does not ask the shaded normal to face the line.
  const float nx = normal.x(), ny = normal.y(), nz = normal.z();
  if (!(t_enter + t0 >= 0.f && t0 <= d)) return false;
  write_contact(sx, sy, sz, lx, ly, lz, t_enter, d, t0, nx, ny, nz, law, out, distance_from_handle);
  return true;
}

bool HapticBox::query_near(const Segment& segment, const ForceLaw& law, std::uint32_t triangle, int max_steps,
                           Contact& out, float& distance_from_handle, std::uint32_t* crossed) const noexcept {
  out = Contact{};
  if (!surface_) return false;
  Located<GeometryOnly> q;
  if (!locate(GeometryOnly{}, segment, q)) return false;
  const float p1[3] = {q.sx + q.t_enter * q.lx, q.sy + q.t_enter * q.ly, q.sz + q.t_enter * q.lz};
  const float l[3] = {q.lx, q.ly, q.lz};
  float t0 = 0.f;
  Vec3 normal;
  bool front = false;
  std::uint32_t face = kNoTriangle;
  if (!surface_->walk(triangle, p1, l, 0.f, max_steps, t0, normal, front, &face) || !front) return false;
  if (crossed) *crossed = face;
  if (!refined_contact(q.sx, q.sy, q.sz, q.lx, q.ly, q.lz, q.t_enter, q.d, t0, normal, law, out, distance_from_handle))
    return false;
  out.face_normal = surface_->face_normal(face);
  return true;
}

bool HapticBox::query_refined(const Segment& segment, const ForceLaw& law, Contact& out, float& distance_from_handle,
                              std::uint32_t* triangle) const noexcept {
  out = Contact{};
  if (triangle) *triangle = kNoTriangle;
  if (!surface_) return false;
  Located<NoFetch> q;  // also prefetches the four quads' triangle ids
  if (!locate(NoFetch{}, segment, q)) return false;
  const float p1[3] = {q.sx + q.t_enter * q.lx, q.sy + q.t_enter * q.ly, q.sz + q.t_enter * q.lz};
  const float l[3] = {q.lx, q.ly, q.lz};
  float t0 = 0.f;
  Vec3 normal;
  std::uint32_t id = kNoTriangle;
  if (!refine(q.p00, q.a0, q.b0, q.sf, p1, l, -1.f, t0, normal, id)) return false;
  if (!refined_contact(q.sx, q.sy, q.sz, q.lx, q.ly, q.lz, q.t_enter, q.d, t0, normal, law, out, distance_from_handle))
    return false;
  out.face_normal = surface_->face_normal(id);
  if (triangle) *triangle = id;
  return true;
}

Contact HapticBox::query(const Segment& segment, const ForceLaw& law) const noexcept {
  Contact c;
  float along = 0.f;
  query_into(segment, law, c, along);
  return c;
}

} // namespace hb
