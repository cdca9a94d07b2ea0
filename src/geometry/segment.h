#pragma once
#include "math/vec3.h"

namespace hb {

/// A probe: a directed line segment from the handle `start` (S) to the tip `end` (E),
/// in model units (paper section 5).
struct Segment {
  Vec3 start{Vec3::Zero()};
  Vec3 end{Vec3::Zero()};
};

} // namespace hb
