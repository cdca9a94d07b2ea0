// The names of the answerers (answerer.h).
#include "perception/answerer.h"

namespace hb {

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
