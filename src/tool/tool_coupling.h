#pragma once
// The virtual coupling of a tool (McNeely et al. 1999; god-object style, Zilles and Salisbury
// 1995): a simulated tool follows the device's pose but is kept out of the model, and the
// force sent to the device is a spring from the device to the simulated tool. Each tick the
// simulated tool moves towards the device in sub-steps of at most a fraction of the tool's
// size, each resolved out of the surface by the tool's contact (ToolProbe), so its centre never
// crosses a surface however hard or fast the device pushes: no pop-through, and the points'
// handles stay outside the model. The hand feels the coupling spring (the workspace's
// stiffness), not the number of touching points. docs/tools.md.
#include "contact/workspace.h"
#include "tool/tool_contact.h"

namespace hb {

struct ToolCouplingOptions {
  /// Largest sub-step of the simulated tool, as a fraction of the tool's own size (a sphere's
  /// or capsule's radius, a mesh tool's margin), in (0, 1].
  double max_step_fraction = 0.5;
  /// Sub-steps a tick at most; a device farther away than that is caught up over the next ticks
  /// (the force, the spring's, still says how far).
  int max_substeps = 16;
};

/// One tick's coupling.
struct ToolCouplingStep {
  Vec3 force{Vec3::Zero()};      ///< N on the device: k (tool - device), model to device metres.
  Vec3 torque{Vec3::Zero()};     ///< N m the contact puts on the simulated tool about its centre.
  ToolPose tool;                 ///< the simulated tool, model units.
  ToolAnswer contact;            ///< the contact of the last sub-step (at the simulated tool).
  int substeps = 0;
  bool touching = false;         ///< the simulated tool touches, or is held off the device.
};

/// A simulated tool coupled to a device over a ContactQuery. One per servo loop or trajectory;
/// step() allocates nothing.
class ToolCoupling {
public:
  /// The tool at `workspace`'s scale (its metres per unit; the force law comes with each step).
  ToolCoupling(const ContactQuery& query, const ToolShape& tool, const Workspace& workspace,
               const ToolCouplingOptions& options = {});
  /// Places the simulated tool at `pose` (the first tick's device pose; the tool should start
  /// out of the model).
  void reset(const ToolPose& pose) noexcept;
  /// The tick at device pose `device` (model units): moves the simulated tool, returns the
  /// coupling force. The first step() without reset() starts at the device.
  const ToolCouplingStep& step(const ToolPose& device, const ForceLaw& law) noexcept;
  const ToolCouplingStep& last() const noexcept { return last_; }
  const ToolProbe& probe() const noexcept { return probe_; }

private:
  const ContactQuery& query_;
  ToolProbe probe_;
  ToolCouplingOptions options_;
  float max_step_ = 0.f;  // model units
  bool started_ = false;
  ToolPose tool_;
  ToolCouplingStep last_;
  float pinch_depth_ = 0.f;  // the squeeze the tool was last left in (model units)
};

} // namespace hb
