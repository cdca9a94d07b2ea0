#pragma once
// What answers a scene's queries: the route a scene takes (SceneRoute) and what its reports
// call the answerer (Answerer, which tells the paper's raw box from refining boxes). Names
// are read and written here only: in box files, JSON and the command line's --route.
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

/// What answers a scene's queries, as reports and box files name it.
enum class Answerer : std::uint8_t {
  none,     ///< not recorded (a scene baked without a budget).
  raw_box,  ///< the paper's haptic box: boxes answering from their samples alone.
  boxes,    ///< boxes refining their answers from their triangle ids.
  cells,    ///< the surface cells' triangles (exact).
  embree,   ///< exact Embree over the scene's surface.
};

/// "boxes", "cells" or "embree".
const char* route_name(SceneRoute route) noexcept;
/// "", "raw", "boxes", "cells" or "embree": the token box files and JSON carry.
const char* answerer_name(Answerer answerer) noexcept;
/// The answerer a token names (answerer_name's inverse), or nothing.
std::optional<Answerer> parse_answerer(std::string_view name) noexcept;
/// The route a token names ("boxes", "cells", "embree"), or nothing.
std::optional<SceneRoute> parse_route(std::string_view name) noexcept;
/// The answerer in words a newcomer understands, e.g. "exact ray casting (Embree) over the
/// surface".
const char* answerer_words(Answerer answerer) noexcept;
/// The answerer of a route: `refining` tells refined boxes from the raw box.
inline Answerer answerer_of(SceneRoute route, bool refining) noexcept {
  return route == SceneRoute::cells    ? Answerer::cells
         : route == SceneRoute::embree ? Answerer::embree
         : refining                    ? Answerer::boxes
                                       : Answerer::raw_box;
}

} // namespace hb
