// Box scene query. SceneRoute::embree asks Embree; SceneRoute::cells walks the surface cells
// from the handle (first_crossing_contact); SceneRoute::boxes takes the steps below.
//  1. Cull: the segment against the axis-aligned bounds of every PBB (flat loop).
//  2. Each surviving box runs its query (which starts with its exact PBB slab test).
//  3. The valid contact nearest the handle wins (contact definition: the first outside
//     surface met walking from the handle). Boxes that refine (HapticBox::attach_surface)
//     compete with their blended answers, refined only where the blend is no contact but
//     could become one (Refine::misses: silhouettes, a tip near the surface); the winner is
//     then refined fully. Measured on the 31-box armadillo: the same agreement as refining
//     every box (99.60% against 99.62%), one full refinement per query.
//  4. With several boxes, a contact is dropped when the handle lies inside any met box's
//     piece along the line and that piece ends before the contact (handle_inside): the first
//     surface from the handle is then an inside one, which the box that found the contact
//     ahead cannot see. Its box queries refine with Refine::misses too.
//  5. With a scene grid (scene_grid.h) steps 1-4 run only for a handle in a cell with surface
//     or of unknown state. A handle in an inside cell has no contact (the exact rule: the
//     first crossing leaves the object), with no box query. From an outside cell the query
//     walks the cells from the handle to the tip and asks (refined fully) each box listed by
//     a surface cell it crosses, once, until a cell begins beyond the nearest contact found;
//     that contact wins. The exact first crossing lies in a surface cell the segment
//     crosses, which lists a box holding its triangle (the one deepest in its piece there),
//     so a box that sees it is always asked; boxes whose pieces have no surface near the
//     segment are not (their contacts could only be blends of surface elsewhere). No inside
//     test is needed: the handle is outside. More than 8 boxes to ask, or no contact from the
//     boxes asked although the segment crossed surface, falls back to steps 1-4. A refining
//     box asked here answers from its triangle ids alone (HapticBox::query_refined): an
//     unconfirmed blend never answers here, so its samples are not read. A handle in a
//     surface cell is routed the same way when it is shown outside: a point up to 4 cells
//     behind it is in an outside cell and no box of the surface cells between them finds an
//     entering crossing there (handle_outside_behind); otherwise steps 1-4. When the boxes
//     the grid named find no contact although the segment crossed surface, the other boxes
//     the segment meets are asked the same way (the handle is outside: no inside test)
//     before steps 1-4 decide.
//  6. Unconfirmed blends (here and in the routed path of step 5): when the winner's full
//     refinement finds no triangle confirming its blended contact, the next blended contact
//     along the segment is refined in turn, and the first confirmed one wins; none confirmed
//     is no contact: a blend nearer the handle than the true surface, which refinement cannot
//     confirm, would push up to a millimetre from any triangle (docs/stability.md).
//  7. The triangles below the grid's surface cells (SurfaceCells, surface_cells.h; built from
//     the grid and the boxes' shared surface when the scene is made). (a) A handle in
//     a surface cell is inside or outside by its cell's triangles (the crossing nearest it
//     on the segment to its cell's centre, whose state is known): inside is no contact with
//     no box query, outside is routed as from an outside cell; only an undecided centre
//     (open meshes) takes handle_outside_behind / steps 1-4. (b) After the routed walk, the
//     first triangle the segment crosses in the surface cells that begin before the boxes'
//     contact (all its surface cells when they found none) decides, as exact's rule: the
//     boxes' own triangle (or none crossed): their answer; a back face: no contact; another
//     front face nearer (a second sheet a box named by the cell does not see: an ear a few
//     microns in front of the head) or a contact the boxes lost: that triangle's contact
//     from a refining box the segment meets (HapticBox::query_near, no walk), else steps 1-4.
//     This settles the second sheets and lost contacts the boxes alone miss.
#include "scene/box_scene_parts.h"
#include "errors.h"
#include "exact/exact_query.h"
#include "geometry/octahedral.h"
#include <algorithm>
#include <cstring>
#include <unordered_map>
#include <cmath>
#include <limits>
#include <mutex>

namespace hb {

using scene_handle::handle_inside;
using scene_handle::handle_outside_behind;

std::size_t BoxScene::cull(const Segment& segment, std::size_t first, std::size_t last,
                           std::uint32_t* out) const noexcept {
  const Vec3 d = segment.end - segment.start;
  float inv[3], s[3];
  for (int a = 0; a < 3; ++a) {
    s[a] = segment.start[a];
    inv[a] = std::fabs(d[a]) > 1e-30f ? 1.f / d[a] : std::copysign(1e30f, d[a]);
  }
  std::size_t met = 0;
  for (std::size_t k = first; k < last; ++k) {
    float t0 = 0.f, t1 = 1.f;
    for (int a = 0; a < 3; ++a) {
      const float u = (bounds_[a][k] - s[a]) * inv[a];
      const float v = (bounds_[3 + a][k] - s[a]) * inv[a];
      t0 = std::max(t0, std::min(u, v));
      t1 = std::min(t1, std::max(u, v));
    }
    out[met] = std::uint32_t(k);
    met += t0 <= t1 ? 1 : 0;
  }
  return met;
}

std::size_t boxes_met(const BoxScene& scene, const Segment& segment) noexcept {
  const Vec3 delta = segment.end - segment.start;
  const float length = delta.norm();
  if (!(length > 0.f)) return 0;
  const Vec3 l = delta / length;
  std::size_t met = 0;
  for (const HapticBox& box : scene.parts().boxes) {
    LineBoxHit hit;
    if (intersect_line_obb(box.obb(), segment.start, l, hit) && hit.t_enter <= length && hit.t_exit >= 0.f) ++met;
  }
  return met;
}

Contact BoxScene::query(const Segment& segment, const ForceLaw& law) const noexcept {
  switch (route_) {
  case SceneRoute::embree: return parts_.embree->exact->query(segment, law);
  case SceneRoute::cells: {
    // An inside handle has no contact; a segment without a length takes the boxes' path.
    if (parts_.grid->code_at(segment.start) == SceneGrid::kInside) return Contact{};
    const float length = (segment.end - segment.start).norm();
    if (length > 0.f && std::isfinite(length)) return first_crossing_contact(segment, length, law);
    return query_met(segment, law, nullptr);
  }
  case SceneRoute::boxes: break;
  }
  Contact routed;
  if (parts_.grid && query_routed(segment, law, routed, nullptr)) return routed;
  return query_met(segment, law, nullptr);
}

std::size_t BoxScene::box_queries(const Segment& segment, const ForceLaw& law) const noexcept {
  if (route_ != SceneRoute::boxes) return 0;
  std::size_t asked = 0;
  Contact c;
  if (parts_.grid && query_routed(segment, law, c, &asked)) return asked;
  query_met(segment, law, &asked);  // after the boxes the grid asked, if any
  return asked;
}

void BoxScene::prime(const Segment& segment, const ForceLaw& law) const noexcept {
  const Contact c = strokes_by_full_mesh(*this) ? parts_.stroke->exact->query(segment, law) : query(segment, law);
  keep_result(c);
}

Contact BoxScene::query(const Segment& segment, const ForceLaw& law, SceneQueryState& state) const noexcept {
  if (stroke_route_ == SceneRoute::embree) {
    // Embree over the surface, or the stroke route over the full mesh.
    ++state.full;
    return (route_ == SceneRoute::embree ? parts_.embree : parts_.stroke)->exact->query(segment, law);
  }
  return route_ == SceneRoute::cells ? query_cells_stroke(segment, law, state)
                                     : query_boxes_stroke(segment, law, state);
}

Contact BoxScene::query_cells_stroke(const Segment& segment, const ForceLaw& law,
                                     SceneQueryState& state) const noexcept {
  // As query()'s cells route: an inside handle has no contact; a segment without a length
  // takes the full query.
  const float length = (segment.end - segment.start).norm();
  const bool inside = parts_.grid->code_at(segment.start) == SceneGrid::kInside;
  if (inside || !(length > 0.f) || !std::isfinite(length)) {
    ++state.full;
    return inside ? Contact{} : query(segment, law);
  }
  const float reach = kFreeReach * parts_.grid->cell();
  // The same owner as cells_, which is alive: the same cells (a control block outlives its
  // weak references, so a later scene's cells cannot share it).
  const bool same_cells = !state.walked_cells.owner_before(cells_) && !cells_.owner_before(state.walked_cells);
  const bool near = same_cells && (segment.start - state.walked_start).squaredNorm() < reach * reach &&
                    (segment.end - state.walked_end).squaredNorm() < reach * reach;
  float s = 0.f;
  bool front = false;
  std::uint32_t triangle = kNoTriangle;
  if (near) {
    ++state.from_state;
    cells_->first_crossing_along(segment.start, segment.end, 1.f, s, front, triangle, state.free_to);
  } else {
    ++state.full;
    cells_->first_crossing_along(segment.start, segment.end, 1.f, s, front, triangle, 0.f, &state.free_to);
    if (!same_cells) state.walked_cells = cells_, state.lattice = SurfaceTriangles::LatticeCache{};
    state.walked_start = segment.start;
    state.walked_end = segment.end;
  }
  return crossing_contact(segment, length, law, triangle, front, &state.lattice);
}

Contact BoxScene::query_boxes_stroke(const Segment& segment, const ForceLaw& law,
                                     SceneQueryState& state) const noexcept {
  if (parts_.grid && state.box < parts_.boxes.size() && state.triangle != SceneQueryState::kNone && parts_.boxes[state.box].refines() &&
      parts_.grid->code_at(segment.start) == SceneGrid::kOutside) {
    const HapticBox& box = parts_.boxes[state.box];
    Contact c;
    float along = 0.f;
    std::uint32_t crossed = kNoTriangle;
    if (box.query_near(segment, law, state.triangle, kStateWalkSteps, c, along, &crossed)) {
      // The full query asks every box named by a surface cell that begins before the nearest
      // contact: it would ask this box alone.
      const float length = (segment.end - segment.start).norm();
      bool alone = true;
      parts_.grid->walk_surface(segment.start, segment.end, [&](std::uint16_t code, float s) {
        if (s * length > along) return false;
        for (const std::uint32_t* b = parts_.grid->boxes_begin(code); b != parts_.grid->boxes_end(code); ++b)
          if (*b != state.box) alone = false;
        return alone;
      });
      if (alone && cells_) {
        // As the full query (step 7): no triangle of the cells before the contact is crossed
        // nearer.
        std::uint32_t cells[Visited::kMax];
        int n = 0;
        bool overflow = false;
        parts_.grid->walk_surface(segment.start, segment.end, [&](std::uint16_t, float s, const int* i) {
          if (s * length > along) return false;
          if (n == Visited::kMax) return !(overflow = true);
          cells[n++] = cells_->index(i[0], i[1], i[2]);
          return true;
        });
        float fs = 0.f;
        bool front = false;
        std::uint32_t first = kNoTriangle;
        if (overflow || (cells_->first_crossing(cells, std::size_t(n), segment.start, segment.end,
                                                along / length + kSameCrossing, fs, front, first) &&
                         first != crossed && fs * length < along - kSameCrossing * length))
          alone = false;
      }
      if (alone) {
        state.triangle = crossed;
        ++state.from_state;
        return c;
      }
    }
  }
  ++state.full;
  // One block-coded box: the state keeps its last decoded quads (DecodedQuads), forgotten
  // when the table is another's.
  DecodedQuads* quads = nullptr;
  if (parts_.boxes.size() == 1 && parts_.boxes[0].codec() == CodecId::block && parts_.boxes[0].table_owner()) {
    const std::shared_ptr<const void>& owner = parts_.boxes[0].table_owner();
    if (state.quads_owner.owner_before(owner) || owner.owner_before(state.quads_owner)) {
      state.quads = DecodedQuads{};
      state.quads_owner = owner;
    }
    quads = &state.quads;
  }
  std::uint32_t box = SceneQueryState::kNone, triangle = kNoTriangle;
  Contact c;
  if (!(parts_.grid && query_routed(segment, law, c, nullptr, &box, &triangle)))
    c = query_met(segment, law, nullptr, &box, &triangle, quads);
  const bool known = c.contact && box < parts_.boxes.size() && triangle != kNoTriangle;
  state.box = known ? box : SceneQueryState::kNone;
  state.triangle = known ? triangle : SceneQueryState::kNone;
  return c;
}

bool BoxScene::query_routed(const Segment& segment, const ForceLaw& law, Contact& out,
                            std::size_t* asked_count, std::uint32_t* out_box, std::uint32_t* out_triangle) const noexcept {
  const SceneGrid& grid = *parts_.grid;
  const std::uint16_t handle = grid.code_at(segment.start);
  if (handle == SceneGrid::kInside) {
    out = Contact{};
    return true;
  }
  const bool cells = cells_ != nullptr;
  // A handle in a surface cell: its cell's triangles say whether it is inside (no contact)
  // or outside (routed); without them, or when they cannot tell, it is routed when shown
  // outside (its cell's boxes then see the surface around it); otherwise the path without
  // the grid decides.
  if (handle != SceneGrid::kOutside) {
    std::uint16_t state = SceneGrid::kUnknown;
    if (cells && handle >= SceneGrid::kFirstSurface) state = cells_->state_at(segment.start);
    if (state == SceneGrid::kInside) {
      out = Contact{};
      return true;
    }
    if (state != SceneGrid::kOutside &&
        (handle < SceneGrid::kFirstSurface ||
         !handle_outside_behind(grid, parts_.boxes, segment, law, asked_count)))
      return false;
  }
  const float length = (segment.end - segment.start).norm();
  if (!(length > 0.f) || !std::isfinite(length)) return false;
  constexpr int kMaxAsked = 8;
  std::uint32_t asked[kMaxAsked];
  int n_asked = 0;
  bool overflow = false;
  Contact best, c;
  float best_along = 0.f;
  std::uint32_t best_box = SceneQueryState::kNone, best_triangle = kNoTriangle;
  Visited visited;
  grid.walk_surface(segment.start, segment.end, [&](std::uint16_t code, float s, const int* i) {
    // A cell that begins beyond the nearest contact cannot hold a nearer one.
    if (best.contact && s * length > best_along) return false;
    if (code < SceneGrid::kFirstSurface) return true;
    if (cells) {
      if (visited.count < Visited::kMax) {
        visited.cell[visited.count] = cells_->index(i[0], i[1], i[2]);
        visited.code[visited.count] = code;
        visited.s[visited.count++] = s;
      } else {
        visited.overflow = true;
      }
    }
    for (const std::uint32_t* b = grid.boxes_begin(code); b != grid.boxes_end(code); ++b) {
      if (std::find(asked, asked + n_asked, *b) != asked + n_asked) continue;
      if (n_asked == kMaxAsked) {
        overflow = true;
        return false;
      }
      asked[n_asked++] = *b;
      float along = 0.f;
      bool refined = false;
      std::uint32_t triangle = kNoTriangle;
      const HapticBox& box = parts_.boxes[*b];
      if (box.refines()) {
        // Unconfirmed blends of refining boxes never answer here (step 6), so the blend is
        // not needed: the triangle ids alone answer (step 7).
        if (!box.query_refined(segment, law, c, along, &triangle)) continue;
      } else {
        if (!box.query_into(segment, law, c, along, Refine::all, &refined, &triangle)) continue;
        if (box.refines() && !refined) continue;
      }
      if (!best.contact || along < best_along) {
        best = c;
        best_along = along;
        best_box = *b;
        best_triangle = triangle;
      }
    }
    return true;
  });
  // No contact although the segment crossed surface: every box it meets decides (the few
  // probes whose owner box loses the surface at a silhouette, or that only graze it).
  if (asked_count) *asked_count += std::size_t(n_asked);
  if (overflow) return false;
  // Step 7: the first triangle crossed in the cells before the contact decides.
  if (cells && !visited.overflow) {
    if (!settle_first_crossing(segment, law, visited, best, best_along, best_box, best_triangle, asked_count))
      return false;
    out = best;
    if (out_box) *out_box = best.contact ? best_box : SceneQueryState::kNone;
    if (out_triangle) *out_triangle = best.contact ? best_triangle : kNoTriangle;
    return true;
  }
  if (n_asked > 0 && !best.contact) {
    // The boxes the grid named lost the surface (a silhouette, a graze). The handle is
    // outside, so the other boxes the segment meets may answer without an inside test.
    constexpr std::size_t kChunk = 64;
    std::uint32_t met[kChunk];
    for (std::size_t first = 0; first < parts_.boxes.size(); first += kChunk) {
      const std::size_t count = cull(segment, first, std::min(parts_.boxes.size(), first + kChunk), met);
      for (std::size_t i = 0; i < count; ++i) {
        if (std::find(asked, asked + n_asked, met[i]) != asked + n_asked) continue;
        if (asked_count) ++*asked_count;
        const HapticBox& box = parts_.boxes[met[i]];
        float along = 0.f;
        std::uint32_t triangle = kNoTriangle;
        bool hit = false;
        if (box.refines()) {
          hit = box.query_refined(segment, law, c, along, &triangle);
        } else {
          hit = box.query_into(segment, law, c, along, Refine::all, nullptr, &triangle);
        }
        if (hit && (!best.contact || along < best_along)) {
          best = c;
          best_along = along;
          best_box = met[i];
          best_triangle = triangle;
        }
      }
    }
    if (!best.contact) return false;
  }
  out = best;
  if (out_box) *out_box = best_box;
  if (out_triangle) *out_triangle = best_triangle;
  return true;
}

Contact BoxScene::first_crossing_contact(const Segment& segment, float length, const ForceLaw& law) const noexcept {
  // The surface cells in the order the segment enters them; a cell entered beyond the nearest
  // crossing so far cannot hold a nearer one (every triangle is listed in each cell it meets).
  float best_s = std::numeric_limits<float>::infinity();
  bool best_front = false;
  std::uint32_t best_id = kNoTriangle;
  // The walk jumps over empty space by the cells' clearance and steps cell by cell near the
  // surface (SurfaceCells::first_crossing_along).
  cells_->first_crossing_along(segment.start, segment.end, 1.f, best_s, best_front, best_id);
  return crossing_contact(segment, length, law, best_id, best_front);
}

Contact BoxScene::crossing_contact(const Segment& segment, float length, const ForceLaw& law, std::uint32_t best_id,
                                   bool best_front, SurfaceTriangles::LatticeCache* lattice) const noexcept {
  // No crossing, or the first one leaves the object (the handle is inside): no contact.
  if (best_id == kNoTriangle || !best_front) return Contact{};
  // Exact's contact on that triangle: the crossing along the unit direction, its shading.
  const Vec3 dir = (segment.end - segment.start) / length;
  const float o[3] = {segment.start.x(), segment.start.y(), segment.start.z()}, d[3] = {dir.x(), dir.y(), dir.z()};
  float t = 0.f;
  Vec3 normal;
  bool front = false;
  const bool crossed = lattice ? cells_->surface().intersect(best_id, o, d, 0.f, t, normal, front, *lattice)
                               : cells_->surface().intersect(best_id, o, d, 0.f, t, normal, front);
  if (!crossed || !front || !(t <= length)) return Contact{};
  return contact_along(segment.start, dir, length, t, normal, law, cells_->surface().face_normal(best_id));
}

bool BoxScene::settle_first_crossing(const Segment& segment, const ForceLaw& law, const Visited& visited, Contact& best,
                                     float& best_along, std::uint32_t& best_box, std::uint32_t& best_triangle,
                                     std::size_t* asked_count) const noexcept {
  const float length = (segment.end - segment.start).norm();
  // The cells that begin before the contact (all the segment's surface cells without one).
  std::uint32_t cells[Visited::kMax];
  int n = 0;
  for (int k = 0; k < visited.count; ++k)
    if (!best.contact || visited.s[k] * length <= best_along) cells[n++] = visited.cell[k];
  const float s_max = best.contact ? best_along / length + kSameCrossing : 1.f;
  float s = 0.f;
  bool front = false;
  std::uint32_t first = kNoTriangle;
  if (!cells_->first_crossing(cells, std::size_t(n), segment.start, segment.end, s_max, s, front, first))
    return true;  // no crossing: the box's contact (its triangle is beyond a float's reach), or none
  if (best.contact && (first == best_triangle || s * length >= best_along - kSameCrossing * length)) return true;
  if (!front) {
    // The first crossing leaves the object: no contact (exact's rule).
    best = Contact{};
    return true;
  }
  // A front face nearer than the boxes' contact (another sheet the box asked does not see),
  // or the boxes lost it: the contact of that triangle, from a refining box the segment meets.
  const auto try_box = [&](std::uint32_t b) {
    if (b >= parts_.boxes.size() || !parts_.boxes[b].refines()) return false;
    if (asked_count) ++*asked_count;
    Contact c;
    float along = 0.f;
    std::uint32_t crossed = kNoTriangle;
    if (!parts_.boxes[b].query_near(segment, law, first, 0, c, along, &crossed)) return false;
    best = c;
    best_along = along;
    best_box = b;
    best_triangle = crossed;
    return true;
  };
  if (best.contact && try_box(best_box)) return true;
  std::uint32_t tried[Visited::kMax];
  int n_tried = 0;
  if (best.contact) tried[n_tried++] = best_box;
  for (int k = 0; k < visited.count; ++k) {
    if (visited.s[k] > s) break;  // the crossing's cell begins before it
    for (const std::uint32_t* b = parts_.grid->boxes_begin(visited.code[k]); b != parts_.grid->boxes_end(visited.code[k]); ++b) {
      if (std::find(tried, tried + n_tried, *b) != tried + n_tried) continue;
      if (n_tried < Visited::kMax) tried[n_tried++] = *b;
      if (try_box(*b)) return true;
    }
  }
  // Then any other box the segment meets (the triangle's own piece is not named there).
  constexpr std::size_t kChunk = 64;
  std::uint32_t met[kChunk];
  for (std::size_t first_box = 0; first_box < parts_.boxes.size(); first_box += kChunk) {
    const std::size_t count = cull(segment, first_box, std::min(parts_.boxes.size(), first_box + kChunk), met);
    for (std::size_t i = 0; i < count; ++i)
      if (std::find(tried, tried + n_tried, met[i]) == tried + n_tried && try_box(met[i])) return true;
  }
  return false;  // no box answers for that triangle: the path without the grid decides
}

Contact BoxScene::query_met(const Segment& segment, const ForceLaw& law, std::size_t* asked, std::uint32_t* out_box,
                            std::uint32_t* out_triangle, DecodedQuads* quads) const noexcept {
  Contact best;
  float best_along = 0.f;
  const std::size_t count = parts_.boxes.size();
  // One box: its own exact slab test replaces the bounds cull (which only ever rejects
  // segments that miss the PBB), and no other piece can hide the handle.
  if (count == 1) {
    if (asked) ++*asked;
    bool refined = false;
    parts_.boxes[0].query_into(segment, law, best, best_along, Refine::all, &refined, out_triangle, quads);
    if (parts_.boxes[0].refines() && best.contact && !refined) return Contact{};
    if (out_box) *out_box = 0;
    return best;
  }
  Contact c;
  constexpr std::size_t kChunk = 64;
  std::uint32_t candidates[kChunk];
  // The blended contacts, nearest the handle first (kept short: a segment meets few boxes).
  constexpr std::size_t kHits = 8;
  std::uint32_t hit_box[kHits];
  float hit_along[kHits];
  std::size_t hits = 0;
  for (std::size_t first = 0; first < count; first += kChunk) {
    const std::size_t met = cull(segment, first, std::min(count, first + kChunk), candidates);
    if (asked) *asked += met;
    for (std::size_t i = 0; i < met; ++i) {
      float along = 0.f;
      // Blended answers (refined only where they are no contact) pick the box; the winner
      // alone is refined fully below.
      if (!parts_.boxes[candidates[i]].query_into(segment, law, c, along, Refine::misses)) continue;
      if (hits == kHits && along >= hit_along[kHits - 1]) continue;
      std::size_t k = hits < kHits ? hits++ : kHits - 1;
      for (; k > 0 && hit_along[k - 1] > along; --k) {
        hit_box[k] = hit_box[k - 1];
        hit_along[k] = hit_along[k - 1];
      }
      hit_box[k] = candidates[i];
      hit_along[k] = along;
      if (k == 0) best = c;
    }
  }
  if (hits == 0) return best;
  best_along = hit_along[0];
  if (parts_.boxes[hit_box[0]].refines()) {
    // The winner's samples are in cache now: its refined answer costs the refinement only.
    // A winner whose refinement does not confirm a contact yields to the next blended
    // contact along the segment that refinement confirms (a blend nearer the handle than the
    // true surface is a ghost), and when none confirms, there is no contact.
    bool found = false;
    for (std::size_t h = 0; h < hits && !found; ++h) {
      const HapticBox& box = parts_.boxes[hit_box[h]];
      float along = 0.f;
      bool refined = false;
      std::uint32_t triangle = kNoTriangle;
      if (asked) ++*asked;
      const bool hit = box.query_into(segment, law, c, along, Refine::all, &refined, &triangle);
      if (hit && (refined || !box.refines())) {
        best = c;
        best_along = along;
        found = true;
      }
      if (found) {
        if (out_box) *out_box = hit_box[h];
        if (out_triangle) *out_triangle = triangle;
      }
    }
    if (!found) return Contact{};
  }
  // With several boxes, a handle inside another piece (the first surface from the handle is
  // that piece's inside: no contact by definition) is invisible to the box that found the
  // contact ahead; ask the boxes whose PBB holds the handle.
  for (std::size_t first = 0; first < count; first += kChunk) {
    const std::size_t met = cull(segment, first, std::min(count, first + kChunk), candidates);
    for (std::size_t i = 0; i < met; ++i)
      if (handle_inside(parts_.boxes[candidates[i]], segment, law, best_along, asked)) return Contact{};
  }
  return best;
}

void BoxScene::query_many(const Segment* segments, std::size_t count, const ForceLaw& law,
                          Contact* out) const noexcept {
  switch (route_) {
  case SceneRoute::embree: return parts_.embree->exact->query_many(segments, count, law, out);  // one stream of rays
  case SceneRoute::cells:
    if (cells_->walks_side_by_side()) return query_many_cells(segments, count, law, out);
    break;
  case SceneRoute::boxes:
    if (parts_.boxes.size() == 1) return parts_.boxes[0].query_many(segments, count, law, out);
    break;
  }
  for (std::size_t i = 0; i < count; ++i) out[i] = query(segments[i], law);
}

void BoxScene::query_many_cells(const Segment* segments, std::size_t count, const ForceLaw& law,
                                Contact* out) const noexcept {
  // The cells route (query_routed's first lines), its walks run side by side a chunk at a
  // time (SurfaceCells::first_crossings_along): the same answers as query().
  constexpr std::size_t kChunk = 64;
  Vec3 a[kChunk], b[kChunk];
  float length[kChunk];
  std::uint32_t which[kChunk];
  SurfaceCells::Crossing crossing[kChunk];
  for (std::size_t first = 0; first < count; first += kChunk) {
    const std::size_t last = std::min(count, first + kChunk);
    std::size_t walks = 0;
    for (std::size_t i = first; i < last; ++i) {
      const Segment& segment = segments[i];
      if (parts_.grid->code_at(segment.start) == SceneGrid::kInside) {
        out[i] = Contact{};
        continue;
      }
      const float l = (segment.end - segment.start).norm();
      if (!(l > 0.f) || !std::isfinite(l)) {
        out[i] = query(segment, law);  // the path without the grid answers
        continue;
      }
      a[walks] = segment.start;
      b[walks] = segment.end;
      length[walks] = l;
      which[walks++] = std::uint32_t(i);
    }
    cells_->first_crossings_along(a, b, walks, crossing);
    for (std::size_t k = 0; k < walks; ++k)
      out[which[k]] = crossing_contact(segments[which[k]], length[k], law, crossing[k].triangle, crossing[k].front);
  }
}

} // namespace hb
