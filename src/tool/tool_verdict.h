#pragma once
// Whether a hand could tell a tool's answer from exact's at the same pose: the net force by
// the product's perceptual thresholds (perception/perceptible.h), the net torque by the torque
// JND (about 13% at a 60 mN m reference, Jandura and Srinivasan 1994) with a floor of the
// force floor times the tool's radius (research/tools.md). docs/tools.md.
#include "perception/perceptible.h"
#include "tool/tool_contact.h"

namespace hb {

/// Torque JND, fraction of |tau_exact| (nominal thresholds; scaled by the force JND's ratio
/// to the nominal one for other presets: 9.1% strict).
constexpr double kTorqueWeber = 0.13;

struct ToolDifference {
  PerceivedDifference force;  ///< the net forces as perceive() judges two contacts.
  bool torque_felt = false;   ///< |tau_box - tau_exact| > max(w_tau |tau_exact|, F0 radius).
  double torque_difference_nm = 0;
  double torque_threshold_nm = 0;
  bool perceptible() const noexcept { return force.perceptible() || torque_felt; }
};

/// The net force as one contact (contact when a point touches and the force is not zero).
Contact as_contact(const ToolAnswer& answer) noexcept;

/// Judges `approx` against `exact` for a tool of bounding radius `radius_m` (0: a point tool,
/// whose torque is not judged). Forces clamped to `max_force_n` as perceive() does.
ToolDifference perceive_tool(const ToolAnswer& exact, const ToolAnswer& approx, const PerceptualThresholds& t,
                             double max_force_n, double radius_m) noexcept;

} // namespace hb
