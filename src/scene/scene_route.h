#pragma once
// How a scene finds the contact (SceneRoute), its names (the command line's --route) and the
// answerer a route is reported as (perception/answerer.h).
#include "perception/answerer.h"
#include <cstdint>
#include <optional>
#include <string_view>

namespace hb {

/// How a scene finds the contact.
enum class SceneRoute : std::uint8_t {
  /// The boxes answer (the paper's haptic box), through the scene grid when there is one,
  /// refined from their triangle ids when they hold them.
  boxes,
  /// The triangles listed in the surface cells the segment crosses answer directly: the first
  /// crossing from the handle, shaded as exact's; no box is asked. The default.
  cells,
  /// Exact Embree over the scene's surface: the same contacts as `cells`, taken where Embree
  /// answers faster (the bake times both).
  embree,
};

/// "boxes", "cells" or "embree".
const char* route_name(SceneRoute route) noexcept;
/// The route a token names ("boxes", "cells", "embree"), or nothing.
std::optional<SceneRoute> parse_route(std::string_view name) noexcept;
/// The answerer of a route: `refining` tells refined boxes from the raw box.
inline Answerer answerer_of(SceneRoute route, bool refining) noexcept {
  return route == SceneRoute::cells    ? Answerer::cells
         : route == SceneRoute::embree ? Answerer::embree
         : refining                    ? Answerer::boxes
                                       : Answerer::raw_box;
}

} // namespace hb
