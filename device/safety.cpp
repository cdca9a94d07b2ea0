// Safety filter.
// 1. Faults first. NaN/Inf and the emergency stop: output zero, restart the ramp. Device fault
//    and watchdog: with FaultResponse::hold_and_ramp the force held so far becomes a ceiling
//    (the fresh force, never more than the held one) that grows back to the maximum force
//    over the ramp time; with zero_and_ramp, zero and restart the ramp (the old behaviour:
//    a probe inside the object then sinks under the hand and is re-stiffened: pop-through or
//    energy injected, docs/stability.md, T8).
// 2. Clamp |F| to the device maximum, keeping the direction.
// 3. Continuous limit: an exponential mean of |F| over `continuous_window_s`; above the
//    device's continuous rating the force is scaled so the mean cannot keep growing.
// 4. Ramp: scale by ticks-since-start-or-fault / ramp ticks.
// 5. Rate limit: the step from the last output is at most max_force_rate * dt.
#include "device/safety.h"
#include <algorithm>
#include <cmath>

namespace hb {

const char* to_string(DeviceStatus status) noexcept {
  switch (status) {
    case DeviceStatus::ok: return "ok";
    case DeviceStatus::disconnected: return "disconnected";
    case DeviceStatus::end_of_stream: return "end of stream";
    case DeviceStatus::fault: return "fault";
  }
  return "unknown";
}

const char* to_string(SafetyEvent e) noexcept {
  switch (e) {
    case SafetyEvent::non_finite: return "non_finite";
    case SafetyEvent::force_clamped: return "force_clamped";
    case SafetyEvent::continuous_limited: return "continuous_limited";
    case SafetyEvent::rate_limited: return "rate_limited";
    case SafetyEvent::watchdog: return "watchdog";
    case SafetyEvent::emergency_stop: return "emergency_stop";
    case SafetyEvent::device_fault: return "device_fault";
    case SafetyEvent::count_: break;
  }
  return "unknown";
}

SafetyFilter::SafetyFilter(const DeviceSpec& spec, const SafetyOptions& options,
                           double dt_s) noexcept
    : max_force_(std::max(0.f, spec.max_force_n)),
      max_continuous_(std::max(0.f, spec.max_continuous_force_n)),
      options_(options),
      dt_(dt_s > 0 ? dt_s : 1e-3) {
  ramp_ticks_total_ = options_.ramp_seconds > 0
                          ? static_cast<std::uint64_t>(std::max(1LL, std::llround(options_.ramp_seconds / dt_)))
                          : 0;
  max_step_ = static_cast<float>(options_.max_force_rate_n_per_s * dt_);
  ceiling_step_ = ramp_ticks_total_ > 0 ? max_force_ / float(ramp_ticks_total_) : max_force_;
  mean_alpha_ = options_.continuous_window_s > 0
                    ? static_cast<float>(std::min(1.0, dt_ / options_.continuous_window_s))
                    : 1.f;
}

void SafetyFilter::flag(SafetyEvent e) noexcept {
  const auto i = static_cast<std::size_t>(e);
  ++counters_[i];
  last_flags_ |= 1u << i;
}

Vec3 SafetyFilter::fault_zero(SafetyEvent e) noexcept {
  flag(e);
  ramp_ticks_done_ = 0;
  ceiling_active_ = false;
  last_ = Vec3::Zero();
  return last_;
}

void SafetyFilter::set_emergency_stop(bool on) noexcept { estop_ = on; }

Vec3 SafetyFilter::apply(const SafetyInput& in) noexcept {
  last_flags_ = 0;
  // Even when disabled, a non-finite force never reaches the device.
  if (!in.desired_force_n.allFinite() || !in.position_m.allFinite() ||
      !std::isfinite(in.lateness_s))
    return fault_zero(SafetyEvent::non_finite);
  if (!options_.enabled) {
    last_ = in.desired_force_n;
    return last_;
  }
  if (estop_) return fault_zero(SafetyEvent::emergency_stop);
  const bool late = in.lateness_s > options_.watchdog_bound_s;
  if (in.device_fault || late) {
    const SafetyEvent e = in.device_fault ? SafetyEvent::device_fault : SafetyEvent::watchdog;
    if (options_.fault_response == FaultResponse::zero_and_ramp) return fault_zero(e);
    flag(e);
    const float held = last_.norm();
    ceiling_ = ceiling_active_ ? std::min(ceiling_, held) : held;
    ceiling_active_ = true;
  }

  Vec3 f = in.desired_force_n;
  float mag = f.norm();
  if (mag > max_force_) {
    f *= max_force_ / mag;
    mag = max_force_;
    flag(SafetyEvent::force_clamped);
  }

  // Predicted mean if this force were applied; cap the force so the mean stays at the rating.
  const float predicted = mean_force_ + mean_alpha_ * (mag - mean_force_);
  if (predicted > max_continuous_ && mag > max_continuous_) {
    const float allowed = std::max(max_continuous_, mean_force_ + (max_continuous_ - mean_force_) / mean_alpha_);
    if (allowed < mag) {
      f *= allowed / mag;
      mag = allowed;
      flag(SafetyEvent::continuous_limited);
    }
  }

  if (ramp_ticks_total_ > 0 && ramp_ticks_done_ < ramp_ticks_total_) {
    ++ramp_ticks_done_;
    f *= static_cast<float>(ramp_ticks_done_) / static_cast<float>(ramp_ticks_total_);
  }

  if (ceiling_active_) {
    const float m = f.norm();
    if (m > ceiling_) f *= ceiling_ / m;
    ceiling_ += ceiling_step_;
    if (ceiling_ >= max_force_) ceiling_active_ = false;
  }

  const Vec3 step = f - last_;
  const float step_norm = step.norm();
  if (step_norm > max_step_) {
    f = last_ + step * (max_step_ / step_norm);
    flag(SafetyEvent::rate_limited);
  }

  mean_force_ += mean_alpha_ * (f.norm() - mean_force_);
  if (!f.allFinite()) return fault_zero(SafetyEvent::non_finite);
  last_ = f;
  return last_;
}

} // namespace hb
