// What a tool with volume asks of a scene: its broad phase (within_reach) and its points'
// segments from one handle (query_star).
// query_star on the cells route: the answers of query() segment by segment, without a walk.
//  1. A handle in an inside cell: no segment is a contact.
//  2. The triangles listed in the surface cells within the segments' reach of the handle: a
//     segment crosses a triangle only at a point of such a cell, which lists it.
//  3. The tips' directions from the handle in buckets of a grid over the unit cube.
//  4. Each triangle is seen from the handle within a cap of directions (about its vertices'
//     mean direction, holding the three: the spherical triangle lies in it); it pairs with the
//     tips whose direction is in that cap (the buckets the cap's chord ball meets).
//  5. Each tip with triangles: the nearest crossing among them (SurfaceTriangles::
//     first_crossing, the walk's own test), shaded as the walk's (crossing_contact). Every
//     triangle the segment crosses is among them, so the crossing is the walk's (a tie between
//     two triangles at one point may name the other). A tip with none crosses nothing.
// A handle beside a triangle (a cap wider than 84 degrees) or too many cells in reach take
// query_many() for every segment.
#include "haptic_box/box_scene.h"
#include <algorithm>
#include <cmath>

namespace hb {
namespace {

constexpr std::size_t kMaxCellsInReach = 1 << 15;
constexpr float kWidestCap = 0.1f;  // cos of the widest cap taken (84 degrees)

} // namespace

bool BoxScene::within_reach(const Vec3& centre, float radius) const noexcept {
  if (!centre.allFinite()) return true;
  // A cell's slack: a stroke route's full mesh may stray from the simplified surface the
  // grid was built on by less than that.
  if (grid_ && !grid_->empty()) return grid_->surface_distance_bound(centre) <= radius + grid_->cell();
  for (std::size_t b = 0; b < boxes_.size(); ++b) {
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
  if (!(grid_ && !grid_->empty() && cells_ && answering_route() == SceneRoute::cells && start.allFinite())) return all();
  std::fill(out, out + count, Contact{});
  // 1.
  if (grid_->code_at(start) == SceneGrid::kInside) return;
  float reach = 0.f;
  for (std::size_t i = 0; i < count; ++i) reach = std::max(reach, (tips[i] - start).norm());
  if (!std::isfinite(reach)) return all();
  // 2. The triangles of the surface cells in reach (a cell box within reach of the handle).
  const float cell = grid_->cell();
  const Vec3& origin = grid_->origin();
  const auto& dims = grid_->dims();
  int lo[3], hi[3];
  std::size_t cells = 1;
  for (int k = 0; k < 3; ++k) {
    const float a = std::floor((start[k] - reach - origin[k]) / cell), b = std::floor((start[k] + reach - origin[k]) / cell);
    lo[k] = int(std::max(0.f, std::min(a, float(dims[k]))));
    hi[k] = int(std::max(-1.f, std::min(b, float(dims[k] - 1))));
    if (hi[k] < lo[k]) return;  // no cell of the grid (which covers the surface) in reach
    cells *= std::size_t(hi[k] - lo[k] + 1);
  }
  if (cells > kMaxCellsInReach) return all();
  std::vector<std::uint32_t>& ids = scratch.ids;
  ids.clear();
  for (int z = lo[2]; z <= hi[2]; ++z)
    for (int y = lo[1]; y <= hi[1]; ++y)
      for (int x = lo[0]; x <= hi[0]; ++x) {
        const std::uint32_t index = cells_->index(x, y, z);
        if (index == SurfaceCells::kNone) continue;
        const Vec3 box_lo = origin + cell * Vec3(float(x), float(y), float(z));
        const Vec3 gap = (box_lo - start).cwiseMax(start - box_lo - Vec3::Constant(cell)).cwiseMax(Vec3::Zero());
        if (gap.norm() > reach) continue;
        ids.insert(ids.end(), cells_->begin(index), cells_->end(index));
      }
  if (ids.empty()) return;
  std::sort(ids.begin(), ids.end());
  ids.erase(std::unique(ids.begin(), ids.end()), ids.end());
  // 3. The tips' directions in buckets of a 8 x 8 x 8 grid over the unit cube.
  constexpr int G = 8;
  const auto bucket_of = [](float v) { return std::min(G - 1, std::max(0, int((v + 1.f) * (0.5f * G)))); };
  std::vector<float>& directions = scratch.directions;
  directions.resize(3 * count);
  std::vector<std::uint32_t>& buckets = scratch.buckets;
  buckets.assign(G * G * G + 1, 0);
  std::vector<std::uint32_t>& order = scratch.order;
  order.resize(count);
  for (std::size_t i = 0; i < count; ++i) {
    const Vec3 d = tips[i] - start;
    const float n = d.norm();
    const Vec3 u = n > 0.f ? Vec3(d / n) : Vec3(Vec3::Zero());
    for (int k = 0; k < 3; ++k) directions[3 * i + std::size_t(k)] = u[k];
    ++buckets[std::size_t((bucket_of(u.z()) * G + bucket_of(u.y())) * G + bucket_of(u.x())) + 1];
  }
  for (std::size_t b = 1; b < buckets.size(); ++b) buckets[b] += buckets[b - 1];
  // Counting sort: each tip into its bucket (`counts`: how many placed so far).
  std::vector<std::uint32_t>& placed = scratch.counts;
  placed.assign(G * G * G, 0);
  for (std::size_t i = 0; i < count; ++i) {
    const float* u = &directions[3 * i];
    const std::size_t b = std::size_t((bucket_of(u[2]) * G + bucket_of(u[1])) * G + bucket_of(u[0]));
    order[buckets[b] + placed[b]++] = std::uint32_t(i);
  }
  // 4. Each triangle, seen from the handle within a cap of directions (the cap about its
  //    vertices' mean direction holding the three), pairs with the tips in that cap.
  const SurfaceTriangles& surface = cells_->surface();
  const SurfaceTriangles::Record* records = surface.records();
  std::vector<std::uint64_t>& pairs = scratch.pairs;
  pairs.clear();
  for (std::uint32_t id : ids) {
    if (id >= surface.size()) continue;
    const SurfaceTriangles::Record& r = records[id];
    const Vec3 a(r.a[0], r.a[1], r.a[2]);
    const Vec3 v[3] = {a - start, a + Vec3(r.e1[0], r.e1[1], r.e1[2]) - start, a + Vec3(r.e2[0], r.e2[1], r.e2[2]) - start};
    Vec3 sum = Vec3::Zero();
    Vec3 u[3];
    for (int k = 0; k < 3; ++k) {
      const float n = v[k].norm();
      if (!(n > 1e-6f * reach)) return all();  // the handle on a vertex: no cap
      u[k] = v[k] / n;
      sum += u[k];
    }
    const float sum_norm = sum.norm();
    if (!(sum_norm > 0.f)) return all();
    const Vec3 axis = sum / sum_norm;
    const float cos_half = std::min({axis.dot(u[0]), axis.dot(u[1]), axis.dot(u[2])}) - 1e-5f;
    if (!(cos_half > kWidestCap)) return all();  // the handle beside the triangle: a wide cap
    const float chord = std::sqrt(std::max(0.f, 2.f - 2.f * cos_half));
    int b0[3], b1[3];
    for (int k = 0; k < 3; ++k) {
      b0[k] = bucket_of(axis[k] - chord);
      b1[k] = bucket_of(axis[k] + chord);
    }
    for (int bz = b0[2]; bz <= b1[2]; ++bz)
      for (int by = b0[1]; by <= b1[1]; ++by)
        for (int bx = b0[0]; bx <= b1[0]; ++bx) {
          const std::size_t b = std::size_t((bz * G + by) * G + bx);
          for (std::uint32_t k = buckets[b]; k < buckets[b + 1]; ++k) {
            const std::uint32_t i = order[k];
            const float* d = &directions[3 * std::size_t(i)];
            if (d[0] * axis.x() + d[1] * axis.y() + d[2] * axis.z() >= cos_half)
              pairs.push_back((std::uint64_t(i) << 32) | id);
          }
        }
  }
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
