#include "haptic_box/box_scene.h"

namespace hb {

BoxScene::BoxScene(std::vector<HapticBox> boxes, SourceInfo source)
    : boxes_(std::move(boxes)), source_(std::move(source)) {}

Contact BoxScene::query(const Segment& segment, const ForceLaw& law) const noexcept {
  // Each box culls itself with its PBB slab test first (query_into returns at once when
  // the line misses it); the valid contact nearest the handle wins.
  Contact best;
  float best_along = 0.f;
  Contact c;
  for (const HapticBox& box : boxes_) {
    float along = 0.f;
    if (box.query_into(segment, law, c, along) && (!best.contact || along < best_along)) {
      best = c;
      best_along = along;
    }
  }
  return best;
}

std::size_t BoxScene::table_bytes() const {
  std::size_t sum = 0;
  for (const HapticBox& box : boxes_) sum += box.table_bytes();
  return sum;
}

} // namespace hb
