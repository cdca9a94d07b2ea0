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
//  6. Contact test (Figure 7): the surface point P1 + t0 l must lie between the handle and
//     the tip, on the outside of the surface (n . l < 0); depth = d - t0; F = k depth n.
//  7. The samples are read through a fetch policy (raw records, block or Haar codec): the
//     codec is switched on once per query and the query body is instantiated per codec.
//     Every codec keeps hit/miss exact, so step 5 sees the same silhouettes on a compressed
//     table as on the raw one; only t and the normals move, within the codec's bound.
#include "haptic_box/haptic_box.h"
#include "errors.h"
#include "geometry/octahedral.h"
#include <algorithm>
#include <cmath>
#include <emmintrin.h>  // SSE2: the x86-64 baseline

namespace hb {
namespace {

// Local axes of face f: the axis it is normal to, its two in-face axes, and its sign.
struct FaceAxes {
  int a, u, v;
  float sign;  // -1: face at -half[a], +1: at +half[a]
};
inline FaceAxes face_axes(int face) noexcept {
  const int a = face / 2;
  return {a, (a + 1) % 3, (a + 2) % 3, (face & 1) ? 1.f : -1.f};
}

// Directional coordinates of a direction (x, y, z) in a hemi-cube frame with z > 0 (into
// the box): sub-block, sub-block face, and continuous grid coordinates in [0, 1].
struct DirCoords {
  int sub, sface;
  float c1, c2;
};
inline DirCoords direction_coords(float x, float y, float z) noexcept {
  DirCoords d;
  d.sub = (x < 0.f ? 1 : 0) | (y < 0.f ? 2 : 0);
  const float X = std::fabs(x), Y = std::fabs(y), Z = std::max(z, 0.f);
  if (Z >= X && Z >= Y) {
    d.sface = 0;
    d.c1 = X / Z;
    d.c2 = Y / Z;
  } else if (X >= Y) {
    d.sface = 1;
    d.c1 = Y / X;
    d.c2 = Z / X;
  } else {
    d.sface = 2;
    d.c1 = X / Y;
    d.c2 = Z / Y;
  }
  return d;
}

// Blend of up to four (t, normal) values with miss handling (overview step 5).
struct Blend {
  float t = 0.f;
  Vec3 n{Vec3::Zero()};
  bool hit = false;
};

// Weighted sums over the 2 x 2 directional samples of one corner (SSE2, branch-free):
// a missed sample (t < 0) gets weight zero; octahedral normals are decoded un-normalised
// (the caller normalises the blend once).
struct CornerBlend {
  float weight, t, nx, ny, nz;
};
inline CornerBlend blend_corner(const Sample* base, std::size_t row, __m128 w) noexcept {
  static_assert(sizeof(Sample) == 8, "two samples per 16-byte load");
  const __m128 r0 = _mm_loadu_ps(reinterpret_cast<const float*>(base));        // t0 n0 t1 n1
  const __m128 r1 = _mm_loadu_ps(reinterpret_cast<const float*>(base + row));  // t2 n2 t3 n3
  const __m128 t = _mm_shuffle_ps(r0, r1, _MM_SHUFFLE(2, 0, 2, 0));
  const __m128i codes = _mm_castps_si128(_mm_shuffle_ps(r0, r1, _MM_SHUFFLE(3, 1, 3, 1)));
  w = _mm_and_ps(w, _mm_cmpge_ps(t, _mm_setzero_ps()));
  const __m128 scale = _mm_set1_ps(1.f / 32767.f);
  __m128 u = _mm_mul_ps(_mm_cvtepi32_ps(_mm_srai_epi32(_mm_slli_epi32(codes, 16), 16)), scale);
  __m128 v = _mm_mul_ps(_mm_cvtepi32_ps(_mm_srai_epi32(codes, 16)), scale);
  const __m128 sign = _mm_set1_ps(-0.f);
  const __m128 z = _mm_sub_ps(_mm_sub_ps(_mm_set1_ps(1.f), _mm_andnot_ps(sign, u)), _mm_andnot_ps(sign, v));
  const __m128 fold = _mm_max_ps(_mm_sub_ps(_mm_setzero_ps(), z), _mm_setzero_ps());
  u = _mm_sub_ps(u, _mm_or_ps(fold, _mm_and_ps(u, sign)));  // u - copysign(fold, u)
  v = _mm_sub_ps(v, _mm_or_ps(fold, _mm_and_ps(v, sign)));
  __m128 a = w, b = _mm_mul_ps(w, t), c = _mm_mul_ps(w, u), d = _mm_mul_ps(w, v);
  _MM_TRANSPOSE4_PS(a, b, c, d);
  float sums[4];
  _mm_storeu_ps(sums, _mm_add_ps(_mm_add_ps(a, b), _mm_add_ps(c, d)));
  __m128 wz = _mm_mul_ps(w, z);
  wz = _mm_add_ps(wz, _mm_movehl_ps(wz, wz));
  wz = _mm_add_ss(wz, _mm_shuffle_ps(wz, wz, 1));
  return {sums[0], sums[1], sums[2], sums[3], _mm_cvtss_f32(wz)};
}

inline void split_cell(float f, int cells, int& i0, float& w) noexcept {
  // f in [0, cells]; i0 in [0, cells - 1], w in [0, 1].
  f = std::min(std::max(f, 0.f), float(cells));
  i0 = std::min(int(f), cells - 1);
  w = f - float(i0);
}

// Directional interpolation at one corner through a policy's load(): missed samples are
// dropped, weights summed (the caller applies the miss rule and normalises).
template <class Fetch>
inline CornerBlend blend_by_load(const Fetch& fetch, const typename Fetch::Corner& corner, const float w[4]) noexcept {
  CornerBlend b{0.f, 0.f, 0.f, 0.f, 0.f};
  for (int k = 0; k < 4; ++k) {
    if (w[k] <= 0.f) continue;
    float ts;
    Vec3 ns;
    if (!fetch.load(corner, k, ts, ns)) continue;
    b.weight += w[k];
    b.t += w[k] * ts;
    b.nx += w[k] * ns.x();
    b.ny += w[k] * ns.y();
    b.nz += w[k] * ns.z();
  }
  return b;
}

// Sample fetch policies: begin() locates (and prefetches) the 2 x 2 directional quad at
// (a0, b0) of one corner's tile; load(k) reads its k-th sample in the order (0,0), (1,0),
// (1,1), (0,1), returning false for a miss; blend() is the corner's directional interpolation.
struct RawFetch {
  const Sample* table;
  std::size_t n, per_position;
  struct Corner {
    const Sample* base;
  };
  void begin(std::size_t position, std::size_t sf, int a0, int b0, Corner& c) const noexcept {
    c.base = table + position * per_position + sf * n * n + std::size_t(a0) * n + std::size_t(b0);
    __builtin_prefetch(c.base);
    __builtin_prefetch(c.base + n);
  }
  void resolve(Corner&) const noexcept {}
  bool load(const Corner& c, int k, float& t, Vec3& nrm) const noexcept {
    const std::size_t offset[4] = {0, n, n + 1, 1};
    const Sample& s = c.base[offset[k]];
    if (s.t < 0.f) return false;
    t = s.t;
    nrm = decode_octahedral32_unnormalized(s.normal);
    return true;
  }
  // Raw samples: the quad is two 16-byte loads, blended with SSE2 (weights reordered to the
  // memory order (0,0), (0,1), (1,0), (1,1)).
  CornerBlend blend(const Corner& c, const float w[4]) const noexcept {
    return blend_corner(c.base, n, _mm_setr_ps(w[0], w[3], w[1], w[2]));
  }
};

template <class View> struct CodecFetch {
  const View& view;
  struct Corner {
    std::size_t tile;
    int a0, b0;
  };
  void begin(std::size_t position, std::size_t sf, int a0, int b0, Corner& c) const noexcept {
    c = {position * 12u + sf, a0, b0};
    view.prefetch(c.tile, a0, b0);
  }
  void resolve(Corner&) const noexcept {}
  bool load(const Corner& c, int k, float& t, Vec3& nrm) const noexcept {
    float u, v;
    if (!view.fetch(c.tile, c.a0 + (k == 1 || k == 2), c.b0 + (k >= 2), t, u, v)) return false;
    nrm = oct_decode_unnormalized(u, v);
    return true;
  }
  CornerBlend blend(const Corner& c, const float w[4]) const noexcept { return blend_by_load(*this, c, w); }
};

// The block codec in two phases: begin() prefetches the index entries of the quad's blocks,
// resolve() (after all corners began) reads them and prefetches the records, so the two
// dependent loads of the four corners overlap instead of running in series.
template <> struct CodecFetch<BlockTable> {
  const BlockTable& view;
  struct Corner {
    std::size_t tile;
    int a0, b0;
    const std::uint8_t* rec[4];
  };
  void begin(std::size_t position, std::size_t sf, int a0, int b0, Corner& c) const noexcept {
    c.tile = position * 12u + sf;
    c.a0 = a0;
    c.b0 = b0;
    view.prefetch(c.tile, a0, b0);
    view.prefetch(c.tile, a0 + 1, b0 + 1);
  }
  void resolve(Corner& c) const noexcept {
    for (int k = 0; k < 4; ++k) {
      c.rec[k] = view.record(view.block_of(c.tile, c.a0 + (k == 1 || k == 2), c.b0 + (k >= 2)));
      __builtin_prefetch(c.rec[k]);
      __builtin_prefetch(c.rec[k] + 64);
    }
  }
  bool load(const Corner& c, int k, float& t, Vec3& nrm) const noexcept {
    float u, v;
    if (!view.fetch_from(c.rec[k], c.a0 + (k == 1 || k == 2), c.b0 + (k >= 2), t, u, v)) return false;
    nrm = oct_decode_unnormalized(u, v);
    return true;
  }
  CornerBlend blend(const Corner& c, const float w[4]) const noexcept { return blend_by_load(*this, c, w); }
};

} // namespace

HapticBox::HapticBox(const Obb& obb, const BoxParams& params, std::vector<Sample> table)
    : obb_(obb), params_(params) {
  if (params_.m < 2 || params_.n < 2)
    throw InvalidInput("HapticBox: m and n must be >= 2 (m=" + std::to_string(params_.m) +
                       ", n=" + std::to_string(params_.n) + ")");
  if (table.size() != params_.sample_count())
    throw InvalidInput("HapticBox: table has " + std::to_string(table.size()) +
                       " samples, expected " + std::to_string(params_.sample_count()));
  auto owned = std::make_shared<const std::vector<Sample>>(std::move(table));
  table_ = owned->data();
  owner_ = std::move(owned);
  samples_ = SampleTable(table_, params_);
  stats_.raw_bytes = stats_.bytes = raw_table_bytes();
  init_faces();
}

HapticBox::HapticBox(const Obb& obb, const BoxParams& params, const Sample* table,
                     std::shared_ptr<const void> owner)
    : obb_(obb), params_(params), table_(table), owner_(std::move(owner)) {
  if (params_.m < 2 || params_.n < 2) throw InvalidInput("HapticBox: m and n must be >= 2");
  if (!table_) throw InvalidInput("HapticBox: null table");
  samples_ = SampleTable(table_, params_);
  stats_.raw_bytes = stats_.bytes = raw_table_bytes();
  init_faces();
}

HapticBox::HapticBox(const Obb& obb, const BoxParams& params, CompressedTable table)
    : obb_(obb), params_(params), stats_(table.stats) {
  if (params_.m < 2 || params_.n < 2) throw InvalidInput("HapticBox: m and n must be >= 2");
  auto owned = std::make_shared<const std::vector<std::uint8_t>>(std::move(table.payload));
  samples_ = SampleTable(table.codec, owned->data(), owned->size(), params_);
  owner_ = std::move(owned);
  init_faces();
}

HapticBox::HapticBox(const Obb& obb, const BoxParams& params, CodecId codec, const std::uint8_t* payload,
                     std::size_t bytes, std::shared_ptr<const void> owner, const CodecStats& stats)
    : obb_(obb), params_(params), stats_(stats), owner_(std::move(owner)) {
  if (params_.m < 2 || params_.n < 2) throw InvalidInput("HapticBox: m and n must be >= 2");
  samples_ = SampleTable(codec, payload, bytes, params_);
  stats_.bytes = bytes;
  stats_.raw_bytes = raw_table_bytes();
  init_faces();
}

HapticBox HapticBox::compressed(const CodecOptions& options) const {
  if (!table_) throw InvalidInput("HapticBox: the table is already compressed");
  return HapticBox(obb_, params_, compress_table(table_, params_, obb_.diagonal(), options));
}

void HapticBox::init_faces() noexcept {
  const float step = 2.f / float(params_.m - 1);
  for (int face = 0; face < 6; ++face) {
    const FaceAxes fa = face_axes(face);
    Vec3 local;
    local[fa.a] = fa.sign * obb_.half[fa.a];
    local[fa.u] = -obb_.half[fa.u];
    local[fa.v] = -obb_.half[fa.v];
    faces_[face].origin = obb_.to_world(local);
    faces_[face].step_i = obb_.axes.col(fa.u) * (obb_.half[fa.u] * step);
    faces_[face].step_j = obb_.axes.col(fa.v) * (obb_.half[fa.v] * step);
  }
}

Vec3 HapticBox::sample_direction(int face, int sub, int sface, int a, int b) const noexcept {
  const FaceAxes fa = face_axes(face);
  const float c1 = float(a) / float(params_.n - 1), c2 = float(b) / float(params_.n - 1);
  float X, Y, Z;
  if (sface == 0) {
    X = c1; Y = c2; Z = 1.f;
  } else if (sface == 1) {
    X = 1.f; Y = c1; Z = c2;
  } else {
    X = c1; Y = 1.f; Z = c2;
  }
  const float x = (sub & 1) ? -X : X;
  const float y = (sub & 2) ? -Y : Y;
  Vec3 local;
  local[fa.u] = x;
  local[fa.v] = y;
  local[fa.a] = -fa.sign * Z;  // into the box
  return (obb_.axes * local).normalized();
}

bool HapticBox::query_into(const Segment& segment, const ForceLaw& law, Contact& out,
                           float& distance_from_handle) const noexcept {
  switch (samples_.codec()) {
  case CodecId::block:
    return query_with(CodecFetch<BlockTable>{samples_.block()}, segment, law, out, distance_from_handle);
  case CodecId::haar:
    return query_with(CodecFetch<HaarTable>{samples_.haar()}, segment, law, out, distance_from_handle);
  default:
    return query_with(RawFetch{table_, std::size_t(params_.n), params_.samples_per_position()}, segment, law, out,
                      distance_from_handle);
  }
}

template <class Fetch>
bool HapticBox::query_with(const Fetch& fetch, const Segment& segment, const ForceLaw& law, Contact& out,
                           float& distance_from_handle) const noexcept {
  out = Contact{};
  const Vec3 delta = segment.end - segment.start;
  const float length = delta.norm();
  if (!(length > 0.f) || !std::isfinite(length)) return false;
  const Vec3 l = delta / length;

  // 1. Entry into the PBB.
  LineBoxHit box_hit;
  if (!intersect_line_obb(obb_, segment.start, l, box_hit)) return false;
  if (box_hit.t_enter > length || box_hit.t_exit < 0.f) return false;
  const Vec3 p1 = segment.start + box_hit.t_enter * l;
  const float d = length - box_hit.t_enter;

  // 2. Cell and positional weights.
  const FaceAxes fa = face_axes(box_hit.enter_face);
  const Vec3 p1_local = obb_.to_local(p1);
  const Vec3 l_local = obb_.axes.transpose() * l;
  const int cells_m = params_.m - 1;
  int i0, j0;
  float d1, d2;
  split_cell((p1_local[fa.u] / obb_.half[fa.u] + 1.f) * 0.5f * float(cells_m), cells_m, i0, d1);
  split_cell((p1_local[fa.v] / obb_.half[fa.v] + 1.f) * 0.5f * float(cells_m), cells_m, j0, d2);

  // 3. Directional cell, once for all corners.
  const DirCoords dc = direction_coords(l_local[fa.u], l_local[fa.v], -fa.sign * l_local[fa.a]);
  const int cells_n = params_.n - 1;
  int a0, b0;
  float wa, wb;
  split_cell(dc.c1 * float(cells_n), cells_n, a0, wa);
  split_cell(dc.c2 * float(cells_n), cells_n, b0, wb);
  const std::size_t sf = std::size_t(dc.sub) * 3u + std::size_t(dc.sface);
  const float dir_w[4] = {(1.f - wa) * (1.f - wb), wa * (1.f - wb), wa * wb, (1.f - wa) * wb};

  // 4. Corners (P2..P5 of eq. 1) and their weights.
  const int ci[4] = {i0, i0 + 1, i0 + 1, i0};
  const int cj[4] = {j0, j0, j0 + 1, j0 + 1};
  const float pos_w[4] = {(1.f - d1) * (1.f - d2), d1 * (1.f - d2), d1 * d2, (1.f - d1) * d2};
  const std::size_t face_base = std::size_t(box_hit.enter_face) * std::size_t(params_.m) * std::size_t(params_.m);

  // The four corners' hemi-cubes lie far apart in memory: start all their loads before
  // using any (memory-level parallelism instead of four serial misses).
  typename Fetch::Corner corners[4];
  for (int c = 0; c < 4; ++c)
    fetch.begin(face_base + std::size_t(ci[c]) * std::size_t(params_.m) + std::size_t(cj[c]), sf, a0, b0, corners[c]);
  for (int c = 0; c < 4; ++c) fetch.resolve(corners[c]);

  Blend corner_sum;
  float corner_hit_weight = 0.f;
  for (int c = 0; c < 4; ++c) {
    if (pos_w[c] <= 0.f) continue;
    // Directional interpolation at this corner.
    const CornerBlend blend = fetch.blend(corners[c], dir_w);
    const float w_hit = blend.weight;
    float t = blend.t;
    Vec3 nrm(blend.nx, blend.ny, blend.nz);
    if (w_hit < 0.5f) continue;  // this corner sees a miss along l
    t /= w_hit;
    nrm.normalize();
    // Half of the tangent-plane correction from the corner to P1.
    const Vec3 corner = position_point(box_hit.enter_face, ci[c], cj[c]);
    const float ln = l.dot(nrm);
    if (ln < -0.2f) {
      const float correction = (corner - p1).dot(nrm) / ln;
      t = std::max(0.f, t + 0.5f * correction);
    }
    corner_hit_weight += pos_w[c];
    corner_sum.t += pos_w[c] * t;
    corner_sum.n += pos_w[c] * nrm;
  }
  if (corner_hit_weight < 0.5f) return false;
  const float t0 = corner_sum.t / corner_hit_weight;
  const float nlen = corner_sum.n.norm();
  if (!(nlen > 0.f)) return false;
  const Vec3 normal = corner_sum.n / nlen;

  // 6. Contact test.
  const float along = box_hit.t_enter + t0;  // handle to surface point
  if (along < 0.f || t0 > d || normal.dot(l) >= 0.f) return false;
  out.contact = true;
  out.depth = d - t0;
  out.point = segment.start + along * l;
  out.normal = normal;
  apply_force_law(out, law);
  distance_from_handle = along;
  return true;
}

Contact HapticBox::query(const Segment& segment, const ForceLaw& law) const noexcept {
  Contact c;
  float along = 0.f;
  query_into(segment, law, c, along);
  return c;
}

} // namespace hb
