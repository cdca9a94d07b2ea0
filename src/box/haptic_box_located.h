#pragma once
// HapticBox's query between its two phases, shared by haptic_box.cpp (locate, finish) and
// haptic_box_settle.cpp (steps 6a and 6b). Internal to the haptic_box layer.
#include "box/haptic_box.h"
#include <cstddef>

namespace hb {

// A query between its two phases: the geometry (steps 1-3) is done and the corners'
// samples are being fetched (step 4 began); finish() blends them.
template <class Fetch> struct HapticBox::Located {
  float sx, sy, sz, lx, ly, lz;  // handle, unit direction
  float t_enter, d;              // box entry from the handle; entry to tip
  float d1, d2;                  // positional weights
  int face, i0, j0, a0, b0;      // position cell, directional cell
  std::size_t p00, sf;           // first corner's position point, sub-block face
  float dir_w[4];                // directional weights
  typename Fetch::Corner corners[4];
};

} // namespace hb
