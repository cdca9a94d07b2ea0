#pragma once
// The points of a set that can be extreme along some direction (fit_obb's rotation search).
#include "math/vec3.h"
#include <vector>

namespace hb {

/// The convex hull's vertices among `points`, with the points Qhull finds on its facets
/// within roundoff, in their order; all of `points` when there are fewer than 4096 (not
/// worth a hull), one is not finite, or Qhull cannot build a hull (all in a plane or on a
/// line). Every extreme of the set along any direction is among them, up to Qhull's roundoff.
std::vector<Vec3> hull_candidates(const std::vector<Vec3>& points);

} // namespace hb
