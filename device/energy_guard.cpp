// Energy guard (passivity observer and controller).
// 1. Observe: add the work of last tick's held force over last tick's motion to the episode.
// 2. A zero desired force ends the episode (its work resets).
// 3. Control: predict the work of the desired force over the next tick from the last
//    velocity; when the episode would turn active, scale the force down to what keeps it
//    passive (a factor in [0, 1]: never reversed, never attracting).
#include "device/energy_guard.h"
#include <algorithm>
#include <cmath>

namespace hb {

Vec3 EnergyGuard::apply(const Vec3& desired, const Vec3& position_m) noexcept {
  if (!options_.enabled) return desired;
  if (have_last_) work_ += double(last_force_.dot(position_m - last_position_));
  const Vec3 step = have_last_ ? Vec3(position_m - last_position_) : Vec3(Vec3::Zero());
  have_last_ = true;
  last_position_ = position_m;
  if (desired.squaredNorm() == 0.f || !desired.allFinite()) {
    work_ = 0.0;
    last_force_ = Vec3::Zero();
    return desired;
  }
  Vec3 out = desired;
  const double predicted = double(desired.dot(step));  // F . v T with v T = the last step
  const double budget = options_.allowance_j - work_;
  if (predicted > 0.0 && predicted > budget) {
    const double scale = std::clamp(budget / predicted, 0.0, 1.0);
    out = desired * float(scale);
    dissipated_ += (1.0 - scale) * predicted;
  }
  last_force_ = out;
  return out;
}

} // namespace hb
