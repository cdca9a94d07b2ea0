#pragma once
// A built-in analytic scene: the solid half-space z < height (model units), answered in closed
// form with the project's contact definition. Lets `hapticbox servo plane` exercise the whole
// device path (and measure its timing) without a box file.
#include "contact/contact.h"

namespace hb {

class PlaneScene final : public ContactQuery {
public:
  explicit PlaneScene(float height = 0.f) noexcept : height_(height) {}
  /// Contact when S is above the plane and E below it; depth = |E - crossing point|.
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
    const Vec3 d = s.end - s.start;
    apply_force_law(c, law, d.norm() > 0.f ? Vec3(d / d.norm()) : Vec3(Vec3::Zero()));
    return c;
  }

private:
  float height_;
};

} // namespace hb
