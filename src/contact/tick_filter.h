#pragma once
// A simulated haptic device's profile and the per-tick filter between the force law and the
// device (the servo's safety, an energy guard): what the trajectory harness (evaluation/) drives
// and the device layer (device/) implements, so neither includes the other.
#include "math/vec3.h"
#include <functional>
#include <memory>
#include <string>

namespace hb {

/// A simulated haptic device. SI units.
struct DeviceProfile {
  std::string name = "falcon";
  double period_s = 1e-3;          ///< servo period T (zero-order hold), s, > 0.
  int delay_ticks = 0;             ///< transport delay: force computed at tick k is applied at k + delay.
  double mass_kg = 0.1;            ///< moving mass of the device, kg, > 0.
  double damping_n_s_per_m = 0.0;  ///< physical damping b, N s/m, >= 0.
  double quantum_m = 0.0;          ///< encoder position quantum per axis, m (0: none).
  double max_force_n = 8.0;        ///< saturation, N.
  double max_stiffness_n_per_m = 3000.0;  ///< the vendor's stable stiffness at 1 kHz, N/m.
  /// Damping at the passivity bound for stiffness k: b = k T / 2 (Colgate and Brown 1994).
  double passivity_damping(double k) const { return 0.5 * k * period_s; }
};

/// Novint Falcon: 8 N, 3000 N/m. Touch: 3.3 N, 400 N/m.
DeviceProfile falcon_profile();
DeviceProfile touch_profile();
/// "falcon" or "touch"; throws hb::InvalidInput naming the value otherwise.
DeviceProfile device_profile(const std::string& name);

/// A filter between the force law and the device (the servo's safety, an energy guard),
/// called once per tick. Implemented in the device layer (hb::device) over SafetyFilter.
class TickFilter {
public:
  virtual ~TickFilter() = default;
  /// desired: the force law's answer; lateness: how late this tick is (a stall), s.
  virtual Vec3d apply(const Vec3d& desired_n, const Vec3d& position_m, const Vec3d& velocity_m_per_s,
                      double lateness_s) noexcept = 0;
};
using TickFilterFactory = std::function<std::unique_ptr<TickFilter>()>;

} // namespace hb
