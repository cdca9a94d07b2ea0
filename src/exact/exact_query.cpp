#include "exact/exact_query.h"

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

} // namespace hb
