#include "haptic_box/surface_triangles.h"
#include "errors.h"
#include "geometry/octahedral.h"
#include <algorithm>
#include <cmath>
#include <limits>
#include <tuple>

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
  std::sort(keyed.begin(), keyed.end());
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
  // from triangle soup still joins its faces, so a walk can cross the crease (issue 11: the
  // refinement of a crisp groove could not, and its contacts were lost).
  std::vector<std::uint32_t> weld(mesh.positions.size());
  {
    std::vector<std::uint32_t> order(mesh.positions.size());
    for (std::uint32_t v = 0; v < order.size(); ++v) order[v] = v;
    const auto key = [&](std::uint32_t v) {
      const Vec3& p = mesh.positions[v];
      return std::make_tuple(p.x(), p.y(), p.z(), v);
    };
    std::sort(order.begin(), order.end(), [&](std::uint32_t a, std::uint32_t b) { return key(a) < key(b); });
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
  std::sort(uses.begin(), uses.end(), [](const EdgeUse& x, const EdgeUse& y) {
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

bool SurfaceTriangles::finish(const Record& r, const float d[3], float u, float v, float s, float s_min, float& s_out,
                              Vec3& normal, bool& front) noexcept {
  if (!(s >= s_min)) return false;
  // Geometric normal e1 x e2 (outward for a consistently oriented mesh).
  const Vec3 g(r.e1[1] * r.e2[2] - r.e1[2] * r.e2[1], r.e1[2] * r.e2[0] - r.e1[0] * r.e2[2],
               r.e1[0] * r.e2[1] - r.e1[1] * r.e2[0]);
  Vec3 shaded = (1.f - u - v) * decode_octahedral32(r.normal[0]) + u * decode_octahedral32(r.normal[1]) +
                v * decode_octahedral32(r.normal[2]);
  if (shaded.dot(g) < 0.f || shaded.squaredNorm() < 1e-12f) shaded = g;
  const float len = shaded.norm();
  if (!(len > 0.f)) return false;
  s_out = s;
  normal = shaded / len;
  front = g.x() * d[0] + g.y() * d[1] + g.z() * d[2] < 0.f;
  return true;
}

bool SurfaceTriangles::intersect(std::uint32_t id, const float o[3], const float d[3], float s_min, float& s,
                                 Vec3& normal, bool& front, float* outside) const noexcept {
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
  return finish(r, d, u, v, hit, s_min, s, normal, front);
}

bool SurfaceTriangles::walk(std::uint32_t start, const float o[3], const float d[3], float s_min, int max_steps,
                            float& s, Vec3& normal, bool& front, std::uint32_t* crossed) const noexcept {
  std::uint32_t id = start, previous = kNoTriangle;
  for (int step = 0; step <= max_steps; ++step) {
    if (id >= count_) return false;
    const Record& r = records_[id];
    for (std::uint32_t next : r.neighbour) prefetch(next);  // the next step's record is one of these
    float u, v, hit;
    if (!plane_hit(r, o, d, u, v, hit)) return false;
    const float w[3] = {1.f - u - v, u, v};
    int worst = 0;
    for (int k = 1; k < 3; ++k)
      if (w[k] < w[worst]) worst = k;
    if (w[worst] >= 0.f) {
      if (crossed) *crossed = id;
      return finish(r, d, u, v, hit, s_min, s, normal, front);
    }
    const std::uint32_t next = r.neighbour[worst];
    if (next == kNoTriangle || next == previous) return false;
    previous = id;
    id = next;
  }
  return false;
}

} // namespace hb
