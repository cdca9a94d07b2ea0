// device_spec_problem: the ranges no haptic device leaves. A spec comes from a driver or, for
// a replay, from a log recorded elsewhere; the safety filter and the stiffness limit trust it,
// so a negative stiffness (forces reversed into the surface), an infinite force maximum (no
// clamp) or a zero one (silent zero force) is refused before any tick runs.
#include "device/haptic_device.h"
#include <cmath>
#include <cstdio>

namespace hb {
namespace {

std::string show(double v) {
  char text[32];
  std::snprintf(text, sizeof text, "%g", v);
  return text;
}

} // namespace

std::string device_spec_problem(const DeviceSpec& s) {
  const auto outside = [](float v, double lo, double hi, bool lo_open) {
    return !(std::isfinite(v) && (lo_open ? v > lo : v >= lo) && v <= hi);
  };
  // Lower bounds too (found by fuzzing): a 1e-40 m workspace maps the model at an infinite
  // scale, a 1e-30 N maximum is a silent zero force.
  if (outside(s.workspace_radius_m, kMinWorkspaceRadiusM, kMaxWorkspaceRadiusM, false))
    return "workspace radius " + show(s.workspace_radius_m) + " m is outside [" + show(kMinWorkspaceRadiusM) + ", " +
           show(kMaxWorkspaceRadiusM) + "]";
  if (outside(s.max_force_n, kMinDeviceForceN, kMaxDeviceForceN, false))
    return "maximum force " + show(s.max_force_n) + " N is outside [" + show(kMinDeviceForceN) + ", " +
           show(kMaxDeviceForceN) + "]";
  if (outside(s.max_continuous_force_n, 0.0, s.max_force_n, true))
    return "maximum continuous force " + show(s.max_continuous_force_n) + " N is outside (0, maximum force " +
           show(s.max_force_n) + "]";
  if (outside(s.max_stiffness_n_per_m, kMinDeviceStiffnessNPerM, kMaxDeviceStiffnessNPerM, false))
    return "maximum stiffness " + show(s.max_stiffness_n_per_m) + " N/m is outside [" +
           show(kMinDeviceStiffnessNPerM) + ", " + show(kMaxDeviceStiffnessNPerM) + "]";
  if (outside(s.max_damping_n_s_per_m, 0.0, kMaxDeviceDampingNsPerM, false))
    return "maximum damping " + show(s.max_damping_n_s_per_m) + " N s/m is outside [0, " +
           show(kMaxDeviceDampingNsPerM) + "]";
  return {};
}

} // namespace hb
