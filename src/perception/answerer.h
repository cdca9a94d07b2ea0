#pragma once
// What answers a scene's queries, as reports, box files and the bake's record name it: the
// paper's raw box, refining boxes, the surface cells or exact Embree. Names are read and
// written here only.
#include <cstdint>
#include <optional>
#include <string_view>

namespace hb {

/// What answers a scene's queries.
enum class Answerer : std::uint8_t {
  none,     ///< not recorded (a scene baked without a budget).
  raw_box,  ///< the paper's haptic box: boxes answering from their samples alone.
  boxes,    ///< boxes refining their answers from their triangle ids.
  cells,    ///< the surface cells' triangles (exact).
  embree,   ///< exact Embree over the scene's surface.
};

/// "", "raw", "boxes", "cells" or "embree": the token box files and JSON carry.
const char* answerer_name(Answerer answerer) noexcept;
/// The answerer a token names (answerer_name's inverse), or nothing.
std::optional<Answerer> parse_answerer(std::string_view name) noexcept;
/// The answerer in words a newcomer understands, e.g. "exact ray casting (Embree) over the
/// surface".
const char* answerer_words(Answerer answerer) noexcept;

} // namespace hb
