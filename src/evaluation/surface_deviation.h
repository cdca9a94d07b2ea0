#pragma once
// How far a simplified surface (hb::decimate) is from the full one, measured.
#include "mesh/triangle_mesh.h"
#include <cstddef>
#include <cstdint>

namespace hb {

/// Distances from the full surface to the simplified one (model units).
struct SurfaceDeviation {
  std::size_t samples = 0;
  double mean = 0.0, p99 = 0.0, max = 0.0;
};

/// From `samples` points on `full` (uniform by area, seed `seed`), the distance along the
/// full mesh's flat normal, both ways, to `simplified` (Embree rays from `cap` behind the
/// point on either side; no hit within `cap` counts as cap: keep it below the thinnest part). Distances along the normal are at least the closest-point distances, so the figures
/// over-state the deviation. On all cores. Throws hb::InvalidInput on an empty mesh.
SurfaceDeviation measure_deviation(const TriangleMesh& full, const TriangleMesh& simplified, std::size_t samples,
                                   double cap, std::uint64_t seed = 7);

} // namespace hb
