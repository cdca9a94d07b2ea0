#pragma once
// The servo's per-tick force path (energy guard, then safety) as the stability suite's
// TickFilter, so the suite runs the very code the servo loop runs (hb::device over the core).
#include "device/energy_guard.h"
#include "device/safety.h"
#include "evaluation/trajectory.h"

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

} // namespace hb
