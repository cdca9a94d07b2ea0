// The names of the routes and answerers (scene_route.h).
#include "scene/scene_route.h"

namespace hb {

const char* route_name(SceneRoute route) noexcept {
  switch (route) {
  case SceneRoute::cells: return "cells";
  case SceneRoute::embree: return "embree";
  case SceneRoute::boxes: break;
  }
  return "boxes";
}

std::optional<SceneRoute> parse_route(std::string_view name) noexcept {
  for (SceneRoute r : {SceneRoute::boxes, SceneRoute::cells, SceneRoute::embree})
    if (name == route_name(r)) return r;
  return std::nullopt;
}

} // namespace hb
