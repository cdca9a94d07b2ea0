// The tool's virtual coupling.
//  1. The simulated tool takes the device's orientation (a 3-DOF device's is fixed; the torque
//     is reported, not yet turned into rotation).
//  2. Its centre moves towards the device's in sub-steps of at most the max step (at most
//     max_substeps a tick); after each, the tool's contact there is resolved by its translation
//     (the smallest move that frees every touching point, ToolAnswer::translation), and the
//     goal loses its component into that contact's normal (the god-object's constraint: the
//     tool slides along the surface, it is not pushed into it again this tick).
//  3. Force on the device: the spring k (tool - device) in metres; the torque: the last
//     contact's.
#include "tool/tool_coupling.h"
#include <algorithm>
#include <cmath>

namespace hb {

ToolCoupling::ToolCoupling(const ContactQuery& query, const ToolShape& tool, const Workspace& workspace,
                           const ToolCouplingOptions& options)
    : query_(query), probe_(tool, workspace.metres_per_unit), options_(options) {
  const double metres_per_unit = workspace.metres_per_unit;
  const double fraction = std::min(1.0, std::max(1e-3, options.max_step_fraction));
  const double size = tool.size_m > 0.0 ? tool.size_m : 1e-3;
  max_step_ = float(fraction * size / metres_per_unit);
  options_.max_substeps = std::max(1, options.max_substeps);
}

void ToolCoupling::reset(const ToolPose& pose) noexcept {
  tool_ = pose;
  started_ = true;
  last_ = ToolCouplingStep{};
  last_.tool = pose;
  pinch_depth_ = probe_.answer(query_, pose, ForceLaw{}).deepest;
}

const ToolCouplingStep& ToolCoupling::step(const ToolPose& device, const ForceLaw& law) noexcept {
  if (!started_ || !tool_.position.allFinite()) reset(device);
  if (!device.position.allFinite()) {
    last_.force = Vec3::Zero();  // a bad pose renders nothing; the safety layer latches
    return last_;
  }
  tool_.orientation = device.orientation;
  // The goal of the sub-steps: the device, projected out of each contact met on the way (a
  // blocked direction is not pushed again this tick).
  Vec3 goal = device.position;
  ToolAnswer contact;
  int n = 0;
  while (n < options_.max_substeps) {
    const Vec3 delta = goal - tool_.position;
    const float distance = delta.norm();
    if (!(distance > 1e-6f * max_step_) && n > 0) break;
    const Vec3 move = distance > max_step_ ? Vec3(delta * (max_step_ / distance)) : delta;
    tool_.position += move;
    contact = probe_.answer(query_, tool_, law);
    ++n;
    if (contact.contacts == 0) continue;
    if (contact.pinched) {
      // No move frees it (a tool squeezed between walls): it may slide along the squeeze, not
      // sink deeper into it.
      if (contact.deepest > pinch_depth_ * 1.01f + 1e-3f * max_step_) {
        tool_.position -= move;
        break;
      }
      pinch_depth_ = contact.deepest;
    } else {
      pinch_depth_ = 0.f;
    }
    tool_.position += contact.translation;
    const float push = contact.translation.norm();
    if (push > 0.f) {
      const Vec3 normal = contact.translation / push;
      goal -= normal * std::min(0.f, normal.dot(goal - tool_.position));
    }
  }
  last_.substeps = n;
  last_.contact = contact;
  last_.tool = tool_;
  const double k_m = double(law.stiffness_n_per_m) * double(law.metres_per_unit);  // N per model unit
  last_.force = ((tool_.position - device.position).cast<double>() * k_m).cast<float>();
  last_.torque = contact.torque;
  last_.touching = contact.contacts > 0 || (tool_.position - device.position).norm() > 1e-6f * max_step_;
  return last_;
}

} // namespace hb
