#include "surface/surface_triangles.h"
#include "errors.h"
#include "geometry/octahedral.h"
#include "prefetch.h"
#include <tbb/parallel_sort.h>
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <limits>
#include <tuple>
#include <emmintrin.h>  // SSE2: the x86-64 baseline
#include <xmmintrin.h>

namespace hb {

SurfaceTriangles::SurfaceTriangles(const TriangleMesh& mesh) {
  if (mesh.normals.size() != mesh.positions.size())
    throw InvalidInput("SurfaceTriangles: mesh has no vertex normals (call compute_vertex_normals)");
  if (mesh.triangle_count() == 0) throw InvalidInput("SurfaceTriangles: mesh has no triangles");
  const std::size_t count = mesh.triangle_count();
  // Slots in Morton order of the triangle centroids: neighbours on the surface are close in
  // memory, so the candidates of one query and the steps of a walk share cache lines and pages
  // (whatever order the mesh file lists its triangles in).
  const Bounds bounds = mesh.bounds();
  const Vec3 extent = (bounds.max - bounds.min).cwiseMax(Vec3::Constant(1e-30f));
  const auto spread = [](std::uint32_t v) {  // 10 bits to every third of 30
    std::uint32_t x = v & 0x3ffu;
    x = (x | (x << 16)) & 0x030000ffu;
    x = (x | (x << 8)) & 0x0300f00fu;
    x = (x | (x << 4)) & 0x030c30c3u;
    x = (x | (x << 2)) & 0x09249249u;
    return x;
  };
  std::vector<std::pair<std::uint32_t, std::uint32_t>> keyed(count);
  for (std::uint32_t t = 0; t < count; ++t) {
    const Triangle& tri = mesh.triangles[t];
    const Vec3 c = (mesh.positions[tri[0]] + mesh.positions[tri[1]] + mesh.positions[tri[2]]) / 3.f;
    const Vec3 q = ((c - bounds.min).cwiseQuotient(extent) * 1023.f).cwiseMax(Vec3::Zero()).cwiseMin(Vec3::Constant(1023.f));
    keyed[t] = {spread(std::uint32_t(q.x())) | (spread(std::uint32_t(q.y())) << 1) | (spread(std::uint32_t(q.z())) << 2), t};
  }
  tbb::parallel_sort(keyed.begin(), keyed.end());  // keys unique (the triangle breaks ties): the order std::sort gives
  slot_of_.resize(count);
  for (std::uint32_t s = 0; s < count; ++s) slot_of_[keyed[s].second] = s;

  auto owned = std::make_shared<std::vector<Record>>(count);
  std::vector<Record>& records = *owned;
  for (std::size_t t = 0; t < count; ++t) {
    const Triangle& tri = mesh.triangles[t];
    const Vec3& a = mesh.positions[tri[0]];
    const Vec3 e1 = mesh.positions[tri[1]] - a, e2 = mesh.positions[tri[2]] - a;
    Record& r = records[slot_of_[t]];
    for (int k = 0; k < 3; ++k) {
      r.a[k] = a[k];
      r.e1[k] = e1[k];
      r.e2[k] = e2[k];
      r.normal[k] = encode_octahedral32(mesh.normals[tri[k]]);
      r.neighbour[k] = kNoTriangle;
    }
    r.pad = 0;
  }
  // Neighbour across the edge opposite vertex k: the first triangle (in mesh order) holding
  // both of the edge's end points. End points are compared by position, not by vertex index:
  // a flat-shaded crease (each face its own vertices, for its own normals) or a mesh read
  // from triangle soup still joins its faces, so a walk can cross the crease (unwelded, the
  // refinement of a crisp groove could not, and its contacts were lost).
  std::vector<std::uint32_t> weld(mesh.positions.size());
  {
    std::vector<std::uint32_t> order(mesh.positions.size());
    for (std::uint32_t v = 0; v < order.size(); ++v) order[v] = v;
    const auto key = [&](std::uint32_t v) {
      const Vec3& p = mesh.positions[v];
      return std::make_tuple(p.x(), p.y(), p.z(), v);
    };
    tbb::parallel_sort(order.begin(), order.end(), [&](std::uint32_t a, std::uint32_t b) { return key(a) < key(b); });
    for (std::size_t i = 0; i < order.size(); ++i)
      weld[order[i]] = i > 0 && mesh.positions[order[i]] == mesh.positions[order[i - 1]] ? weld[order[i - 1]] : order[i];
  }
  struct EdgeUse {
    std::uint64_t edge;
    std::uint32_t triangle;
    int k;
  };
  std::vector<EdgeUse> uses;
  uses.reserve(3 * count);
  for (std::uint32_t t = 0; t < count; ++t) {
    const Triangle& tri = mesh.triangles[t];
    for (int k = 0; k < 3; ++k) {
      const std::uint32_t a = weld[tri[(k + 1) % 3]], b = weld[tri[(k + 2) % 3]];
      if (a == b) continue;  // a degenerate edge joins nothing
      uses.push_back({(std::uint64_t(std::min(a, b)) << 32) | std::max(a, b), t, k});
    }
  }
  tbb::parallel_sort(uses.begin(), uses.end(), [](const EdgeUse& x, const EdgeUse& y) {
    return x.edge != y.edge ? x.edge < y.edge : x.triangle < y.triangle;
  });
  for (std::size_t i = 0; i < uses.size();) {
    std::size_t j = i;
    while (j < uses.size() && uses[j].edge == uses[i].edge) ++j;
    for (std::size_t a = i; a < j; ++a)
      for (std::size_t b = i; b < j; ++b)
        if (uses[b].triangle != uses[a].triangle) {
          records[slot_of_[uses[a].triangle]].neighbour[uses[a].k] = slot_of_[uses[b].triangle];
          break;
        }
    i = j;
  }
  records_ = records.data();
  count_ = records.size();
  owner_ = std::move(owned);
}

TriangleIds pack_triangle_ids(const std::vector<std::uint32_t>& ids, std::shared_ptr<const void>& owner) {
  std::uint32_t lo = kNoTriangle, hi = 0;
  for (std::uint32_t id : ids)
    if (id != kNoTriangle) {
      lo = std::min(lo, id);
      hi = std::max(hi, id);
    }
  TriangleIds out;
  if (lo == kNoTriangle) lo = hi = 0;
  if (hi - lo < 0xffffu) {
    auto narrow = std::make_shared<std::vector<std::uint16_t>>(ids.size());
    for (std::size_t k = 0; k < ids.size(); ++k)
      (*narrow)[k] = ids[k] == kNoTriangle ? std::uint16_t(0xffffu) : std::uint16_t(ids[k] - lo);
    out = {narrow->data(), 2, lo};
    owner = std::move(narrow);
  } else {
    auto wide = std::make_shared<std::vector<std::uint32_t>>(ids);
    out = {wide->data(), 4, 0};
    owner = std::move(wide);
  }
  return out;
}

SurfaceTriangles::SurfaceTriangles(const Record* records, std::size_t count, std::shared_ptr<const void> owner)
    : records_(records), count_(count), owner_(std::move(owner)) {
  if (!records_ || count_ == 0) throw InvalidInput("SurfaceTriangles: no triangles");
}

bool SurfaceTriangles::plane_hit(const Record& r, const float o[3], const float d[3], float& u, float& v,
                                 float& s) noexcept {
  // Moller-Trumbore: p = d x e2, det = e1 . p.
  const float px = d[1] * r.e2[2] - d[2] * r.e2[1];
  const float py = d[2] * r.e2[0] - d[0] * r.e2[2];
  const float pz = d[0] * r.e2[1] - d[1] * r.e2[0];
  const float det = r.e1[0] * px + r.e1[1] * py + r.e1[2] * pz;
  if (!(std::fabs(det) > 1e-20f)) return false;
  const float inv = 1.f / det;
  const float tx = o[0] - r.a[0], ty = o[1] - r.a[1], tz = o[2] - r.a[2];
  u = (tx * px + ty * py + tz * pz) * inv;
  const float qx = ty * r.e1[2] - tz * r.e1[1];
  const float qy = tz * r.e1[0] - tx * r.e1[2];
  const float qz = tx * r.e1[1] - ty * r.e1[0];
  v = (d[0] * qx + d[1] * qy + d[2] * qz) * inv;
  s = (r.e2[0] * qx + r.e2[1] * qy + r.e2[2] * qz) * inv;
  return std::isfinite(u) && std::isfinite(v) && std::isfinite(s);
}

static_assert(offsetof(SurfaceTriangles::Record, a) == 0 && offsetof(SurfaceTriangles::Record, e1) == 12 &&
                  offsetof(SurfaceTriangles::Record, e2) == 24 && offsetof(SurfaceTriangles::Record, normal) == 36,
              "plane_hits reads a record's first 12 floats as one array");

unsigned SurfaceTriangles::plane_hits(const std::uint32_t* ids, int count, const float o[3], const float d[3],
                                      float* u_out, float* v_out, float* s_out) const noexcept {
  unsigned ok = 0;
  const __m128 d0 = _mm_set1_ps(d[0]), d1 = _mm_set1_ps(d[1]), d2 = _mm_set1_ps(d[2]);
  const __m128 o0 = _mm_set1_ps(o[0]), o1 = _mm_set1_ps(o[1]), o2 = _mm_set1_ps(o[2]);
  const __m128 abs_mask = _mm_castsi128_ps(_mm_set1_epi32(0x7fffffff));
  const __m128 inf = _mm_set1_ps(std::numeric_limits<float>::infinity());
  for (int first = 0; first < count; first += 4) {
    // Four records (lanes beyond count or out of range read record 0 and are masked off;
    // unaligned loads: a mapped file need not place the records on 16 bytes),
    // transposed to a, e1, e2 per axis: each record's first 12 floats are a, e1, e2[0..2].
    const Record* r[4];
    unsigned in_range = 0;
    for (int k = 0; k < 4; ++k) {
      const bool valid = first + k < count && ids[first + k] < count_;
      r[k] = records_ + (valid ? ids[first + k] : 0u);
      in_range |= valid ? 1u << k : 0u;
    }
    // The first 12 floats of a record as one array (a, e1, e2 are laid out back to back: the
    // static_asserts below), so a load of floats 4-7 or 8-11 does not index past `a`.
    const float* f[4];
    for (int k = 0; k < 4; ++k) f[k] = reinterpret_cast<const float*>(r[k]);
    __m128 ax = _mm_loadu_ps(f[0]), ay = _mm_loadu_ps(f[1]), az = _mm_loadu_ps(f[2]), e1x = _mm_loadu_ps(f[3]);
    _MM_TRANSPOSE4_PS(ax, ay, az, e1x);  // ax = a.x of the 4 records, ay = a.y, az = a.z, e1x
    __m128 e1y = _mm_loadu_ps(f[0] + 4), e1z = _mm_loadu_ps(f[1] + 4), e2x = _mm_loadu_ps(f[2] + 4),
           e2y = _mm_loadu_ps(f[3] + 4);
    _MM_TRANSPOSE4_PS(e1y, e1z, e2x, e2y);
    __m128 e2z = _mm_loadu_ps(f[0] + 8), x1 = _mm_loadu_ps(f[1] + 8), x2 = _mm_loadu_ps(f[2] + 8),
           x3 = _mm_loadu_ps(f[3] + 8);
    _MM_TRANSPOSE4_PS(e2z, x1, x2, x3);
    // plane_hit(), lane by lane.
    const __m128 px = _mm_sub_ps(_mm_mul_ps(d1, e2z), _mm_mul_ps(d2, e2y));
    const __m128 py = _mm_sub_ps(_mm_mul_ps(d2, e2x), _mm_mul_ps(d0, e2z));
    const __m128 pz = _mm_sub_ps(_mm_mul_ps(d0, e2y), _mm_mul_ps(d1, e2x));
    const __m128 det = _mm_add_ps(_mm_add_ps(_mm_mul_ps(e1x, px), _mm_mul_ps(e1y, py)), _mm_mul_ps(e1z, pz));
    const __m128 big = _mm_cmpgt_ps(_mm_and_ps(det, abs_mask), _mm_set1_ps(1e-20f));
    const __m128 inv = _mm_div_ps(_mm_set1_ps(1.f), det);
    const __m128 tx = _mm_sub_ps(o0, ax), ty = _mm_sub_ps(o1, ay), tz = _mm_sub_ps(o2, az);
    const __m128 u =
        _mm_mul_ps(_mm_add_ps(_mm_add_ps(_mm_mul_ps(tx, px), _mm_mul_ps(ty, py)), _mm_mul_ps(tz, pz)), inv);
    const __m128 qx = _mm_sub_ps(_mm_mul_ps(ty, e1z), _mm_mul_ps(tz, e1y));
    const __m128 qy = _mm_sub_ps(_mm_mul_ps(tz, e1x), _mm_mul_ps(tx, e1z));
    const __m128 qz = _mm_sub_ps(_mm_mul_ps(tx, e1y), _mm_mul_ps(ty, e1x));
    const __m128 v =
        _mm_mul_ps(_mm_add_ps(_mm_add_ps(_mm_mul_ps(d0, qx), _mm_mul_ps(d1, qy)), _mm_mul_ps(d2, qz)), inv);
    const __m128 sv =
        _mm_mul_ps(_mm_add_ps(_mm_add_ps(_mm_mul_ps(e2x, qx), _mm_mul_ps(e2y, qy)), _mm_mul_ps(e2z, qz)), inv);
    // Finite: |x| < infinity (false for NaN and both infinities).
    const __m128 finite = _mm_and_ps(_mm_and_ps(_mm_cmplt_ps(_mm_and_ps(u, abs_mask), inf),
                                                _mm_cmplt_ps(_mm_and_ps(v, abs_mask), inf)),
                                     _mm_cmplt_ps(_mm_and_ps(sv, abs_mask), inf));
    const unsigned lanes = unsigned(_mm_movemask_ps(_mm_and_ps(big, finite))) & in_range;
    alignas(16) float ub[4], vb[4], sb[4];
    _mm_store_ps(ub, u);
    _mm_store_ps(vb, v);
    _mm_store_ps(sb, sv);
    for (int k = 0; k < 4 && first + k < count; ++k) {
      u_out[first + k] = ub[k], v_out[first + k] = vb[k], s_out[first + k] = sb[k];
    }
    ok |= lanes << first;
  }
  return ok;
}

void SurfaceTriangles::set_normal_map(int side, const std::uint32_t* map, std::shared_ptr<const void> owner) {
  if (side < 1 || side > kMaxMapSide)
    throw InvalidInput("SurfaceTriangles: normal map side " + std::to_string(side) + " outside [1, " +
                       std::to_string(kMaxMapSide) + "]");
  if (!map) throw InvalidInput("SurfaceTriangles: no normal map");
  map_ = map;
  map_side_ = side;
  map_owner_ = std::move(owner);
}

void SurfaceTriangles::set_normal_map(int side, const std::vector<std::uint32_t>& by_triangle) {
  if (side < 1 || side > kMaxMapSide)
    throw InvalidInput("SurfaceTriangles: normal map side " + std::to_string(side) + " outside [1, " +
                       std::to_string(kMaxMapSide) + "]");
  const std::size_t per = lattice_points(side);
  if (slot_of_.size() != count_ || by_triangle.size() != count_ * per)
    throw InvalidInput("SurfaceTriangles: a normal map of " + std::to_string(by_triangle.size()) + " codes for " +
                       std::to_string(count_) + " triangles at side " + std::to_string(side) +
                       (slot_of_.size() != count_ ? " (the surface was not built from a mesh)" : ""));
  auto map = std::make_shared<std::vector<std::uint32_t>>(by_triangle.size());
  for (std::size_t t = 0; t < count_; ++t)
    std::copy_n(by_triangle.data() + t * per, per, map->data() + std::size_t(slot_of_[t]) * per);
  set_normal_map(side, map->data(), map);
}

namespace {
// The three corner normals interpolated (a surface without a normal map).
inline Vec3 corner_shading(const SurfaceTriangles::Record& r, float u, float v) noexcept {
  return (1.f - u - v) * decode_octahedral32(r.normal[0]) + u * decode_octahedral32(r.normal[1]) +
         v * decode_octahedral32(r.normal[2]);
}
} // namespace

Vec3 SurfaceTriangles::shading_at(std::uint32_t id, float u, float v) const noexcept {
  return map_ ? lattice_shading(id, u, v) : corner_shading(records_[id], u, v);
}

Vec3 SurfaceTriangles::lattice_shading(std::uint32_t id, float u, float v, LatticeCache* cache) const noexcept {
  const int k = map_side_;
  const std::uint32_t* p = map_ + std::size_t(id) * lattice_points(k);
  int i, j;
  float fu, fv;
  lattice_cell(k, u, v, i, j, fu, fv);
  const auto at = [&](int a, int b) { return decode_octahedral32(p[lattice_index(k, a, b)]); };
  const bool lower = fu + fv <= 1.f || i + j == k - 1;
  // The cell's three corners in the blend's order, decoded here or kept from the last call in
  // this cell (`cache`: the same bits).
  Vec3 decoded[3];
  const Vec3* n = decoded;
  if (cache && cache->map == map_ && cache->id == id && cache->i == i && cache->j == j && cache->upper == !lower) {
    n = cache->n;
  } else {
    if (lower)
      decoded[0] = at(i, j), decoded[1] = at(i + 1, j), decoded[2] = at(i, j + 1);
    else
      decoded[0] = at(i + 1, j + 1), decoded[1] = at(i + 1, j), decoded[2] = at(i, j + 1);
    if (cache) *cache = LatticeCache{map_, id, i, j, !lower, {decoded[0], decoded[1], decoded[2]}};
  }
  if (lower) return (1.f - fu - fv) * n[0] + fu * n[1] + fv * n[2];
  return (fu + fv - 1.f) * n[0] + (1.f - fv) * n[1] + (1.f - fu) * n[2];
}

bool SurfaceTriangles::finish(const Record& r, const float d[3], float u, float v, float s, float s_min, float& s_out,
                              Vec3& normal, bool& front, LatticeCache* cache) const noexcept {
  if (!(s >= s_min)) return false;
  // Geometric normal e1 x e2 (outward for a consistently oriented mesh).
  const Vec3 g(r.e1[1] * r.e2[2] - r.e1[2] * r.e2[1], r.e1[2] * r.e2[0] - r.e1[0] * r.e2[2],
               r.e1[0] * r.e2[1] - r.e1[1] * r.e2[0]);
  // The corner normals inline: the map's lattice is the rarer case, out of line.
  Vec3 shaded = map_ ? lattice_shading(std::uint32_t(&r - records_), u, v, cache) : corner_shading(r, u, v);
  if (shaded.dot(g) < 0.f || shaded.squaredNorm() < 1e-12f) shaded = g;
  float len = shaded.norm();
  if (!(len > 0.f)) return false;
  if (!(len <= std::numeric_limits<float>::max())) {
    // Edges so long that |g|^2 overflows (only a damaged or absurd file has them: the norm
    // would be infinite and the normal zero): scale g down first.
    shaded /= shaded.cwiseAbs().maxCoeff();
    len = shaded.norm();
    if (!(len > 0.f && len <= std::numeric_limits<float>::max())) return false;
  }
  s_out = s;
  normal = shaded / len;
  front = g.x() * d[0] + g.y() * d[1] + g.z() * d[2] < 0.f;
  return true;
}

Vec3 SurfaceTriangles::face_normal(std::uint32_t id) const noexcept {
  if (id >= count_) return Vec3::Zero();
  const Record& r = records_[id];
  const Vec3 g = Vec3(r.e1[0], r.e1[1], r.e1[2]).cross(Vec3(r.e2[0], r.e2[1], r.e2[2]));
  const float len = g.norm();
  return len > 0.f && len <= std::numeric_limits<float>::max() ? Vec3(g / len) : Vec3(Vec3::Zero());
}

bool SurfaceTriangles::intersect(std::uint32_t id, const float o[3], const float d[3], float s_min, float& s,
                                 Vec3& normal, bool& front, LatticeCache& cache) const noexcept {
  return intersect_with(id, o, d, s_min, s, normal, front, nullptr, &cache);
}

bool SurfaceTriangles::intersect(std::uint32_t id, const float o[3], const float d[3], float s_min, float& s,
                                 Vec3& normal, bool& front, float* outside) const noexcept {
  return intersect_with(id, o, d, s_min, s, normal, front, outside, nullptr);
}

bool SurfaceTriangles::intersect_with(std::uint32_t id, const float o[3], const float d[3], float s_min, float& s,
                                      Vec3& normal, bool& front, float* outside, LatticeCache* cache) const noexcept {
  if (outside) *outside = std::numeric_limits<float>::infinity();
  if (id >= count_) return false;
  const Record& r = records_[id];
  float u, v, hit;
  if (!plane_hit(r, o, d, u, v, hit)) return false;
  const float w = std::min(std::min(u, v), 1.f - u - v);
  if (w < 0.f) {
    if (outside) *outside = -w;
    return false;
  }
  if (outside) *outside = 0.f;
  return finish(r, d, u, v, hit, s_min, s, normal, front, cache);
}

bool SurfaceTriangles::first_crossing(const std::uint32_t* ids, std::size_t count, const float o[3], const float d[3],
                                      float s_min, float s_max, float& s_out, bool& front,
                                      std::uint32_t& id_out) const noexcept {
  // plane_hits()' lanes with the inside and range tests kept in the registers too: the
  // candidates come out as a 4-bit mask, so the scalar loop only sees real crossings (most
  // lanes of a cell miss) and no u, v, s round trip through memory. The same float
  // operations in the same order as plane_hits() and the scalar tests it replaces (all
  // values finite there, so min(min(u, v), 1 - u - v) >= 0 is the three comparisons), and
  // candidates are taken in list order with a strict `<`: the same crossing, bit for bit.
  float best = std::numeric_limits<float>::infinity(), best_u = 0.f, best_v = 0.f;
  std::uint32_t best_id = kNoTriangle;
  const __m128 d0 = _mm_set1_ps(d[0]), d1 = _mm_set1_ps(d[1]), d2 = _mm_set1_ps(d[2]);
  const __m128 o0 = _mm_set1_ps(o[0]), o1 = _mm_set1_ps(o[1]), o2 = _mm_set1_ps(o[2]);
  const __m128 abs_mask = _mm_castsi128_ps(_mm_set1_epi32(0x7fffffff));
  const __m128 inf = _mm_set1_ps(std::numeric_limits<float>::infinity());
  const __m128 zero = _mm_setzero_ps(), one = _mm_set1_ps(1.f), tiny = _mm_set1_ps(1e-20f);
  const __m128 lo = _mm_set1_ps(s_min), hi = _mm_set1_ps(s_max);
  for (std::size_t first = 0; first < count; first += 4) {
    const Record* r[4];
    unsigned in_range = 0;
    for (int k = 0; k < 4; ++k) {
      const bool valid = first + std::size_t(k) < count && ids[first + std::size_t(k)] < count_;
      r[k] = records_ + (valid ? ids[first + std::size_t(k)] : 0u);
      in_range |= valid ? 1u << k : 0u;
    }
    if (first + 4 < count)
      for (int k = 4; k < 8 && first + std::size_t(k) < count; ++k)
        if (ids[first + std::size_t(k)] < count_) hb::prefetch(records_ + ids[first + std::size_t(k)]);
    const float* f[4];
    for (int k = 0; k < 4; ++k) f[k] = reinterpret_cast<const float*>(r[k]);
    __m128 ax = _mm_loadu_ps(f[0]), ay = _mm_loadu_ps(f[1]), az = _mm_loadu_ps(f[2]), e1x = _mm_loadu_ps(f[3]);
    _MM_TRANSPOSE4_PS(ax, ay, az, e1x);
    __m128 e1y = _mm_loadu_ps(f[0] + 4), e1z = _mm_loadu_ps(f[1] + 4), e2x = _mm_loadu_ps(f[2] + 4),
           e2y = _mm_loadu_ps(f[3] + 4);
    _MM_TRANSPOSE4_PS(e1y, e1z, e2x, e2y);
    __m128 e2z = _mm_loadu_ps(f[0] + 8), x1 = _mm_loadu_ps(f[1] + 8), x2 = _mm_loadu_ps(f[2] + 8),
           x3 = _mm_loadu_ps(f[3] + 8);
    _MM_TRANSPOSE4_PS(e2z, x1, x2, x3);
    const __m128 px = _mm_sub_ps(_mm_mul_ps(d1, e2z), _mm_mul_ps(d2, e2y));
    const __m128 py = _mm_sub_ps(_mm_mul_ps(d2, e2x), _mm_mul_ps(d0, e2z));
    const __m128 pz = _mm_sub_ps(_mm_mul_ps(d0, e2y), _mm_mul_ps(d1, e2x));
    const __m128 det = _mm_add_ps(_mm_add_ps(_mm_mul_ps(e1x, px), _mm_mul_ps(e1y, py)), _mm_mul_ps(e1z, pz));
    const __m128 big = _mm_cmpgt_ps(_mm_and_ps(det, abs_mask), tiny);
    const __m128 inv = _mm_div_ps(one, det);
    const __m128 tx = _mm_sub_ps(o0, ax), ty = _mm_sub_ps(o1, ay), tz = _mm_sub_ps(o2, az);
    const __m128 u =
        _mm_mul_ps(_mm_add_ps(_mm_add_ps(_mm_mul_ps(tx, px), _mm_mul_ps(ty, py)), _mm_mul_ps(tz, pz)), inv);
    const __m128 qx = _mm_sub_ps(_mm_mul_ps(ty, e1z), _mm_mul_ps(tz, e1y));
    const __m128 qy = _mm_sub_ps(_mm_mul_ps(tz, e1x), _mm_mul_ps(tx, e1z));
    const __m128 qz = _mm_sub_ps(_mm_mul_ps(tx, e1y), _mm_mul_ps(ty, e1x));
    const __m128 v =
        _mm_mul_ps(_mm_add_ps(_mm_add_ps(_mm_mul_ps(d0, qx), _mm_mul_ps(d1, qy)), _mm_mul_ps(d2, qz)), inv);
    const __m128 sv =
        _mm_mul_ps(_mm_add_ps(_mm_add_ps(_mm_mul_ps(e2x, qx), _mm_mul_ps(e2y, qy)), _mm_mul_ps(e2z, qz)), inv);
    const __m128 finite = _mm_and_ps(_mm_and_ps(_mm_cmplt_ps(_mm_and_ps(u, abs_mask), inf),
                                                _mm_cmplt_ps(_mm_and_ps(v, abs_mask), inf)),
                                     _mm_cmplt_ps(_mm_and_ps(sv, abs_mask), inf));
    const __m128 w = _mm_sub_ps(_mm_sub_ps(one, u), v);
    const __m128 inside =
        _mm_and_ps(_mm_and_ps(_mm_cmpge_ps(u, zero), _mm_cmpge_ps(v, zero)), _mm_cmpge_ps(w, zero));
    const __m128 in_s = _mm_and_ps(_mm_cmpge_ps(sv, lo), _mm_cmple_ps(sv, hi));
    unsigned lanes =
        unsigned(_mm_movemask_ps(_mm_and_ps(_mm_and_ps(big, finite), _mm_and_ps(inside, in_s)))) & in_range;
    if (!lanes) continue;
    alignas(16) float sb[4], ub[4], vb[4];
    _mm_store_ps(sb, sv);
    _mm_store_ps(ub, u);
    _mm_store_ps(vb, v);
    for (; lanes; lanes &= lanes - 1) {
      const int k = __builtin_ctz(lanes);
      if (!(sb[k] < best)) continue;
      best = sb[k];
      best_u = ub[k];
      best_v = vb[k];
      best_id = ids[first + std::size_t(k)];
    }
  }
  if (best_id == kNoTriangle) return false;
  prefetch_shading(best_id, best_u, best_v);  // the map, when there is one
  const Record& r = records_[best_id];  // in range: in_range masks the others off
  const float gx = r.e1[1] * r.e2[2] - r.e1[2] * r.e2[1], gy = r.e1[2] * r.e2[0] - r.e1[0] * r.e2[2],
              gz = r.e1[0] * r.e2[1] - r.e1[1] * r.e2[0];
  front = gx * d[0] + gy * d[1] + gz * d[2] < 0.f;
  s_out = best;
  id_out = best_id;
  return true;
}

namespace {
// The memo's slot of `id`: where it is, or the free slot it would take; -1 when full.
int memo_slot(const SurfaceTriangles::WalkMemo& m, std::uint32_t id) noexcept {
  constexpr int kSlots = SurfaceTriangles::WalkMemo::kSlots;
  int h = int((id * 0x9E3779B1u) >> 24) & (kSlots - 1);
  for (int probe = 0; probe < kSlots; ++probe, h = (h + 1) & (kSlots - 1))
    if (m.id[h] == id || m.id[h] == kNoTriangle) return h;
  return -1;
}
} // namespace

bool SurfaceTriangles::walk(std::uint32_t start, const float o[3], const float d[3], float s_min, int max_steps,
                            float& s, Vec3& normal, bool& front, std::uint32_t* crossed, WalkMemo* memo) const noexcept {
  constexpr int kMaxMemoPath = 32;
  if (memo && max_steps >= kMaxMemoPath) memo = nullptr;
  std::uint32_t path[kMaxMemoPath];
  int path_len = 0;
  bool settled = false, result = false;
  std::uint32_t id = start, previous = kNoTriangle;
  for (int step = 0; step <= max_steps; ++step) {
    if (memo) {
      // An earlier walk of this line went on from here with at least this budget, or to an
      // end no budget changes: the same edges, the same end, nothing new.
      const int slot = memo_slot(*memo, id);
      if (slot >= 0 && memo->id[slot] == id &&
          (memo->left[slot] == WalkMemo::kSettled || int(memo->left[slot]) >= max_steps - step))
        return false;
      path[path_len++] = id;
    }
    if (id >= count_) {
      settled = true;
      break;
    }
    const Record& r = records_[id];
    for (std::uint32_t next : r.neighbour) prefetch(next);  // the next step's record is one of these
    float u, v, hit;
    if (!plane_hit(r, o, d, u, v, hit)) {
      settled = true;
      break;
    }
    const float w[3] = {1.f - u - v, u, v};
    int worst = 0;
    for (int k = 1; k < 3; ++k)
      if (w[k] < w[worst]) worst = k;
    if (w[worst] >= 0.f) {
      if (crossed) *crossed = id;
      result = finish(r, d, u, v, hit, s_min, s, normal, front);
      settled = true;
      break;
    }
    const std::uint32_t next = r.neighbour[worst];
    if (next == kNoTriangle || next == previous) {
      settled = true;
      break;
    }
    previous = id;
    id = next;
  }
  if (memo)
    for (int k = 0; k < path_len; ++k) {
      const int slot = memo_slot(*memo, path[k]);
      if (slot < 0) break;
      if (memo->id[slot] == kNoTriangle) ++memo->used;
      memo->id[slot] = path[k];
      memo->left[slot] = settled ? WalkMemo::kSettled : std::uint8_t(max_steps - k);
    }
  return result;
}

} // namespace hb
