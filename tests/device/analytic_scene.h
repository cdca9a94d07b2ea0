#pragma once
// A real ContactQuery for device tests: the half-space z < height (model units), answered in
// closed form with the project's contact definition (first surface met walking from S to E
// must lie on the segment; S inside = no contact).
#include "haptic_box/contact.h"

namespace hb::test {

class HalfSpaceScene final : public ContactQuery {
public:
  explicit HalfSpaceScene(float height = 0.f) : height_(height) {}
  Contact query(const Segment& s, const ForceLaw& law) const noexcept override {
    Contact c;
    const float zs = s.start.z() - height_, ze = s.end.z() - height_;
    if (zs > 0.f && ze < 0.f) {
      const float t = zs / (zs - ze);
      c.contact = true;
      c.point = s.start + t * (s.end - s.start);
      c.depth = (s.end - c.point).norm();
      c.normal = Vec3(0.f, 0.f, 1.f);
    }
    apply_force_law(c, law);
    return c;
  }

private:
  float height_;
};

/// Returns NaN forces: for the safety path.
class NanScene final : public ContactQuery {
public:
  Contact query(const Segment&, const ForceLaw&) const noexcept override {
    Contact c;
    c.contact = true;
    c.force = Vec3::Constant(std::numeric_limits<float>::quiet_NaN());
    return c;
  }
};

} // namespace hb::test
