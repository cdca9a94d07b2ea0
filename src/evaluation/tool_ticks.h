#pragma once
// Tools judged and timed where they matter: along slides over a model's surface, tick by tick
// (docs/tools.md). A slide is a tool held at a depth while it glides over the surface at a
// hand's speed, guided by exact answers; the box (any ContactQuery) and exact are then asked
// the same poses, and each contact tick's net force and torque are judged as a hand would.
#include "perception/perceptible.h"
#include "contact/workspace.h"
#include "tool/tool_contact.h"
#include <cstdint>
#include <vector>

namespace hb {

struct TriangleMesh;

struct ToolSlideOptions {
  std::size_t slides = 20;          ///< slides, each from a random surface point (area-weighted).
  std::size_t ticks = 250;          ///< ticks a slide (1 kHz: a quarter of a second).
  double speed_m_per_s = 0.03;      ///< gliding speed at the device (a hand exploring: 10-100 mm/s).
  double depth_m = 0.0005;          ///< the depth the slide holds (0.75 N at 1500 N/m).
  std::uint64_t seed = 1;
};

/// The slides' poses (model units), each a run of ticks 1 ms apart: the tool starts just above
/// a random surface point in a random orientation, sinks to `depth_m`, then glides along a
/// tangent, kept at that depth by exact's answer (its resolving translation) every tick.
/// Deterministic for a seed. Throws hb::InvalidInput on options out of range.
std::vector<std::vector<ToolPose>> tool_slides(const TriangleMesh& mesh, const ContactQuery& exact, const ToolShape& tool,
                                               const Workspace& workspace, const ToolSlideOptions& options = {});

/// Box against exact on the same ticks.
struct ToolTickStats {
  std::size_t ticks = 0;
  std::size_t contact_ticks = 0;      ///< ticks where either answer touches.
  std::size_t perceptible_ticks = 0;  ///< contact ticks a hand could tell apart (force or torque).
  std::size_t force_felt = 0, torque_felt = 0;
  /// Tick-to-tick changes of the net force beyond the thresholds (a buzz or a bump), each
  /// method against its own previous tick.
  std::size_t box_jumps = 0, exact_jumps = 0;
  double max_force_error_n = 0, mean_force_error_n = 0;  ///< |F_box - F_exact| over contact ticks.
  double max_torque_error_nm = 0;
  double mean_contacts = 0;           ///< exact's touching points a contact tick.
  double perceptible_share() const noexcept {
    return contact_ticks ? double(perceptible_ticks) / double(contact_ticks) : 0.0;
  }
};

/// Judges `approx` against `exact` on every tick of `slides` (in parallel over slides).
ToolTickStats compare_tool_ticks(const ContactQuery& approx, const ContactQuery& exact, const ToolShape& tool,
                                 const std::vector<std::vector<ToolPose>>& slides, const Workspace& workspace,
                                 const PerceptualThresholds& thresholds);

/// A tool's tick times on one core: each tick (ToolProbe::answer) timed on its own, the ticks
/// in slide order, `rounds` times over; the quantiles of each tick's median across the rounds
/// (the tail the ticks cause, the machine's one-off stalls filtered out).
struct ToolTickTiming {
  double p50_us = 0, p99_us = 0, max_us = 0;
  std::size_t ticks = 0;
};
ToolTickTiming time_tool_ticks(const ContactQuery& query, const ToolShape& tool,
                               const std::vector<std::vector<ToolPose>>& slides, const Workspace& workspace,
                               int rounds = 3);

/// Asks query() one segment at a time (query_many's default loop): exact Embree's single rays,
/// to time against its stream of rays.
class OneAtATime final : public ContactQuery {
public:
  explicit OneAtATime(const ContactQuery& query) : query_(query) {}
  Contact query(const Segment& segment, const ForceLaw& law) const noexcept override {
    return query_.query(segment, law);
  }
  bool within_reach(const Vec3& centre, float radius) const noexcept override {
    return query_.within_reach(centre, radius);
  }

private:
  const ContactQuery& query_;
};

} // namespace hb
