#pragma once
// Axis-aligned bounds of points (a mesh, a box, a scene).
#include "math/vec3.h"

namespace hb {

/// Axis-aligned bounds.
struct Bounds {
  Vec3 min{Vec3::Constant(0.f)};
  Vec3 max{Vec3::Constant(0.f)};
  float diagonal() const { return (max - min).norm(); }
};

} // namespace hb
