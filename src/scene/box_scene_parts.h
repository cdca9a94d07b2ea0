#pragma once
// The parts of BoxScene's query its files share (internal to scene/): the surface cells a
// routed walk crossed (step 7 of box_scene.cpp's overview) and the two tests of the side of
// the surface the handle is on (box_scene_handle.cpp).
#include "exact/exact_query.h"
#include "scene/box_scene.h"
#include "mesh/triangle_mesh.h"
#include <memory>

namespace hb {

// The surface cells a routed query's walk crossed (step 7).
struct BoxScene::Visited {
  static constexpr int kMax = 32;
  std::uint32_t cell[kMax];
  std::uint16_t code[kMax];
  float s[kMax];
  int count = 0;
  bool overflow = false;
};

namespace scene_handle {

// True when the handle lies inside the box's piece along the segment's line: walking from the
// box entry towards the handle meets the piece's outside first (the line entered the piece
// before the handle), and walking back from the box exit towards the handle does too (the
// piece goes on past the handle). Both are ordinary box queries on the same tables.
// The piece's far surface must also come before the contact found ahead (`contact_along`
// from the handle): otherwise the line leaves the piece, and the handle sits in a pocket of
// it, not inside it.
bool handle_inside(const HapticBox& box, const Segment& segment, const ForceLaw& law, float contact_along,
                   std::size_t* asked) noexcept;

// A handle in a surface cell lies outside the object when a point a little behind it on the
// segment's line is in an outside cell and no refining box whose surface the short segment
// from there to the handle crosses finds an entering crossing on it (the first crossing from
// outside enters). False (undecided: the caller takes the unrouted path) when no outside cell
// is within kBehind cells, a listed box does not refine, or a crossing is found.
bool handle_outside_behind(const SceneGrid& grid, const std::vector<HapticBox>& boxes, const Segment& segment,
                           const ForceLaw& law, std::size_t* asked_count) noexcept;

} // namespace scene_handle
} // namespace hb
