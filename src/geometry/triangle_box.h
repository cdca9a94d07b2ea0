#pragma once
// Whether a triangle meets an axis-aligned cube: the scene grid's and the surface cells'
// listing test.
#include "math/vec3.h"
#include <algorithm>
#include <cmath>

namespace hb {

/// Separating-axis test of triangle (a, b, c3) against the axis-aligned cube of centre c and
/// half extent h (Akenine-Moller 2001: the three box axes, the triangle's normal, the nine
/// edge cross products).
inline bool triangle_meets_box(const Vec3& a, const Vec3& b, const Vec3& c3, const Vec3& c, float h) {
  const Vec3 v0 = a - c, v1 = b - c, v2 = c3 - c;
  for (int k = 0; k < 3; ++k) {
    const float lo = std::min({v0[k], v1[k], v2[k]}), hi = std::max({v0[k], v1[k], v2[k]});
    if (lo > h || hi < -h) return false;
  }
  const Vec3 e[3] = {v1 - v0, v2 - v1, v0 - v2};
  const Vec3 n = e[0].cross(e[1]);
  {
    const float r = h * (std::fabs(n.x()) + std::fabs(n.y()) + std::fabs(n.z()));
    const float s = n.dot(v0);
    if (s > r || s < -r) return false;
  }
  for (int i = 0; i < 3; ++i)
    for (int k = 0; k < 3; ++k) {
      Vec3 axis = Vec3::Zero();
      axis[k] = 1.f;
      const Vec3 ax = axis.cross(e[i]);
      const float p0 = ax.dot(v0), p1 = ax.dot(v1), p2 = ax.dot(v2);
      const float r = h * (std::fabs(ax.x()) + std::fabs(ax.y()) + std::fabs(ax.z()));
      if (std::min({p0, p1, p2}) > r || std::max({p0, p1, p2}) < -r) return false;
    }
  return true;
}

} // namespace hb
