#pragma once
// The box query's sample blending (haptic_box.cpp, overview steps 4, 5 and 8), internal to
// haptic_box.cpp: a corner's 2 x 2 directional quad blended with the miss rule, the raw
// records' SSE2 lanes, and one fetch policy per codec (RawFetch, CodecFetch<View>): begin()
// locates and prefetches a corner's quad, resolve() runs a codec's dependent fetch, blend4()
// blends the four corners. Everything is inline: it is the query's inner loop.
#include "codec/sample_table.h"
#include "geometry/octahedral.h"
#include "box/box_layout.h"
#include "box/decoded_quads.h"
#include "prefetch.h"
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <emmintrin.h>  // SSE2: the x86-64 baseline

namespace hb {
namespace box_query {


// Blend of up to four (t, normal) values with miss handling (overview step 5).
struct Blend {
  float t = 0.f;
  Vec3 n{Vec3::Zero()};
  bool hit = false;
};

// The 2 x 2 directional samples of one corner's quad (SSE2, branch-free, memory order):
// per sample the weight (zero for a miss, t < 0), and the weighted t and octahedral normal
// decoded un-normalised (the caller normalises the blend once). Kept per lane so that the
// raw path can sum four corners at once.
struct CornerLanes {
  __m128 w, t, nx, ny, nz;
};
// Weights w (zero for a miss), t and octahedral u, v per lane: the weighted t and the normal
// decoded un-normalised (oct_decode_unnormalized, side by side).
inline CornerLanes weighted_lanes(__m128 w, __m128 t, __m128 u, __m128 v) noexcept {
  const __m128 sign = _mm_set1_ps(-0.f);
  const __m128 z = _mm_sub_ps(_mm_sub_ps(_mm_set1_ps(1.f), _mm_andnot_ps(sign, u)), _mm_andnot_ps(sign, v));
  const __m128 fold = _mm_max_ps(_mm_sub_ps(_mm_setzero_ps(), z), _mm_setzero_ps());
  u = _mm_sub_ps(u, _mm_or_ps(fold, _mm_and_ps(u, sign)));
  v = _mm_sub_ps(v, _mm_or_ps(fold, _mm_and_ps(v, sign)));
  return {w, _mm_mul_ps(w, t), _mm_mul_ps(w, u), _mm_mul_ps(w, v), _mm_mul_ps(w, z)};
}
inline CornerLanes corner_lanes(const Sample* base, std::size_t row, __m128 w) noexcept {
  const __m128 r0 = _mm_loadu_ps(reinterpret_cast<const float*>(base));
  const __m128 r1 = _mm_loadu_ps(reinterpret_cast<const float*>(base + row));
  const __m128 t = _mm_shuffle_ps(r0, r1, _MM_SHUFFLE(2, 0, 2, 0));
  const __m128i codes = _mm_castps_si128(_mm_shuffle_ps(r0, r1, _MM_SHUFFLE(3, 1, 3, 1)));
  w = _mm_and_ps(w, _mm_cmpge_ps(t, _mm_setzero_ps()));
  const __m128 scale = _mm_set1_ps(1.f / 32767.f);
  const __m128 u = _mm_mul_ps(_mm_cvtepi32_ps(_mm_srai_epi32(_mm_slli_epi32(codes, 16), 16)), scale);
  const __m128 v = _mm_mul_ps(_mm_cvtepi32_ps(_mm_srai_epi32(codes, 16)), scale);
  return weighted_lanes(w, t, u, v);
}

// Lane c of the result: the sum of the four lanes of x_c.
inline __m128 lane_sums(__m128 x0, __m128 x1, __m128 x2, __m128 x3) noexcept {
  _MM_TRANSPOSE4_PS(x0, x1, x2, x3);
  return _mm_add_ps(_mm_add_ps(x0, x1), _mm_add_ps(x2, x3));
}

// The weighted sums over one corner's quad.
struct CornerBlend {
  float weight, t, nx, ny, nz;
};

// The four corners' blends side by side (lane c: corner c), through any policy's blend().
struct Corners4 {
  __m128 w, t, nx, ny, nz;
};
template <class Fetch>
inline Corners4 blend_each(const Fetch& fetch, const typename Fetch::Corner* corners, const float w[4]) noexcept {
  alignas(16) float cw[4], ct[4], cnx[4], cny[4], cnz[4];
  for (int c = 0; c < 4; ++c) {
    const CornerBlend b = fetch.blend(corners[c], w);
    cw[c] = b.weight, ct[c] = b.t, cnx[c] = b.nx, cny[c] = b.ny, cnz[c] = b.nz;
  }
  return {_mm_load_ps(cw), _mm_load_ps(ct), _mm_load_ps(cnx), _mm_load_ps(cny), _mm_load_ps(cnz)};
}

inline void split_cell(float f, int cells, int& i0, float& w) noexcept {
  // f in [0, cells] (NaN: 0); i0 in [0, cells - 1], w in [0, 1].
  // f >= 0 ? f : 0 is std::max(f, 0.f) for every number (-0 kept) and maps NaN to 0, so no
  // input, finite or not, makes an index outside the grid (query_lanes_kernel.inc: the same).
  f = std::min(f >= 0.f ? f : 0.f, float(cells));
  i0 = std::min(int(f), cells - 1);
  w = f - float(i0);
}

// Directional interpolation at one corner over its decoded quad (hit mask and values in the
// quad order, as a codec's fetch_quad gives them): missed samples and zero weights are
// dropped, weights summed (the caller applies the miss rule and normalises). Samples are
// added in k order 0..3 by add_sample(), so every codec's sums follow the same float ops.
inline void add_sample(CornerBlend& b, float w, float t, const Vec3& n) noexcept {
  b.weight += w;
  b.t += w * t;
  b.nx += w * n.x();
  b.ny += w * n.y();
  b.nz += w * n.z();
}
inline CornerBlend blend_quad(unsigned hits, const float t[4], const float u[4], const float v[4],
                              const float w[4]) noexcept {
  CornerBlend b{0.f, 0.f, 0.f, 0.f, 0.f};
  for (int k = 0; k < 4; ++k) {
    if (w[k] <= 0.f || !((hits >> k) & 1u)) continue;
    add_sample(b, w[k], t[k], oct_decode_unnormalized(u[k], v[k]));
  }
  return b;
}

// Sample fetch policies: begin() locates (and prefetches) the 2 x 2 directional quad at
// (a0, b0) of one corner's tile, resolve() runs a codec's second, dependent fetch, and
// blend4() blends the four corners' quads (directional interpolation, samples in the order
// (0,0), (1,0), (1,1), (0,1) of the directional weights).
struct RawFetch {
  const Sample* table;
  const BoxLayout& layout;
  std::size_t n;
  RawFetch(const Sample* table, const BoxLayout& layout)
      : table(table), layout(layout), n(std::size_t(layout.params().n)) {}
  struct Corner {
    const Sample* base;
  };
  void begin(std::size_t position, std::size_t sf, int a0, int b0, Corner& c) const noexcept {
    c.base = table + layout.first_sample(position, sf, a0, b0);
    hb::prefetch(c.base);
    hb::prefetch(c.base + n);
  }
  void resolve(Corner&) const noexcept {}
  void resolve_all(Corner*) const noexcept {}
  // No probe memory (DecodedQuads) on this path.
  SettledQuadric* settled() const noexcept { return nullptr; }
  // A corner's quad, sample k in the directional weights' order (0,0), (1,0), (1,1), (0,1):
  // t and octahedral u, v (a miss: t < 0). Returns the hit mask.
  unsigned quad(const Corner& c, float t[4], float u[4], float v[4]) const noexcept {
    const Sample* s[4] = {c.base, c.base + n, c.base + n + 1, c.base + 1};
    unsigned hits = 0;
    for (int k = 0; k < 4; ++k) {
      t[k] = s[k]->t;
      oct_coordinates(s[k]->normal, u[k], v[k]);
      hits |= t[k] >= 0.f ? 1u << k : 0u;
    }
    return hits;
  }
  // Raw samples: each quad is two 16-byte loads, blended with SSE2 (weights reordered to the
  // memory order (0,0), (0,1), (1,0), (1,1)); per-sample lanes for all four corners, then
  // one transpose per quantity sums them.
  Corners4 blend4(const Corner* c, const float w[4]) const noexcept {
    const __m128 wv = _mm_setr_ps(w[0], w[3], w[1], w[2]);
    const CornerLanes a = corner_lanes(c[0].base, n, wv), b = corner_lanes(c[1].base, n, wv);
    const CornerLanes e = corner_lanes(c[2].base, n, wv), f = corner_lanes(c[3].base, n, wv);
    return {lane_sums(a.w, b.w, e.w, f.w), lane_sums(a.t, b.t, e.t, f.t), lane_sums(a.nx, b.nx, e.nx, f.nx),
            lane_sums(a.ny, b.ny, e.ny, f.ny), lane_sums(a.nz, b.nz, e.nz, f.nz)};
  }
};

// Sample fetch for a codec's view (RawFetch's interface), one specialisation per codec.
template <class View> struct CodecFetch;

// The Haar codec: a corner's quad in one fetch_quad() (header, shared coarse coefficients
// and bitmap ranks read once, not per sample), blended by blend_quad().
template <> struct CodecFetch<HaarTable> {
  const HaarTable& view;
  struct Corner {
    std::size_t tile;
    int a0, b0;
  };
  void begin(std::size_t position, std::size_t sf, int a0, int b0, Corner& c) const noexcept {
    c = {BoxLayout::tile_index(position, sf), a0, b0};
    view.prefetch(c.tile, a0, b0);
  }
  void resolve(Corner&) const noexcept {}
  void resolve_all(Corner*) const noexcept {}
  SettledQuadric* settled() const noexcept { return nullptr; }
  unsigned quad(const Corner& c, float t[4], float u[4], float v[4]) const noexcept {
    return view.fetch_quad(c.tile, c.a0, c.b0, t, u, v);
  }
  CornerBlend blend(const Corner& c, const float w[4]) const noexcept {
    float t[4], u[4], v[4];
    const unsigned hits = view.fetch_quad(c.tile, c.a0, c.b0, t, u, v);
    return blend_quad(hits, t, u, v, w);
  }
  Corners4 blend4(const Corner* c, const float w[4]) const noexcept { return blend_each(*this, c, w); }
};

// The block codec in two phases: begin() prefetches the index entries of the quad's blocks,
// resolve() (after all corners began) reads them and prefetches the records, so the two
// dependent loads of the four corners overlap instead of running in series.
template <> struct CodecFetch<BlockTable> {
  const BlockTable& view;
  /// A probe's last decoded quads (nullptr: none kept): a query in the same cells of the same
  /// table skips resolve() and the decode, and blends the kept lanes (the same bits).
  DecodedQuads* cache = nullptr;
  struct Corner {
    std::size_t tile;
    int a0, b0;
    const std::uint8_t* rec[4];
  };
  void begin(std::size_t position, std::size_t sf, int a0, int b0, Corner& c) const noexcept {
    c.tile = BoxLayout::tile_index(position, sf);
    c.a0 = a0;
    c.b0 = b0;
    view.prefetch(c.tile, a0, b0);
    view.prefetch(c.tile, a0 + 1, b0 + 1);
  }
  void resolve(Corner& c) const noexcept {
    view.quad_records(c.tile, c.a0, c.b0, c.rec);
    // A quad within one block (49 in 64) has one record: its lines are loaded once.
    const int n = (c.rec[1] == c.rec[0] && c.rec[3] == c.rec[0]) ? 1 : 4;
    for (int k = 0; k < n; ++k) {
      hb::prefetch(c.rec[k]);
      hb::prefetch(c.rec[k] + 64);
    }
  }
  /// The probe's last settled quadric when it is this table's (else a blank one the settle
  /// fills), nullptr without a probe memory.
  SettledQuadric* settled() const noexcept {
    if (!cache) return nullptr;
    if (cache->settled.table != view.identity()) cache->settled = SettledQuadric{view.identity(), false, {}, 0};
    return &cache->settled;
  }
  bool cached(const Corner* c) const noexcept {
    return cache && cache->table == view.identity() && cache->a0 == c[0].a0 && cache->b0 == c[0].b0 &&
           cache->tiles[0] == c[0].tile && cache->tiles[1] == c[1].tile && cache->tiles[2] == c[2].tile &&
           cache->tiles[3] == c[3].tile;
  }
  void resolve_all(Corner* c) const noexcept {
    if (cached(c)) return;
    for (int k = 0; k < 4; ++k) resolve(c[k]);
  }
  // After resolve(c).
  unsigned quad(const Corner& c, float t[4], float u[4], float v[4]) const noexcept {
    return view.fetch_quad_from(c.rec, c.a0, c.b0, t, u, v);
  }
  // Each quad in one quad_lanes() (each block's header read once), its samples weighted and
  // decoded side by side as the raw records are (weighted_lanes), the four corners summed by
  // one transpose: measured along strokes (bumpy sphere, m32 n16, one core), 184 ns a query
  // with a scalar blend per sample (blend_quad), 148 ns so (exact: 130).
  static CornerLanes lanes(__m128 w, __m128 hit, __m128 t, __m128 u, __m128 v) noexcept {
    return weighted_lanes(_mm_and_ps(w, hit), _mm_and_ps(hit, t), _mm_and_ps(hit, u), _mm_and_ps(hit, v));
  }
  Corners4 blend4(const Corner* c, const float w[4]) const noexcept {
    const __m128 wv = _mm_loadu_ps(w);  // the quad's order is the weights' order
    __m128 t[4], u[4], v[4], hit[4];
    if (cached(c)) {
      ++cache->reused;
      for (int k = 0; k < 4; ++k) {
        t[k] = _mm_load_ps(cache->t[k]), u[k] = _mm_load_ps(cache->u[k]);
        v[k] = _mm_load_ps(cache->v[k]), hit[k] = _mm_load_ps(cache->hit[k]);
      }
    } else {
      for (int k = 0; k < 4; ++k) hit[k] = view.quad_lanes(c[k].rec, c[k].a0, c[k].b0, t[k], u[k], v[k]);
      if (cache) {
        cache->table = view.identity(), cache->a0 = c[0].a0, cache->b0 = c[0].b0;
        for (int k = 0; k < 4; ++k) {
          cache->tiles[k] = c[k].tile;
          _mm_store_ps(cache->t[k], t[k]), _mm_store_ps(cache->u[k], u[k]);
          _mm_store_ps(cache->v[k], v[k]), _mm_store_ps(cache->hit[k], hit[k]);
        }
      }
    }
    const CornerLanes a = lanes(wv, hit[0], t[0], u[0], v[0]), b = lanes(wv, hit[1], t[1], u[1], v[1]);
    const CornerLanes e = lanes(wv, hit[2], t[2], u[2], v[2]), f = lanes(wv, hit[3], t[3], u[3], v[3]);
    return {lane_sums(a.w, b.w, e.w, f.w), lane_sums(a.t, b.t, e.t, f.t), lane_sums(a.nx, b.nx, e.nx, f.nx),
            lane_sums(a.ny, b.ny, e.ny, f.ny), lane_sums(a.nz, b.nz, e.nz, f.nz)};
  }
};


} // namespace box_query
} // namespace hb
