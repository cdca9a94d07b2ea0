#pragma once
// Force safety between the contact query and the device: every rule is on by default.
#include "device/haptic_device.h"
#include <array>
#include <cstdint>

namespace hb {

/// Kinds of safety events, counted by SafetyFilter (index into SafetyCounters).
enum class SafetyEvent : std::uint8_t {
  non_finite = 0,      ///< NaN/Inf in position or force: zero force, ramp restarts.
  force_clamped,       ///< |F| exceeded the device's maximum force: scaled down.
  continuous_limited,  ///< the running mean of |F| exceeded the maximum continuous force.
  rate_limited,        ///< dF per tick exceeded the rate limit: limited.
  watchdog,            ///< the tick woke later than the watchdog bound: force held, ramps from it.
  emergency_stop,      ///< the emergency stop is latched: zero force until reset.
  device_fault,        ///< the device reported a transient fault: force held, ramps from it.
  count_
};
constexpr std::size_t safety_event_count = static_cast<std::size_t>(SafetyEvent::count_);
using SafetyCounters = std::array<std::uint64_t, safety_event_count>;
const char* to_string(SafetyEvent e) noexcept;

/// What a watchdog (late tick) or transient device fault does to the force.
enum class FaultResponse : std::uint8_t {
  /// Keep the held force as a ceiling and ramp the ceiling back up from it over `ramp_seconds`
  /// (the default): a probe inside the object is never dropped and then re-stiffened, which
  /// lets a pushing hand pop through the stylus or injects energy (stability test T8).
  hold_and_ramp,
  /// Zero the force and restart the ramp from zero (the first servo's behaviour).
  zero_and_ramp,
};

/// Options of SafetyFilter. Defaults are conservative and on.
struct SafetyOptions {
  bool enabled = true;                 ///< false only for offline analysis; never with hardware.
  float ramp_seconds = 0.5f;           ///< force scale grows linearly 0 -> 1 over this, at start
                                       ///< and after every fault, s (>= 0; 0 = no ramp).
  float max_force_rate_n_per_s = 2000.f;  ///< |dF/dt| limit, N/s (2 N per 1 ms tick).
  float continuous_window_s = 2.f;     ///< time constant of the |F| running mean, s.
  double watchdog_bound_s = 0.002;     ///< a tick waking later than deadline + this is a fault, s.
  FaultResponse fault_response = FaultResponse::hold_and_ramp;  ///< watchdog and device faults.
};

/// Inputs of one safety tick besides the desired force.
struct SafetyInput {
  Vec3 desired_force_n{Vec3::Zero()};  ///< from the contact query (after the workspace mapping).
  Vec3 position_m{Vec3::Zero()};       ///< device position, checked for NaN/Inf.
  double lateness_s = 0.0;             ///< wake-up time minus deadline, s.
  bool device_fault = false;           ///< the device reported a transient fault this tick.
};

/// Applies, in order: non-finite check, emergency stop, device fault, watchdog, clamp to the
/// maximum force, continuous-force limit, ramp-in, fault ceiling, rate limit. Non-finite
/// values and the emergency stop zero the force; a watchdog or device fault does what
/// SafetyOptions::fault_response says. The ramp and the rate limit
/// count ticks of the nominal period `dt`, not wall time, so a replay gives the same forces.
/// The output is always finite and |output| <= max force. noexcept, allocation-free.
class SafetyFilter {
public:
  SafetyFilter(const DeviceSpec& spec, const SafetyOptions& options, double dt_s) noexcept;

  /// One tick; returns the force to send to the device, N.
  Vec3 apply(const SafetyInput& in) noexcept;

  /// Latches the emergency stop (thread-safe to call via ServoLoop::emergency_stop, which
  /// forwards an atomic flag; here it is called from the servo thread only).
  void set_emergency_stop(bool on) noexcept;
  bool emergency_stopped() const noexcept { return estop_; }

  const SafetyCounters& counters() const noexcept { return counters_; }
  /// Bit i set when event i happened in the last apply().
  std::uint32_t last_flags() const noexcept { return last_flags_; }

private:
  void flag(SafetyEvent e) noexcept;
  Vec3 fault_zero(SafetyEvent e) noexcept;

  float max_force_;
  float max_continuous_;
  SafetyOptions options_;
  double dt_;
  std::uint64_t ramp_ticks_total_;
  std::uint64_t ramp_ticks_done_ = 0;
  float max_step_;       ///< rate limit per tick, N.
  float mean_alpha_;     ///< running-mean weight per tick.
  float mean_force_ = 0.f;
  float ceiling_ = 0.f;       ///< after a held fault: |F| limit, grows by ceiling_step_ a tick.
  float ceiling_step_ = 0.f;
  bool ceiling_active_ = false;
  bool estop_ = false;
  Vec3 last_{Vec3::Zero()};
  SafetyCounters counters_{};
  std::uint32_t last_flags_ = 0;
};

} // namespace hb
