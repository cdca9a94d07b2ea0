#pragma once
// Real ContactQuery scenes for device tests: the closed-form half-space (the project's contact
// definition) and a scene that answers NaN forces, for the safety path.
#include "device/plane_scene.h"
#include "contact/contact.h"
#include <limits>

namespace hb::test {

/// The device layer's own closed-form half-space scene (device/plane_scene.h).
using HalfSpaceScene = hb::PlaneScene;

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
