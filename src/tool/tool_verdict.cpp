#include "tool/tool_verdict.h"
#include <algorithm>
#include <cmath>

namespace hb {

Contact as_contact(const ToolAnswer& answer) noexcept {
  Contact c;
  c.contact = answer.contacts > 0 && answer.force.squaredNorm() > 0.f;
  c.force = c.contact ? answer.force : Vec3(Vec3::Zero());
  c.normal = c.contact ? Vec3(answer.force.normalized()) : Vec3(Vec3::Zero());
  return c;
}

ToolDifference perceive_tool(const ToolAnswer& exact, const ToolAnswer& approx, const PerceptualThresholds& t,
                             double max_force_n, double radius_m) noexcept {
  ToolDifference d;
  d.force = perceive(as_contact(exact), as_contact(approx), t, max_force_n);
  if (radius_m > 0.0) {
    const double weber = kTorqueWeber * (t.weber / PerceptualThresholds{}.weber);
    d.torque_difference_nm = double((approx.torque - exact.torque).norm());
    d.torque_threshold_nm = std::max(weber * double(exact.torque.norm()), t.floor_n * radius_m);
    d.torque_felt = std::isfinite(d.torque_difference_nm) ? d.torque_difference_nm > d.torque_threshold_nm : true;
  }
  return d;
}

} // namespace hb
