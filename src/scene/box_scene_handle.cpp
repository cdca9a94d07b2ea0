// The side of the surface a scene query's handle is on (box_scene_parts.h): inside a box's
// piece along the segment's line (step 4 of box_scene.cpp's overview), or outside from a
// point a little behind it (step 5).
#include "scene/box_scene_parts.h"
#include <algorithm>
#include <cmath>

namespace hb {
namespace scene_handle {

// True when the handle lies inside the box's piece along the segment's line: walking from the
// box entry towards the handle meets the piece's outside first (the line entered the piece
// before the handle), and walking back from the box exit towards the handle does too (the
// piece goes on past the handle). Both are ordinary box queries on the same tables.
// The piece's far surface must also come before the contact found ahead (`contact_along`
// from the handle): otherwise the line leaves the piece, and the handle sits in a pocket of
// it, not inside it.
bool handle_inside(const HapticBox& box, const Segment& segment, const ForceLaw& law, float contact_along,
                   std::size_t* asked) noexcept {
  const Vec3 delta = segment.end - segment.start;
  const float length = delta.norm();
  if (!(length > 0.f)) return false;
  const Vec3 l = delta / length;
  LineBoxHit hit;
  if (!intersect_line_obb(box.obb(), segment.start, l, hit) || hit.t_enter >= 0.f || hit.t_exit <= 0.f)
    return false;
  const float margin = 1e-3f * box.obb().diagonal();
  if (asked) *asked += 2;
  Contact c;
  float along = 0.f;
  if (!box.query_into({segment.start + (hit.t_enter - margin) * l, segment.start}, law, c, along, Refine::misses)) return false;
  if (!box.query_into({segment.start + (hit.t_exit + margin) * l, segment.start}, law, c, along, Refine::misses)) return false;
  const float far_surface = hit.t_exit + margin - along;  // from the handle along l
  return far_surface < contact_along;
}

// A handle in a surface cell lies outside the object when a point a little behind it on the
// segment's line is in an outside cell and no refining box whose surface the short segment
// from there to the handle crosses finds an entering crossing on it (the first crossing from
// outside enters). False (undecided: the caller takes the unrouted path) when no outside cell
// is within kBehind cells, a listed box does not refine, or a crossing is found.
bool handle_outside_behind(const SceneGrid& grid, const std::vector<HapticBox>& boxes, const Segment& segment,
                           const ForceLaw& law, std::size_t* asked_count) noexcept {
  constexpr int kBehind = 4;
  constexpr int kMaxAsked = 8;
  const Vec3 delta = segment.end - segment.start;
  const float length = delta.norm();
  if (!(length > 0.f) || !std::isfinite(length)) return false;
  const Vec3 l = delta / length;
  Vec3 behind = segment.start;
  bool found = false;
  for (int k = 1; k <= kBehind && !found; ++k) {
    behind = segment.start - (float(k) * grid.cell()) * l;
    const std::uint16_t code = grid.code_at(behind);
    if (code == SceneGrid::kOutside) found = true;
    else if (code < SceneGrid::kFirstSurface) return false;  // inside or unknown behind
  }
  if (!found) return false;
  const Segment back{behind, segment.start};
  std::uint32_t asked[kMaxAsked];
  int n_asked = 0;
  bool outside = true;
  grid.walk_surface(back.start, back.end, [&](std::uint16_t code, float) {
    for (const std::uint32_t* b = grid.boxes_begin(code); b != grid.boxes_end(code); ++b) {
      if (std::find(asked, asked + n_asked, *b) != asked + n_asked) continue;
      if (n_asked == kMaxAsked || !boxes[*b].refines()) return outside = false;
      asked[n_asked++] = *b;
      if (asked_count) ++*asked_count;
      Contact c;
      float along = 0.f;
      if (boxes[*b].query_refined(back, law, c, along)) return outside = false;
    }
    return true;
  });
  return outside;
}

} // namespace scene_handle
} // namespace hb
