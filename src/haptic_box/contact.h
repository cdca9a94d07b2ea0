#pragma once
// The answer to a probe query, shared by the exact reference and the haptic box so that a
// comparison isolates the approximation.
#include "geometry/segment.h"
#include <cstddef>

namespace hb {

/// Hooke's law (paper eq. 2): F = k (d - t0) n, with the depth converted to metres.
struct ForceLaw {
  float stiffness_n_per_m = 500.f;   ///< k in N/m, > 0.
  float metres_per_unit = 0.001f;    ///< model units to metres (default: models in mm).
};

/// Contact definition (paper Figure 7), the same for every method: walking the line of the
/// segment from outside the object towards the tip, the first surface met must lie on the
/// segment, between the handle S and the tip E. A handle already inside the object (the first
/// surface is behind S) or a tip short of the surface is no contact.
struct Contact {
  bool contact = false;         ///< true when the definition above holds.
  float depth = 0.f;            ///< penetration d - t0 along the segment, model units, >= 0.
  Vec3 point{Vec3::Zero()};     ///< surface point on the segment, model units.
  Vec3 normal{Vec3::Zero()};    ///< unit outward (shaded) surface normal at `point`.
  Vec3 force{Vec3::Zero()};     ///< k * depth * metres_per_unit * normal, in N.
};

/// Anything that answers a probe segment: the exact reference, one haptic box, a scene of
/// boxes. Implementations are noexcept, allocation-free and safe from many threads.
class ContactQuery {
public:
  virtual ~ContactQuery() = default;
  virtual Contact query(const Segment& segment, const ForceLaw& law) const noexcept = 0;
  /// Answers segments[0, count) into out[0, count), the same answers as query() one by one.
  /// Implementations may overlap the work of several queries (see HapticBox::query_many);
  /// this default runs query() in a loop.
  virtual void query_many(const Segment* segments, std::size_t count, const ForceLaw& law,
                          Contact* out) const noexcept {
    for (std::size_t i = 0; i < count; ++i) out[i] = query(segments[i], law);
  }
};

/// Fills `c.force` from `c.depth` and `c.normal`.
inline void apply_force_law(Contact& c, const ForceLaw& law) noexcept {
  c.force = c.contact ? Vec3(c.normal * (law.stiffness_n_per_m * c.depth * law.metres_per_unit))
                      : Vec3(Vec3::Zero());
}

} // namespace hb
