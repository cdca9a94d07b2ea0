#include "exact/exact_query.h"
#include <algorithm>
#include <cmath>

namespace hb {

Contact ExactQuery::query(const Segment& segment, const ForceLaw& law) const noexcept {
  Contact c;
  const Vec3 delta = segment.end - segment.start;
  const float length = delta.norm();
  if (!(length > 0.f) || !std::isfinite(length)) return c;
  const Vec3 dir = delta / length;
  const RayHit hit = scene_.intersect(segment.start, dir, 0.f, length);
  if (!hit.hit || hit.back_face) return c;
  return contact_along(segment.start, dir, length, hit.t, hit.normal, law, hit.face_normal);
}

void ExactQuery::query_many(const Segment* segments, std::size_t count, const ForceLaw& law,
                            Contact* out) const noexcept {
  constexpr std::size_t kChunk = 64;
  Vec3 dirs[kChunk];
  float lengths[kChunk];
  Vec3 origins[kChunk];
  RayHit hits[kChunk];
  for (std::size_t first = 0; first < count; first += kChunk) {
    const std::size_t m = std::min(kChunk, count - first);
    for (std::size_t j = 0; j < m; ++j) {
      const Segment& s = segments[first + j];
      const Vec3 delta = s.end - s.start;
      const float length = delta.norm();
      origins[j] = s.start;
      // A segment query() answers with no contact traces a ray that misses (t_far < 0).
      const bool ok = length > 0.f && std::isfinite(length);
      lengths[j] = ok ? length : -1.f;
      dirs[j] = ok ? Vec3(delta / length) : Vec3(0.f, 0.f, 1.f);
    }
    scene_.intersect_many(origins, dirs, lengths, m, hits);
    for (std::size_t j = 0; j < m; ++j) {
      const RayHit& hit = hits[j];
      out[first + j] = !hit.hit || hit.back_face
                           ? Contact{}
                           : contact_along(origins[j], dirs[j], lengths[j], hit.t, hit.normal, law, hit.face_normal);
    }
  }
}

} // namespace hb
