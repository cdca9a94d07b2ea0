#pragma once
// The servo's per-tick force path (energy guard, then safety) as the stability suite's
// TickFilter, so the suite runs the very code the servo loop runs (hb::device over the core),
// and the suite's default filter, one definition for `hapticbox stability`, `hapticbox report
// --stability` and the window's Stability tab.
#include "contact/tick_filter.h"
#include "device/energy_guard.h"
#include "device/safety.h"
#include <string>

namespace hb {

class SafetyTickFilter final : public TickFilter {
public:
  SafetyTickFilter(const DeviceSpec& spec, const SafetyOptions& safety, const EnergyGuardOptions& guard,
                   double dt_s) noexcept
      : guard_(guard, dt_s), safety_(spec, safety, dt_s) {}

  Vec3d apply(const Vec3d& desired_n, const Vec3d& position_m, const Vec3d&, double lateness_s) noexcept override {
    SafetyInput in;
    in.position_m = position_m.cast<float>();
    in.desired_force_n = guard_.apply(desired_n.cast<float>(), in.position_m);
    in.lateness_s = lateness_s;
    return safety_.apply(in).cast<double>();
  }

  const SafetyFilter& safety() const noexcept { return safety_; }
  const EnergyGuard& guard() const noexcept { return guard_; }

private:
  EnergyGuard guard_;
  SafetyFilter safety_;
};

/// The device spec a simulated profile stands for (force, stiffness).
inline DeviceSpec device_spec_of(const DeviceProfile& p) {
  DeviceSpec s;
  s.name = p.name;
  s.max_force_n = float(p.max_force_n);
  s.max_continuous_force_n = float(p.max_force_n);
  s.max_stiffness_n_per_m = float(p.max_stiffness_n_per_m);
  return s;
}

/// A factory of hb::SafetyTickFilter for `device`: the given fault response, the energy guard
/// on or off, ticking at the profile's period.
TickFilterFactory safety_tick_filter_factory(const DeviceProfile& device, FaultResponse response, bool energy_guard);

/// The stability suite's default filter (hb::StabilityOptions::filter and filter_name): the
/// safety filter with hold-and-ramp and no energy guard, ticking at `device`'s period.
void use_servo_force_path(TickFilterFactory& filter, std::string& filter_name, const DeviceProfile& device);

} // namespace hb
