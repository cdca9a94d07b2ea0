// The names of the routes and answerers (scene_route.h).
#include "haptic_box/scene_route.h"

namespace hb {

const char* route_name(SceneRoute route) noexcept {
  switch (route) {
  case SceneRoute::cells: return "cells";
  case SceneRoute::embree: return "embree";
  case SceneRoute::boxes: break;
  }
  return "boxes";
}

const char* answerer_name(Answerer answerer) noexcept {
  switch (answerer) {
  case Answerer::raw_box: return "raw";
  case Answerer::boxes: return "boxes";
  case Answerer::cells: return "cells";
  case Answerer::embree: return "embree";
  case Answerer::none: break;
  }
  return "";
}

std::optional<Answerer> parse_answerer(std::string_view name) noexcept {
  for (Answerer a : {Answerer::none, Answerer::raw_box, Answerer::boxes, Answerer::cells, Answerer::embree})
    if (name == answerer_name(a)) return a;
  return std::nullopt;
}

std::optional<SceneRoute> parse_route(std::string_view name) noexcept {
  for (SceneRoute r : {SceneRoute::boxes, SceneRoute::cells, SceneRoute::embree})
    if (name == route_name(r)) return r;
  return std::nullopt;
}

const char* answerer_words(Answerer answerer) noexcept {
  switch (answerer) {
  case Answerer::raw_box: return "the paper's raw haptic box (no triangle test)";
  case Answerer::boxes: return "haptic boxes refined against the triangles";
  case Answerer::cells: return "the surface cells' triangles (exact first crossing)";
  case Answerer::embree: return "exact ray casting (Embree) over the surface";
  case Answerer::none: break;
  }
  return "haptic boxes";
}

} // namespace hb
