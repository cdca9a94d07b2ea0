// What a tool with volume asks of a scene: its broad phase (within_reach) and its points'
// segments from one handle (query_star).
// query_star on the cells route: the answers of query() segment by segment, without a walk.
//  1. A handle in an inside cell: no segment is a contact.
//  2. The triangles listed in the surface cells within the segments' reach of the handle: a
//     segment crosses a triangle only at a point of such a cell, which lists it.
//  3. The tips' directions from the handle in the cells of a cube map.
//  4. Each triangle, seen from the handle, is the spherical triangle of its vertices'
//     directions; it pairs with the tips inside its three edge planes, looked for in the cube
//     map's cells under the box of its projected vertices (a central projection keeps great
//     circles straight, so on one face that box holds it), or among all tips when it spans
//     faces.
//  5. Each tip with triangles: the nearest crossing among them (SurfaceTriangles::
//     first_crossing, the walk's own test), shaded as the walk's (crossing_contact). Every
//     triangle the segment crosses is among them, so the crossing is the walk's (a tie between
//     two triangles at one point may name the other). A tip with none crosses nothing.
// A handle on a vertex or too many cells in reach take query_many() for every segment.
#include "scene/box_scene.h"
#include <algorithm>
#include <cmath>

namespace hb {
namespace {

constexpr std::size_t kMaxCellsInReach = 1 << 15;
constexpr int kFace = 16;  // cube-map cells along a face's edge

// The cube-map face of unit u (0..5: +x -x +y -y +z -z) and its coordinates on it, in [-1, 1]
// (u's other two components over its largest, a central projection onto the face).
int cube_face(const Vec3& u, float& a, float& b) noexcept {
  const float x = std::fabs(u.x()), y = std::fabs(u.y()), z = std::fabs(u.z());
  if (x >= y && x >= z) {
    a = u.y() / x;
    b = u.z() / x;
    return u.x() >= 0.f ? 0 : 1;
  }
  if (y >= z) {
    a = u.x() / y;
    b = u.z() / y;
    return u.y() >= 0.f ? 2 : 3;
  }
  a = u.x() / z;
  b = u.y() / z;
  return u.z() >= 0.f ? 4 : 5;
}

int face_cell(float a) noexcept { return std::min(kFace - 1, std::max(0, int((a + 1.f) * (0.5f * kFace)))); }


// 2. The triangles of the surface cells within `reach` of `start` (a cell box in reach) into
// scratch.ids, each once.
enum class Gathered { none, some, too_many };
Gathered gather_triangles(const SceneGrid& grid, const SurfaceCells& cells_in, const Vec3& start, float reach,
                          StarScratch& scratch) {
  const SurfaceCells& cells = cells_in;
  const float cell = grid.cell();
  const Vec3& origin = grid.origin();
  const auto& dims = grid.dims();
  int lo[3], hi[3];
  std::size_t cell_count = 1;
  for (int k = 0; k < 3; ++k) {
    const float a = std::floor((start[k] - reach - origin[k]) / cell), b = std::floor((start[k] + reach - origin[k]) / cell);
    lo[k] = int(std::max(0.f, std::min(a, float(dims[k]))));
    hi[k] = int(std::max(-1.f, std::min(b, float(dims[k] - 1))));
    if (hi[k] < lo[k]) return Gathered::none;  // no cell of the grid (which covers the surface) in reach
    cell_count *= std::size_t(hi[k] - lo[k] + 1);
  }
  if (cell_count > kMaxCellsInReach) return Gathered::too_many;
  std::vector<std::uint32_t>& ids = scratch.ids;
  ids.clear();
  // Each triangle once (a triangle is listed in every cell it meets): stamped with this call.
  const SurfaceTriangles& surface = cells.surface();
  std::vector<std::uint32_t>& stamps = scratch.stamps;
  if (stamps.size() != surface.size()) stamps.assign(surface.size(), 0);
  if (++scratch.call == 0) {
    std::fill(stamps.begin(), stamps.end(), 0);
    scratch.call = 1;
  }
  const std::uint32_t call = scratch.call;
  for (int z = lo[2]; z <= hi[2]; ++z)
    for (int y = lo[1]; y <= hi[1]; ++y)
      for (int x = lo[0]; x <= hi[0]; ++x) {
        const std::uint32_t index = cells.index(x, y, z);
        if (index == SurfaceCells::kNone) continue;
        const Vec3 box_lo = origin + cell * Vec3(float(x), float(y), float(z));
        const Vec3 gap = (box_lo - start).cwiseMax(start - box_lo - Vec3::Constant(cell)).cwiseMax(Vec3::Zero());
        if (gap.norm() > reach) continue;
        for (const std::uint32_t* t = cells.begin(index); t != cells.end(index); ++t)
          if (*t < stamps.size() && stamps[*t] != call) {
            stamps[*t] = call;
            ids.push_back(*t);
          }
      }
  return ids.empty() ? Gathered::none : Gathered::some;
}

// 3. The tips' directions from `start` (scratch.directions) in the cells of a cube map: the
// tips of cube-map cell c are scratch.order[buckets[c], buckets[c + 1]).
void bucket_tips(const Vec3& start, const Vec3* tips, std::size_t count, StarScratch& scratch) {
  std::vector<float>& directions = scratch.directions;
  directions.resize(3 * count);
  std::vector<std::uint32_t>& buckets = scratch.buckets;
  buckets.assign(6 * kFace * kFace + 1, 0);
  std::vector<std::uint32_t>& order = scratch.order;
  order.resize(count);
  std::vector<std::uint32_t>& cell_of_tip = scratch.triangles;  // reused below for the pairs
  cell_of_tip.resize(count);
  for (std::size_t i = 0; i < count; ++i) {
    const Vec3 d = tips[i] - start;
    const float n = d.norm();
    const Vec3 u = n > 0.f ? Vec3(d / n) : Vec3(0.f, 0.f, 1.f);
    for (int k = 0; k < 3; ++k) directions[3 * i + std::size_t(k)] = u[k];
    float fa, fb;
    const int face = cube_face(u, fa, fb);
    cell_of_tip[i] = std::uint32_t((face * kFace + face_cell(fb)) * kFace + face_cell(fa));
    ++buckets[cell_of_tip[i] + 1];
  }
  for (std::size_t b = 1; b < buckets.size(); ++b) buckets[b] += buckets[b - 1];
  std::vector<std::uint32_t>& placed = scratch.counts;  // counting sort: how many placed a cell
  placed.assign(6 * kFace * kFace, 0);
  for (std::size_t i = 0; i < count; ++i) order[buckets[cell_of_tip[i]] + placed[cell_of_tip[i]]++] = std::uint32_t(i);
}

// 4. Each triangle of scratch.ids pairs with the tips whose direction it covers (scratch.pairs:
// tip << 32 | triangle): seen from the handle it is the spherical triangle of its vertices'
// directions (inside its three edge planes). On one face of the cube map (a central projection,
// which keeps great circles straight) it lies in the box of its projected vertices; a triangle
// wider than 35 degrees across faces is tested against every tip. False: the handle is on a
// vertex (no directions).
bool pair_triangles(const SurfaceTriangles& surface, const Vec3& start, float reach, std::size_t count,
                    StarScratch& scratch) {
  const std::vector<std::uint32_t>& ids = scratch.ids;
  const std::vector<std::uint32_t>& buckets = scratch.buckets;
  const std::vector<std::uint32_t>& order = scratch.order;
  const SurfaceTriangles::Record* records = surface.records();
  std::vector<std::uint64_t>& pairs = scratch.pairs;
  pairs.clear();
  const float* dir = scratch.directions.data();
  for (std::uint32_t id : ids) {
    const SurfaceTriangles::Record& r = records[id];
    const Vec3 a(r.a[0], r.a[1], r.a[2]);
    const Vec3 v[3] = {a - start, a + Vec3(r.e1[0], r.e1[1], r.e1[2]) - start, a + Vec3(r.e2[0], r.e2[1], r.e2[2]) - start};
    Vec3 u[3];
    for (int k = 0; k < 3; ++k) {
      const float n = v[k].norm();
      if (!(n > 1e-6f * reach)) return false;  // the handle on a vertex
      u[k] = v[k] / n;
    }
    // The edge planes, oriented inward; a triangle seen edge-on (or the handle in its plane)
    // bounds nothing by them.
    Vec3 e[3] = {u[0].cross(u[1]), u[1].cross(u[2]), u[2].cross(u[0])};
    const float side = e[0].dot(u[2]);
    const bool flat = !(std::fabs(side) > 1e-7f);
    if (side < 0.f)
      for (Vec3& p : e) p = -p;
    const auto covers = [&](std::uint32_t i) {
      const float* d = dir + 3 * std::size_t(i);
      if (flat) return true;
      for (const Vec3& p : e)
        if (p.x() * d[0] + p.y() * d[1] + p.z() * d[2] < -1e-6f) return false;
      return true;
    };
    // On each face whose plane all three vertices are in front of, the box of their
    // projections (cut to the face) holds the part of the triangle in that face's cone. A face
    // some vertex is behind holds none of it unless the triangle spans more than 35 degrees (the
    // cone is within 55 of its axis): then every tip is tested.
    const float spread = std::min({u[0].dot(u[1]), u[1].dot(u[2]), u[2].dot(u[0])});
    bool wide = false;
    for (int face = 0; face < 6 && !wide; ++face) {
      const int axis = face / 2;
      const float sign = face % 2 ? -1.f : 1.f;
      const int ia = axis == 0 ? 1 : 0, ib = axis == 2 ? 1 : 2;
      float lo_a = 1e30f, hi_a = -1e30f, lo_b = 1e30f, hi_b = -1e30f;
      int in_front = 0;
      for (const Vec3& w : u) {
        const float main = sign * w[axis];
        if (!(main > 1e-3f)) continue;
        ++in_front;
        lo_a = std::min(lo_a, w[ia] / main);
        hi_a = std::max(hi_a, w[ia] / main);
        lo_b = std::min(lo_b, w[ib] / main);
        hi_b = std::max(hi_b, w[ib] / main);
      }
      if (in_front < 3) {
        wide = in_front > 0 && spread < 0.819f;  // cos 35 degrees
        continue;
      }
      if (lo_a > 1.f || hi_a < -1.f || lo_b > 1.f || hi_b < -1.f) continue;
      const int a0 = face_cell(lo_a - 1e-4f), a1 = face_cell(hi_a + 1e-4f);
      const int b0 = face_cell(lo_b - 1e-4f), b1 = face_cell(hi_b + 1e-4f);
      for (int cb = b0; cb <= b1; ++cb)
        for (int ca = a0; ca <= a1; ++ca) {
          const std::size_t c = std::size_t((face * kFace + cb) * kFace + ca);
          for (std::uint32_t j = buckets[c]; j < buckets[c + 1]; ++j)
            if (covers(order[j])) pairs.push_back((std::uint64_t(order[j]) << 32) | id);
        }
    }
    if (wide) {  // every tip (the pairs of the faces above may repeat: first_crossing takes either)
      for (std::uint32_t i = 0; i < std::uint32_t(count); ++i)
        if (covers(i)) pairs.push_back((std::uint64_t(i) << 32) | id);
    }
  }
  return true;
}

} // namespace

bool BoxScene::within_reach(const Vec3& centre, float radius) const noexcept {
  if (!centre.allFinite()) return true;
  // A cell's slack: a stroke route's full mesh may stray from the simplified surface the
  // grid was built on by less than that.
  if (parts_.grid && !parts_.grid->empty()) return parts_.grid->surface_distance_bound(centre) <= radius + parts_.grid->cell();
  for (std::size_t b = 0; b < parts_.boxes.size(); ++b) {
    float d2 = 0.f;
    for (int k = 0; k < 3; ++k) {
      const float below = bounds_[k][b] - centre[k], above = centre[k] - bounds_[k + 3][b];
      const float gap = std::max({below, above, 0.f});
      d2 += gap * gap;
    }
    if (d2 <= radius * radius) return true;
  }
  return false;
}

void BoxScene::query_star(const Vec3& start, const Vec3* tips, std::size_t count, const ForceLaw& law, Contact* out,
                          StarScratch& scratch) const noexcept {
  const auto all = [&] { ContactQuery::query_star(start, tips, count, law, out, scratch); };
  if (!(parts_.grid && !parts_.grid->empty() && cells_ && route_ == SceneRoute::cells && start.allFinite())) return all();
  std::fill(out, out + count, Contact{});
  // 1.
  if (parts_.grid->code_at(start) == SceneGrid::kInside) return;
  float reach = 0.f;
  for (std::size_t i = 0; i < count; ++i) reach = std::max(reach, (tips[i] - start).norm());
  if (!std::isfinite(reach)) return all();
  switch (gather_triangles(*parts_.grid, *cells_, start, reach, scratch)) {
  case Gathered::none: return;
  case Gathered::too_many: return all();
  case Gathered::some: break;
  }
  bucket_tips(start, tips, count, scratch);
  if (!pair_triangles(cells_->surface(), start, reach, count, scratch)) return all();
  const SurfaceTriangles& surface = cells_->surface();
  std::vector<std::uint64_t>& pairs = scratch.pairs;
  // 5. Each paired tip: the nearest crossing among its triangles, as the cells' walk takes it
  //    (its triangles grouped by a counting sort on the tip).
  std::vector<std::uint32_t>& first = scratch.counts;
  first.assign(count + 1, 0);
  for (std::uint64_t pair : pairs) ++first[std::size_t(pair >> 32) + 1];
  for (std::size_t i = 1; i <= count; ++i) first[i] += first[i - 1];
  std::vector<std::uint32_t>& triangles = scratch.triangles;
  triangles.resize(pairs.size());
  for (std::uint64_t pair : pairs) {
    const std::size_t i = std::size_t(pair >> 32);
    triangles[first[i]++] = std::uint32_t(pair);
  }
  // `first[i]` is now the end of tip i's triangles: tip i's run is [first[i - 1], first[i]).
  for (std::size_t i = 0; i < count; ++i) {
    const std::uint32_t begin = i == 0 ? 0 : first[i - 1], end = first[i];
    if (begin == end) continue;
    const Segment segment{start, tips[i]};
    const Vec3 delta = segment.end - segment.start;
    const float length = delta.norm();
    if (!(length > 0.f)) continue;
    const float o[3] = {start.x(), start.y(), start.z()}, d[3] = {delta.x(), delta.y(), delta.z()};
    float s = 0.f;
    bool front = false;
    std::uint32_t id = kNoTriangle;
    if (surface.first_crossing(triangles.data() + begin, end - begin, o, d, 0.f, 1.f, s, front, id))
      out[i] = crossing_contact(segment, length, law, id, front);
  }
}

} // namespace hb
