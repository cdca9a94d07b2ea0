#pragma once
// A probe's memory of its last block-coded quads (haptic_box.h, query_into; sample_fetch.h).
#include <cstddef>
#include <cstdint>

namespace hb {

/// The decoded samples of a query's four quads (a block-coded table's), kept by a probe's
/// query state so that the next tick, in the same position and directional cells, blends
/// them again without decoding (BoxScene::query with a SceneQueryState). Along a stroke the
/// cells change every hundred ticks or so. Keyed by the table and the quads; `reused` counts
/// the queries it served.
struct DecodedQuads {
  const void* table = nullptr;
  std::size_t tiles[4] = {0, 0, 0, 0};
  int a0 = -1, b0 = -1;
  alignas(16) float t[4][4], u[4][4], v[4][4], hit[4][4];  // per corner, per sample; hit: all bits or none
  std::uint64_t reused = 0;
};

}  // namespace hb
