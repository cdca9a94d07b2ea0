#pragma once
// Hardware-free trajectories: a simulated device (1 kHz zero-order hold, optional one-tick
// delay, mass, damping, position quantum, force saturation) with an optional hand model,
// driving any ContactQuery (the box, exact Embree, an analytic wall) in device space.
// The protocol and its reference figures: docs/stability.md.
#include "contact/contact.h"
#include "contact/god_object.h"
#include "contact/tick_filter.h"
#include "contact/workspace.h"
#include <cstdint>
#include <Eigen/Core>
#include <limits>
#include <memory>
#include <functional>
#include <string>
#include <vector>

namespace hb {

/// A hand holding the handle: a mass-spring-damper pulled toward a set-point (Hulin et al.).
struct HandModel {
  std::string name = "none";
  double mass_kg = 0.0, damping_n_s_per_m = 0.0, stiffness_n_per_m = 0.0;
  bool present() const { return mass_kg > 0 || damping_n_s_per_m > 0 || stiffness_n_per_m > 0; }
};
HandModel no_hand();
HandModel light_grip();  ///< 0.1 kg, 2 N s/m, 50 N/m: the least stabilising grip.
HandModel arm_hand();    ///< 0.554 kg, 6.45 N s/m, 135 N/m.

/// One rendered answer in device space.
struct Rendered {
  bool contact = false;
  Vec3d force{Vec3d::Zero()};   ///< N.
  Vec3d normal{Vec3d::Zero()};  ///< unit, outward.
  double depth_m = 0.0;         ///< along the stylus.
  Vec3d point_m{Vec3d::Zero()}; ///< the surface point of the answer, device space.
};

/// The probe: the tip at the device position (mapped to the model by `map`), the handle
/// `stylus_m` behind it along `dir` (unit, handle -> tip). `law.metres_per_unit` must equal
/// map.metres_per_unit (the tests vary the stiffness; the scale is the workspace's).
Rendered render(const ContactQuery& query, const ForceLaw& law, const Workspace& map, const Vec3d& tip_m,
                const Vec3d& dir, double stylus_m);

// How a trajectory's answers become forces: ContactLaw (contact/god_object.h).

/// Renders the ticks of one trajectory, in order: render() with the penalty law, through a
/// GodObject (created per renderer: its state is the trajectory's) with the proxy.
class TrajectoryRenderer {
public:
  TrajectoryRenderer(const ContactQuery& query, const ForceLaw& law, const Workspace& map, ContactLaw kind,
                     GodObjectOptions proxy_options = {});
  Rendered operator()(const Vec3d& tip_m, const Vec3d& dir, double stylus_m) noexcept;
  /// The proxy (nullptr with the penalty law).
  const GodObject* proxy() const noexcept { return kind_ == ContactLaw::proxy ? &proxy_ : nullptr; }

private:
  const ContactQuery& query_;
  ForceLaw law_;
  Workspace map_;
  ContactLaw kind_;
  GodObject proxy_;
};

/// A flat analytic wall (plane through `point`, outward `normal`), answering segments with
/// the project's contact definition: the calibration reference of the suite.
class AnalyticWall final : public ContactQuery {
public:
  AnalyticWall(const Vec3& point, const Vec3& normal) : point_(point), normal_(normal.normalized()) {}
  Contact query(const Segment& segment, const ForceLaw& law) const noexcept override;

private:
  Vec3 point_, normal_;
};

/// A servo stall: no tick runs for `ticks` periods from tick `at` on (the device holds the last
/// force); the next tick is late by that much.
struct Stall {
  std::size_t at = 0;
  std::size_t ticks = 0;
};

/// A closed-loop run: the device (and hand) integrated with RK4 at T / substeps while the
/// force is held per tick.
struct ClosedLoopRun {
  DeviceProfile device;
  HandModel hand;
  Vec3d start_m{Vec3d::Zero()};
  Vec3d start_velocity{Vec3d::Zero()};
  /// The hand's set-point at time t (ignored without a hand).
  std::function<Vec3d(double)> set_point;
  double hand_release_s = std::numeric_limits<double>::infinity();  ///< the hand lets go.
  double seconds = 1.0;
  Vec3d stylus_dir{0, 0, -1};  ///< unit, handle -> tip.
  double stylus_m = 0.008;
  std::vector<Stall> stalls;
  TickFilter* filter = nullptr;  ///< not owned; nullptr: the force law straight to the device.
  int substeps = 100;
  /// Stop at the first tick out of contact after `stop_after_contact_ticks` ticks of contact
  /// (0: never stop early): free bounces end when the tip leaves.
  std::size_t stop_after_contact_ticks = 0;
  ContactLaw contact_law = ContactLaw::penalty;
};

/// One tick of a run: state at the tick (sampled position), the force applied over the tick.
struct TickRecord {
  double t = 0;
  Vec3d x{Vec3d::Zero()}, v{Vec3d::Zero()};
  Vec3d force{Vec3d::Zero()};    ///< applied (after delay, filter and saturation), N.
  Vec3d desired{Vec3d::Zero()};  ///< the force law's answer this tick, N.
  Vec3d normal{Vec3d::Zero()};
  bool contact = false;
  bool stalled = false;          ///< no tick ran: the device held the last force.
};

/// Runs a closed loop on `query`. Deterministic. Throws hb::InvalidInput on bad options.
std::vector<TickRecord> run_closed_loop(const ContactQuery& query, const ForceLaw& law, const Workspace& map,
                                        const ClosedLoopRun& run);

/// Prescribed motion: the probe at each tip position in turn (one per tick), fixed stylus.
/// Work and velocity fields follow the positions (v from finite differences).
std::vector<TickRecord> play_positions(const ContactQuery& query, const ForceLaw& law, const Workspace& map,
                                       const std::vector<Vec3d>& tips_m, const Vec3d& stylus_dir, double stylus_m,
                                       double period_s, ContactLaw contact_law = ContactLaw::penalty);

/// Passivity-equivalent stiffness of a prescribed run: K_eff = W_net / ((T/2) sum_contact |v|^2 T),
/// W_net = sum F_k . (x_{k+1} - x_k) the work of the held force on the probe (N/m). For an
/// exact wall K_eff is about k (0.976-1.000).
double passivity_equivalent_stiffness(const std::vector<TickRecord>& ticks, double period_s);

} // namespace hb
