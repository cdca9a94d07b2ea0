// Batched haptic box queries, four side by side in the lanes of SSE2 vectors.
//
// query() is one long dependency chain (square roots and divisions from the probe to the
// sample addresses, then from the samples to t0) of about 1,100 instructions, longer than
// the core's reorder window: two queries in a row hardly overlap, even when their samples are
// in cache. Here lane q of every vector belongs to query q, so each instruction advances four
// queries and their chains run side by side. query_many() uses this path for raw tables
// without refinement (the common case for evaluations, error fields and several contact
// points per tick); codecs and refining boxes keep the one-query path.
//
// Every arithmetic step is the one query() performs, in the same order and association, on
// the same operands (IEEE single precision, no fused multiply-add on the SSE2 baseline), so
// the answers are query()'s bit for bit (tests/core/query_many_test.cpp checks it): the
// comments name the step of haptic_box.cpp that each block mirrors. Selections replace
// query()'s branches (the slab test's swap and entry face, the cube-map face), with the same
// tie rules. A lane whose segment misses the box reads the table's first samples and is
// answered "no contact".
#include "haptic_box/haptic_box.h"
#include <algorithm>
#include <atomic>
#include <cmath>
#include <limits>
#include <emmintrin.h>  // SSE2: the x86-64 baseline

namespace hb {

// Inlined into both the SSE2 and the AVX entry points below.
#define HB_LANES_INLINE __attribute__((always_inline)) inline

namespace {

HB_LANES_INLINE __m128 select(__m128 mask, __m128 a, __m128 b) noexcept {
  return _mm_or_ps(_mm_and_ps(mask, a), _mm_andnot_ps(mask, b));
}
HB_LANES_INLINE __m128i select(__m128i mask, __m128i a, __m128i b) noexcept {
  return _mm_or_si128(_mm_and_si128(mask, a), _mm_andnot_si128(mask, b));
}
HB_LANES_INLINE __m128 abs_ps(__m128 x) noexcept { return _mm_andnot_ps(_mm_set1_ps(-0.f), x); }

// split_cell of haptic_box.cpp per lane: f clamped to [0, cells], i0 = min(int(f), cells - 1),
// w = f - i0 (std::max(f, 0) is (0 > f ? 0 : f), std::min(x, cells) is (cells < x ? cells : x)).
HB_LANES_INLINE void split_cells(__m128 f, int cells, __m128i& i0, __m128& w) noexcept {
  f = _mm_min_ps(_mm_set1_ps(float(cells)), _mm_max_ps(_mm_setzero_ps(), f));
  const __m128i last = _mm_set1_epi32(cells - 1);
  const __m128i i = _mm_cvttps_epi32(f);
  i0 = select(_mm_cmplt_epi32(last, i), last, i);
  w = _mm_sub_ps(f, _mm_cvtepi32_ps(i0));
}

// One sample of every lane (corner_lanes of haptic_box.cpp, lane by lane): the weight zeroed
// for a miss, and the weighted t and un-normalised octahedral normal.
struct SampleLanes {
  __m128 w, t, nx, ny, nz;
};
HB_LANES_INLINE SampleLanes sample_lanes(__m128 t, __m128 code_bits, __m128 w) noexcept {
  const __m128i codes = _mm_castps_si128(code_bits);
  w = _mm_and_ps(w, _mm_cmpge_ps(t, _mm_setzero_ps()));
  const __m128 scale = _mm_set1_ps(1.f / 32767.f);
  __m128 u = _mm_mul_ps(_mm_cvtepi32_ps(_mm_srai_epi32(_mm_slli_epi32(codes, 16), 16)), scale);
  __m128 v = _mm_mul_ps(_mm_cvtepi32_ps(_mm_srai_epi32(codes, 16)), scale);
  const __m128 sign = _mm_set1_ps(-0.f);
  const __m128 z = _mm_sub_ps(_mm_sub_ps(_mm_set1_ps(1.f), _mm_andnot_ps(sign, u)), _mm_andnot_ps(sign, v));
  const __m128 fold = _mm_max_ps(_mm_sub_ps(_mm_setzero_ps(), z), _mm_setzero_ps());
  u = _mm_sub_ps(u, _mm_or_ps(fold, _mm_and_ps(u, sign)));
  v = _mm_sub_ps(v, _mm_or_ps(fold, _mm_and_ps(v, sign)));
  return {w, _mm_mul_ps(w, t), _mm_mul_ps(w, u), _mm_mul_ps(w, v), _mm_mul_ps(w, z)};
}

// (a + b) + (c + d): the association of lane_sums in haptic_box.cpp.
HB_LANES_INLINE __m128 sum4(__m128 a, __m128 b, __m128 c, __m128 d) noexcept {
  return _mm_add_ps(_mm_add_ps(a, b), _mm_add_ps(c, d));
}

} // namespace

// Four queries between their two phases (as HapticBox::Located, one lane per query).
struct HapticBox::Lanes {
  int count = 0;                  // lanes in use
  int located = 0;                // bit q: lane q met the box
  __m128 sx, sy, sz, lx, ly, lz;  // handle, unit direction
  __m128 t_enter, d, d1, d2;
  __m128 dir_w[4];                // directional weights, (0,0), (1,0), (1,1), (0,1)
  alignas(16) int face[4], i0[4], j0[4];
  const Sample* corner[4][4];     // [corner][lane]: the first sample of the corner's quad
};

HB_LANES_INLINE void HapticBox::locate_lanes(const Segment* segments, int count, Lanes& q) const noexcept {
  q.count = count;
  alignas(16) float S[3][4], E[3][4];
  for (int k = 0; k < 4; ++k) {
    const Segment& s = segments[k < count ? k : 0];
    for (int a = 0; a < 3; ++a) S[a][k] = s.start[a], E[a][k] = s.end[a];
  }
  const __m128 zero = _mm_setzero_ps(), one = _mm_set1_ps(1.f);
  const __m128 sx = _mm_load_ps(S[0]), sy = _mm_load_ps(S[1]), sz = _mm_load_ps(S[2]);
  const __m128 dx = _mm_sub_ps(_mm_load_ps(E[0]), sx), dy = _mm_sub_ps(_mm_load_ps(E[1]), sy),
               dz = _mm_sub_ps(_mm_load_ps(E[2]), sz);
  const __m128 length =
      _mm_sqrt_ps(_mm_add_ps(_mm_add_ps(_mm_mul_ps(dx, dx), _mm_mul_ps(dy, dy)), _mm_mul_ps(dz, dz)));
  const __m128 max_float = _mm_set1_ps(std::numeric_limits<float>::max());
  __m128 reject = _mm_or_ps(_mm_cmpngt_ps(length, zero), _mm_cmpnle_ps(length, max_float));
  const __m128 inv_length = _mm_div_ps(one, length);
  q.sx = sx, q.sy = sy, q.sz = sz;
  q.lx = _mm_mul_ps(dx, inv_length), q.ly = _mm_mul_ps(dy, inv_length), q.lz = _mm_mul_ps(dz, inv_length);

  // Step 1: the slab test in box-local coordinates (locate(), lane by lane).
  const __m128 px = _mm_sub_ps(sx, _mm_set1_ps(center_[0])), py = _mm_sub_ps(sy, _mm_set1_ps(center_[1])),
               pz = _mm_sub_ps(sz, _mm_set1_ps(center_[2]));
  __m128 o[3], D[3];
  for (int a = 0; a < 3; ++a) {
    const __m128 r0 = _mm_set1_ps(rt_[a][0]), r1 = _mm_set1_ps(rt_[a][1]), r2 = _mm_set1_ps(rt_[a][2]);
    o[a] = _mm_add_ps(_mm_add_ps(_mm_mul_ps(r0, px), _mm_mul_ps(r1, py)), _mm_mul_ps(r2, pz));
    D[a] = _mm_add_ps(_mm_add_ps(_mm_mul_ps(r0, dx), _mm_mul_ps(r1, dy)), _mm_mul_ps(r2, dz));
  }
  __m128 s_enter = _mm_set1_ps(-std::numeric_limits<float>::infinity());
  __m128 s_exit = _mm_set1_ps(std::numeric_limits<float>::infinity());
  __m128i face = _mm_setzero_si128();
  const __m128 parallel = _mm_mul_ps(_mm_set1_ps(1e-12f), length);
  for (int a = 0; a < 3; ++a) {
    const __m128 half = _mm_set1_ps(half_[a]), neg_half = _mm_set1_ps(-half_[a]);
    const __m128 par = _mm_cmplt_ps(abs_ps(D[a]), parallel);
    reject = _mm_or_ps(reject, _mm_and_ps(par, _mm_or_ps(_mm_cmplt_ps(o[a], neg_half), _mm_cmpgt_ps(o[a], half))));
    const __m128 inv = _mm_div_ps(one, D[a]);
    const __m128 s0 = _mm_mul_ps(_mm_sub_ps(neg_half, o[a]), inv);
    const __m128 s1 = _mm_mul_ps(_mm_sub_ps(half, o[a]), inv);
    const __m128 swap = _mm_cmpgt_ps(s0, s1);
    const __m128 lo = select(swap, s1, s0), hi = select(swap, s0, s1);
    const __m128i f0 = _mm_sub_epi32(_mm_set1_epi32(2 * a), _mm_castps_si128(swap));  // 2a, or 2a + 1 swapped
    const __m128 enter = _mm_andnot_ps(par, _mm_cmpgt_ps(lo, s_enter));
    s_enter = select(enter, lo, s_enter);
    face = select(_mm_castps_si128(enter), f0, face);
    s_exit = select(_mm_andnot_ps(par, _mm_cmplt_ps(hi, s_exit)), hi, s_exit);  // std::min(s_exit, s1)
  }
  reject = _mm_or_ps(reject, _mm_cmpnle_ps(s_enter, s_exit));
  reject = _mm_or_ps(reject, _mm_cmpnle_ps(abs_ps(s_enter), max_float));
  reject = _mm_or_ps(reject, _mm_or_ps(_mm_cmpgt_ps(s_enter, one), _mm_cmplt_ps(s_exit, zero)));
  q.located = ~_mm_movemask_ps(reject) & ((1 << count) - 1);
  q.t_enter = _mm_mul_ps(s_enter, length);
  q.d = _mm_sub_ps(length, q.t_enter);

  // The entry face's axes per lane: a = face / 2, u = (a + 1) % 3, v = (a + 2) % 3.
  const __m128i axis = _mm_srli_epi32(face, 1);
  const __m128 on[3] = {_mm_castsi128_ps(_mm_cmpeq_epi32(axis, _mm_setzero_si128())),
                        _mm_castsi128_ps(_mm_cmpeq_epi32(axis, _mm_set1_epi32(1))),
                        _mm_castsi128_ps(_mm_cmpeq_epi32(axis, _mm_set1_epi32(2)))};
  const auto pick = [&](const __m128* x, int shift) {  // x[(a + shift) % 3] per lane
    return _mm_or_ps(_mm_or_ps(_mm_and_ps(on[0], x[shift % 3]), _mm_and_ps(on[1], x[(1 + shift) % 3])),
                     _mm_and_ps(on[2], x[(2 + shift) % 3]));
  };
  const __m128 scales[3] = {_mm_set1_ps(grid_scale_[0]), _mm_set1_ps(grid_scale_[1]), _mm_set1_ps(grid_scale_[2])};

  // Step 2: cell and positional weights.
  const int cells_m = params_.m - 1;
  const __m128 half_cells = _mm_set1_ps(0.5f * float(cells_m));
  __m128i i0, j0;
  split_cells(_mm_add_ps(_mm_mul_ps(_mm_add_ps(pick(o, 1), _mm_mul_ps(s_enter, pick(D, 1))), pick(scales, 1)), half_cells),
              cells_m, i0, q.d1);
  split_cells(_mm_add_ps(_mm_mul_ps(_mm_add_ps(pick(o, 2), _mm_mul_ps(s_enter, pick(D, 2))), pick(scales, 2)), half_cells),
              cells_m, j0, q.d2);

  // Step 3: directional cell (the cube-map face by the same comparisons as locate()).
  const __m128 odd = _mm_castsi128_ps(_mm_cmpeq_epi32(_mm_and_si128(face, _mm_set1_epi32(1)), _mm_set1_epi32(1)));
  const __m128 minus_sign = select(odd, _mm_set1_ps(-1.f), one);  // -fa.sign
  const __m128 x = pick(D, 1), y = pick(D, 2), z = _mm_mul_ps(minus_sign, pick(D, 0));
  const __m128i sub = _mm_or_si128(_mm_and_si128(_mm_castps_si128(_mm_cmplt_ps(x, zero)), _mm_set1_epi32(1)),
                                   _mm_and_si128(_mm_castps_si128(_mm_cmplt_ps(y, zero)), _mm_set1_epi32(2)));
  const __m128 X = abs_ps(x), Y = abs_ps(y), Z = _mm_max_ps(zero, z);
  const __m128 top = _mm_and_ps(_mm_cmpge_ps(Z, X), _mm_cmpge_ps(Z, Y));
  const __m128 side_x = _mm_andnot_ps(top, _mm_cmpge_ps(X, Y));
  const __m128 num1 = select(side_x, Y, X);
  const __m128 num2 = select(top, Y, Z);
  const __m128 den = select(top, Z, select(side_x, X, Y));
  const __m128i sface = _mm_sub_epi32(_mm_setzero_si128(), _mm_add_epi32(_mm_castps_si128(side_x),
      _mm_slli_epi32(_mm_castps_si128(_mm_andnot_ps(_mm_or_ps(top, side_x), _mm_castsi128_ps(_mm_set1_epi32(-1)))), 1)));
  const int cells_n = params_.n - 1;
  const __m128 dir_scale = _mm_div_ps(_mm_set1_ps(float(cells_n)), den);
  __m128i a0, b0;
  __m128 wa, wb;
  split_cells(_mm_mul_ps(num1, dir_scale), cells_n, a0, wa);
  split_cells(_mm_mul_ps(num2, dir_scale), cells_n, b0, wb);
  const __m128 owa = _mm_sub_ps(one, wa), owb = _mm_sub_ps(one, wb);
  q.dir_w[0] = _mm_mul_ps(owa, owb);
  q.dir_w[1] = _mm_mul_ps(wa, owb);
  q.dir_w[2] = _mm_mul_ps(wa, wb);
  q.dir_w[3] = _mm_mul_ps(owa, wb);

  // Step 4: the corners' quads, all fetches started before any is used.
  alignas(16) int sf[4], sub_blocks[4], a0s[4], b0s[4];
  _mm_store_si128(reinterpret_cast<__m128i*>(q.face), face);
  _mm_store_si128(reinterpret_cast<__m128i*>(q.i0), i0);
  _mm_store_si128(reinterpret_cast<__m128i*>(q.j0), j0);
  _mm_store_si128(reinterpret_cast<__m128i*>(sub_blocks), sub);
  _mm_store_si128(reinterpret_cast<__m128i*>(sf), sface);
  _mm_store_si128(reinterpret_cast<__m128i*>(a0s), a0);
  _mm_store_si128(reinterpret_cast<__m128i*>(b0s), b0);
  const std::size_t m = std::size_t(params_.m), n = std::size_t(params_.n);
  const std::size_t per_position = params_.samples_per_position();
  const std::size_t corner_offset[4] = {0, m, m + 1, 1};
  for (int k = 0; k < 4; ++k) {
    if (!(q.located >> k & 1)) {
      for (int c = 0; c < 4; ++c) q.corner[c][k] = table_;  // read, never used
      continue;
    }
    const std::size_t p00 = std::size_t(q.face[k]) * m * m + std::size_t(q.i0[k]) * m + std::size_t(q.j0[k]);
    const std::size_t within = (std::size_t(sub_blocks[k]) * 3u + std::size_t(sf[k])) * n * n +
                               std::size_t(a0s[k]) * n + std::size_t(b0s[k]);
    for (int c = 0; c < 4; ++c) {
      const Sample* base = table_ + (p00 + corner_offset[c]) * per_position + within;
      q.corner[c][k] = base;
      __builtin_prefetch(base);
      __builtin_prefetch(base + n);
    }
  }
}

HB_LANES_INLINE void HapticBox::finish_lanes(const Lanes& q, const ForceLaw& law, Contact* out) const noexcept {
  const std::size_t n = std::size_t(params_.n);
  const __m128 zero = _mm_setzero_ps(), one = _mm_set1_ps(1.f);
  // Steps 4-5 per corner c (finish(), whose SSE lanes are the corners, lane by lane here).
  const __m128 p1x = _mm_add_ps(q.sx, _mm_mul_ps(q.t_enter, q.lx));
  const __m128 p1y = _mm_add_ps(q.sy, _mm_mul_ps(q.t_enter, q.ly));
  const __m128 p1z = _mm_add_ps(q.sz, _mm_mul_ps(q.t_enter, q.lz));
  alignas(16) float frame[9][4];  // origin, step_i, step_j of each lane's face
  for (int k = 0; k < 4; ++k) {
    const FaceFrame& f = faces_[q.face[k]];
    for (int a = 0; a < 3; ++a) frame[a][k] = f.origin[a], frame[3 + a][k] = f.step_i[a], frame[6 + a][k] = f.step_j[a];
  }
  const __m128 i0 = _mm_cvtepi32_ps(_mm_load_si128(reinterpret_cast<const __m128i*>(q.i0)));
  const __m128 j0 = _mm_cvtepi32_ps(_mm_load_si128(reinterpret_cast<const __m128i*>(q.j0)));
  const __m128 i1 = _mm_cvtepi32_ps(_mm_add_epi32(_mm_load_si128(reinterpret_cast<const __m128i*>(q.i0)), _mm_set1_epi32(1)));
  const __m128 j1 = _mm_cvtepi32_ps(_mm_add_epi32(_mm_load_si128(reinterpret_cast<const __m128i*>(q.j0)), _mm_set1_epi32(1)));
  const __m128 od1 = _mm_sub_ps(one, q.d1), od2 = _mm_sub_ps(one, q.d2);
  const __m128 offset_x = _mm_sub_ps(_mm_load_ps(frame[0]), p1x), offset_y = _mm_sub_ps(_mm_load_ps(frame[1]), p1y),
               offset_z = _mm_sub_ps(_mm_load_ps(frame[2]), p1z);
  // Memory order of a quad: (a0, b0), (a0, b0 + 1), (a0 + 1, b0), (a0 + 1, b0 + 1).
  const __m128 quad_w[4] = {q.dir_w[0], q.dir_w[3], q.dir_w[1], q.dir_w[2]};
  __m128 PWv[4], PT[4], PNX[4], PNY[4], PNZ[4];
  for (int c = 0; c < 4; ++c) {
    __m128 r0[4], r1[4];
    for (int k = 0; k < 4; ++k) {
      r0[k] = _mm_loadu_ps(reinterpret_cast<const float*>(q.corner[c][k]));
      r1[k] = _mm_loadu_ps(reinterpret_cast<const float*>(q.corner[c][k] + n));
    }
    _MM_TRANSPOSE4_PS(r0[0], r0[1], r0[2], r0[3]);  // t, code of (a0, b0), then of (a0, b0 + 1)
    _MM_TRANSPOSE4_PS(r1[0], r1[1], r1[2], r1[3]);  // the same for row a0 + 1
    const SampleLanes s00 = sample_lanes(r0[0], r0[1], quad_w[0]), s01 = sample_lanes(r0[2], r0[3], quad_w[1]);
    const SampleLanes s10 = sample_lanes(r1[0], r1[1], quad_w[2]), s11 = sample_lanes(r1[2], r1[3], quad_w[3]);
    const __m128 W = sum4(s00.w, s01.w, s10.w, s11.w);
    const __m128 Tsum = sum4(s00.t, s01.t, s10.t, s11.t);
    const __m128 NXu = sum4(s00.nx, s01.nx, s10.nx, s11.nx);
    const __m128 NYu = sum4(s00.ny, s01.ny, s10.ny, s11.ny);
    const __m128 NZu = sum4(s00.nz, s01.nz, s10.nz, s11.nz);
    // Corner c: (i0, j0), (i0 + 1, j0), (i0 + 1, j0 + 1), (i0, j0 + 1).
    const __m128 wi = (c == 0 || c == 3) ? od1 : q.d1, wj = c < 2 ? od2 : q.d2;
    const __m128 CI = (c == 0 || c == 3) ? i0 : i1, CJ = c < 2 ? j0 : j1;
    const __m128 PW = _mm_mul_ps(wi, wj);
    const __m128 valid = _mm_and_ps(_mm_cmpgt_ps(PW, zero), _mm_cmpge_ps(W, _mm_set1_ps(0.5f)));
    __m128 T = _mm_div_ps(Tsum, W);
    const __m128 sq = _mm_add_ps(_mm_add_ps(_mm_mul_ps(NXu, NXu), _mm_mul_ps(NYu, NYu)), _mm_mul_ps(NZu, NZu));
    const __m128 rn = _mm_and_ps(_mm_cmpgt_ps(sq, zero), _mm_div_ps(one, _mm_sqrt_ps(sq)));
    const __m128 DX = _mm_add_ps(offset_x, _mm_add_ps(_mm_mul_ps(CI, _mm_load_ps(frame[3])), _mm_mul_ps(CJ, _mm_load_ps(frame[6]))));
    const __m128 DY = _mm_add_ps(offset_y, _mm_add_ps(_mm_mul_ps(CI, _mm_load_ps(frame[4])), _mm_mul_ps(CJ, _mm_load_ps(frame[7]))));
    const __m128 DZ = _mm_add_ps(offset_z, _mm_add_ps(_mm_mul_ps(CI, _mm_load_ps(frame[5])), _mm_mul_ps(CJ, _mm_load_ps(frame[8]))));
    const __m128 LNu = _mm_add_ps(_mm_add_ps(_mm_mul_ps(NXu, q.lx), _mm_mul_ps(NYu, q.ly)), _mm_mul_ps(NZu, q.lz));
    const __m128 DNu = _mm_add_ps(_mm_add_ps(_mm_mul_ps(NXu, DX), _mm_mul_ps(NYu, DY)), _mm_mul_ps(NZu, DZ));
    const __m128 corrected = _mm_max_ps(zero, _mm_add_ps(T, _mm_mul_ps(_mm_set1_ps(0.5f), _mm_div_ps(DNu, LNu))));
    const __m128 steep = _mm_cmplt_ps(_mm_mul_ps(LNu, rn), _mm_set1_ps(-0.2f));
    T = select(steep, corrected, T);
    PWv[c] = _mm_and_ps(valid, PW);
    PT[c] = _mm_and_ps(valid, _mm_mul_ps(PW, T));
    PNX[c] = _mm_and_ps(valid, _mm_mul_ps(PW, _mm_mul_ps(NXu, rn)));
    PNY[c] = _mm_and_ps(valid, _mm_mul_ps(PW, _mm_mul_ps(NYu, rn)));
    PNZ[c] = _mm_and_ps(valid, _mm_mul_ps(PW, _mm_mul_ps(NZu, rn)));
  }
  // The positional blend: finish() sums corners as (c0 + c1) + (c2 + c3), and nz as
  // (c0 + c2) + (c1 + c3).
  const __m128 weight = sum4(PWv[0], PWv[1], PWv[2], PWv[3]);
  const __m128 nsx = sum4(PNX[0], PNX[1], PNX[2], PNX[3]), nsy = sum4(PNY[0], PNY[1], PNY[2], PNY[3]);
  const __m128 nsz = sum4(PNZ[0], PNZ[2], PNZ[1], PNZ[3]);
  // Step 6, as finish(): blended hit, t0, unit normal, contact test, depth, point, force.
  const __m128 nlen = _mm_sqrt_ps(_mm_add_ps(_mm_add_ps(_mm_mul_ps(nsx, nsx), _mm_mul_ps(nsy, nsy)), _mm_mul_ps(nsz, nsz)));
  const __m128 t0 = _mm_div_ps(sum4(PT[0], PT[1], PT[2], PT[3]), weight);
  const __m128 inv_nlen = _mm_div_ps(one, nlen);
  const __m128 nx = _mm_mul_ps(nsx, inv_nlen), ny = _mm_mul_ps(nsy, inv_nlen), nz = _mm_mul_ps(nsz, inv_nlen);
  __m128 contact = _mm_and_ps(_mm_cmpge_ps(weight, _mm_set1_ps(0.5f)), _mm_cmpgt_ps(nlen, zero));
  contact = _mm_and_ps(contact, _mm_cmpge_ps(_mm_add_ps(q.t_enter, t0), zero));
  contact = _mm_and_ps(contact, _mm_cmple_ps(t0, q.d));
  const __m128 ln = _mm_add_ps(_mm_add_ps(_mm_mul_ps(nx, q.lx), _mm_mul_ps(ny, q.ly)), _mm_mul_ps(nz, q.lz));
  contact = _mm_and_ps(contact, _mm_cmplt_ps(ln, zero));
  const int contacts = _mm_movemask_ps(contact) & q.located;
  const __m128 along = _mm_add_ps(q.t_enter, t0);
  const __m128 depth = _mm_sub_ps(q.d, t0);
  // apply_force_law: normal * ((k * depth) * metres_per_unit).
  const __m128 f = _mm_mul_ps(_mm_mul_ps(_mm_set1_ps(law.stiffness_n_per_m), depth), _mm_set1_ps(law.metres_per_unit));
  alignas(16) float v[10][4];
  _mm_store_ps(v[0], depth);
  _mm_store_ps(v[1], _mm_add_ps(q.sx, _mm_mul_ps(along, q.lx)));
  _mm_store_ps(v[2], _mm_add_ps(q.sy, _mm_mul_ps(along, q.ly)));
  _mm_store_ps(v[3], _mm_add_ps(q.sz, _mm_mul_ps(along, q.lz)));
  _mm_store_ps(v[4], nx), _mm_store_ps(v[5], ny), _mm_store_ps(v[6], nz);
  _mm_store_ps(v[7], _mm_mul_ps(nx, f)), _mm_store_ps(v[8], _mm_mul_ps(ny, f)), _mm_store_ps(v[9], _mm_mul_ps(nz, f));
  for (int k = 0; k < q.count; ++k) {
    Contact& c = out[k];
    if (!(contacts >> k & 1)) {
      c = Contact{};
      continue;
    }
    c.contact = true;
    c.depth = v[0][k];
    c.point = Vec3(v[1][k], v[2][k], v[3][k]);
    c.normal = Vec3(v[4][k], v[5][k], v[6][k]);
    c.force = Vec3(v[7][k], v[8][k], v[9][k]);
  }
}

HB_LANES_INLINE void HapticBox::run_lanes(const Segment* segments, std::size_t count, const ForceLaw& law,
                                          Contact* out) const noexcept {
  // Software pipeline: group g + kAhead is located (its fetches start) before group g is
  // blended, so each group's samples have kAhead groups' compute to arrive from DRAM.
  // Measured on the 832K armadillo (m=32 n=16, 200,000 random probes): one group ahead and
  // two are within noise (98-131 and 119-130 ns a query), three is slower (128-150 ns): the
  // lines of further groups only crowd the core's miss queue.
  constexpr std::size_t kAhead = 1;
  Lanes ring[kAhead + 1];
  const std::size_t groups = (count + 3) / 4;
  for (std::size_t g = 0; g < groups + kAhead; ++g) {
    if (g < groups) locate_lanes(segments + 4 * g, int(std::min<std::size_t>(4, count - 4 * g)), ring[g % (kAhead + 1)]);
    if (g >= kAhead) finish_lanes(ring[(g - kAhead) % (kAhead + 1)], law, out + 4 * (g - kAhead));
  }
}

// The same code compiled three times: for the SSE2 baseline; with AVX's three-operand (VEX)
// encoding, which spares the register copies of SSE's two-operand forms; and with AVX-512VL,
// whose 32 vector registers spare most spills (still 128-bit vectors). None of them fuses a
// multiply and an add (the file is built with -ffp-contract=off), so all three compute what
// query() computes, bit for bit.
__attribute__((target("avx"))) void HapticBox::run_lanes_avx(const Segment* segments, std::size_t count,
                                                              const ForceLaw& law, Contact* out) const noexcept {
  run_lanes(segments, count, law, out);
}
__attribute__((target("avx512f,avx512vl"))) void HapticBox::run_lanes_avx512(const Segment* segments, std::size_t count,
                                                                             const ForceLaw& law,
                                                                             Contact* out) const noexcept {
  run_lanes(segments, count, law, out);
}

namespace {
std::atomic<int> lane_isa_cap{int(LaneIsa::avx512)};
LaneIsa best_lane_isa() noexcept {
  static const LaneIsa best = __builtin_cpu_supports("avx512vl") ? LaneIsa::avx512
                              : __builtin_cpu_supports("avx")    ? LaneIsa::avx
                                                                 : LaneIsa::sse2;
  return best;
}
} // namespace

LaneIsa lane_isa() noexcept {
  return LaneIsa(std::min(int(best_lane_isa()), lane_isa_cap.load(std::memory_order_relaxed)));
}
const char* lane_isa_name(LaneIsa isa) noexcept {
  return isa == LaneIsa::avx512 ? "avx512" : isa == LaneIsa::avx ? "avx" : "sse2";
}
void set_lane_isa_cap(LaneIsa cap) noexcept { lane_isa_cap.store(int(cap), std::memory_order_relaxed); }

void HapticBox::query_many_lanes(const Segment* segments, std::size_t count, const ForceLaw& law,
                                 Contact* out) const noexcept {
  switch (lane_isa()) {
  case LaneIsa::avx512:
    return run_lanes_avx512(segments, count, law, out);
  case LaneIsa::avx:
    return run_lanes_avx(segments, count, law, out);
  default:
    return run_lanes(segments, count, law, out);
  }
}

} // namespace hb
