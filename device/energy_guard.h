#pragma once
// An energy guard between the force law and the safety filter: a passivity observer and
// controller (Hannaford and Ryu 2002), windowed per contact episode. Off by default.
#include "math/vec3.h"

namespace hb {

/// Options of EnergyGuard.
struct EnergyGuardOptions {
  bool enabled = false;            ///< off: apply() returns the force unchanged.
  double allowance_j = 0.0;        ///< energy the display may give out per episode, J (>= 0).
};

/// Passivity observer: the work the held force did on the probe since the contact episode
/// began, W = sum F_{k-1} . (x_k - x_{k-1}) (exact for a zero-order hold). W > 0 means the
/// display gave out more energy than it took in (active). Controller, one step ahead: the
/// force about to be held does about F . v T of work over the next tick (v from the last
/// tick); when W + F . v T would exceed the allowance, the force is scaled down (never below
/// zero, never reversed: it never attracts) so that it does not. A free bounce then returns at
/// most the energy it brought (restitution <= 1 whatever the stiffness).
/// The episode (and W) resets when the desired force is zero (out of contact), so dissipation
/// banked in an earlier contact never masks a later active one (the caveat of a cumulative
/// observer, docs/stability.md). noexcept, allocation-free.
class EnergyGuard {
public:
  EnergyGuard(const EnergyGuardOptions& options, double dt_s) noexcept : options_(options), dt_(dt_s) {}

  /// One tick: `desired` from the force law, `position_m` the device position now.
  Vec3 apply(const Vec3& desired, const Vec3& position_m) noexcept;

  /// Work the display did on the probe this episode, J (> 0: active).
  double episode_work() const noexcept { return work_; }
  /// Energy the controller removed over the run, J.
  double dissipated() const noexcept { return dissipated_; }

private:
  EnergyGuardOptions options_;
  double dt_;
  bool have_last_ = false;
  Vec3 last_position_{Vec3::Zero()};
  Vec3 last_force_{Vec3::Zero()};
  double work_ = 0.0, dissipated_ = 0.0;
};

} // namespace hb
