#pragma once
// The stability suite (docs/stability.md): deterministic, hardware-free trajectory
// tests, the box and exact Embree side by side on the same trajectories, every figure as box,
// exact, difference, threshold and verdict. A calibration gate on an analytic wall runs first.
#include "stability/trajectory.h"
#include "scene/box_scene.h"
#include "parallel/communicator.h"
#include <cstdint>
#include <string>
#include <vector>

namespace hb {

struct TriangleMesh;
class ExactQuery;

/// How a metric's threshold is checked.
enum class StabilityRule : std::uint8_t {
  at_most,             ///< value <= threshold.
  at_least,            ///< value >= threshold.
  within,              ///< |value - threshold| <= tolerance (the calibration gate).
  difference_at_most,  ///< box - exact <= threshold.
  info,                ///< no threshold: a figure shown beside the others.
};

/// One figure of the suite.
struct StabilityMetric {
  std::string test;    ///< "calibration", "T1" .. "T8".
  std::string scene;   ///< the model, or a generated object ("wall", "plate 0.25 mm", ...).
  std::string metric;  ///< what is measured.
  std::string unit;
  double box = 0, exact = 0;  ///< exact is NaN where no reference exists (calibration).
  StabilityRule rule = StabilityRule::at_most;
  double threshold = 0, tolerance = 0;
  bool pass = false;        ///< the box (or the harness, for calibration) meets the threshold.
  bool exact_pass = false;  ///< exact meets it too (when not, a failure is the law's, not the box's).
  std::string verdict;      ///< "pass", "fail (box)", "fail (law: exact fails too)".
  double difference() const { return box - exact; }
};

/// A force magnitude along one trajectory, for the report's plot.
struct ForceTrace {
  std::string test, scene, label;
  std::vector<double> t_s, box_n, exact_n;
};

/// Options of run_stability_suite.
struct StabilityOptions {
  DeviceProfile device = falcon_profile();
  /// Tests to run: "T1" .. "T8" (empty: all). The calibration gate always runs.
  std::vector<std::string> tests;
  std::size_t sites = 12;        ///< trajectories per test and model (surface points by area).
  std::uint64_t seed = 1;
  double stylus_m = 0.008;       ///< the virtual stylus, handle to tip (the project's 8 mm).
  /// The model's scale at the device: hb::scene_workspace of the box (its mesh's bounding-box
  /// diagonal at diagonal_m, 80 mm by default; centred on its boxes), as `hapticbox servo`
  /// renders it. The tests set the stiffness themselves (the device's).
  WorkspaceOptions workspace;
  DepthLaw depth_law = DepthLaw::normal;
  /// How answers become forces along a trajectory: the penalty law (default) or a proxy
  /// (god-object) over the same answerer, box and exact alike.
  ContactLaw contact_law = ContactLaw::penalty;
  /// The servo's per-tick filter (hb::device's safety, with or without the energy guard) for
  /// T6 and T8; empty: the force law goes to the device unfiltered.
  TickFilterFactory filter;
  std::string filter_name = "none";
  bool generated = true;         ///< also the generated walls, plates and concave corners.
  int generated_m = 16, generated_n = 8;  ///< their boxes' densities.
  bool generated_refine = true;  ///< refine their boxes (default: as the model's box).
  std::string model_name = "model";
  /// Exact Embree on the model's mesh when the caller has it (the bake's trajectory check);
  /// null: built here.
  const ExactQuery* exact = nullptr;
  /// The ranks sharing the suite (nullptr: this process alone): every rank calls
  /// run_stability_suite with the same box, mesh and options; the tasks (the calibration gate,
  /// each test on each scene) are dealt in turn, and every rank returns the whole report,
  /// the same as one process's but for `seconds`.
  Communicator* communicator = nullptr;
};

struct StabilityReport {
  std::string device, filter, depth_law, contact_law = "penalty";
  std::vector<StabilityMetric> calibration;
  bool calibration_pass = false;
  std::vector<StabilityMetric> metrics;
  std::vector<ForceTrace> traces;
  std::size_t passed = 0, failed = 0, failed_law = 0;  ///< over `metrics`
  double seconds = 0;
};

/// The calibration gate: on an analytic flat wall the harness must give restitution
/// 1.148 +- 0.01 at K = 3000 N/m, b = 0, and 0.990 +- 0.01 at b = 1.5 N s/m (the reference
/// simulation), and K_eff / K in [0.976, 1.0] for prescribed in-out strokes.
std::vector<StabilityMetric> run_calibration(const DeviceProfile& device);

/// Runs the gate, then the tests on `box` (baked from `mesh`) against exact Embree on `mesh`,
/// and on the generated objects. Throws hb::InvalidInput on an unknown test name or an empty
/// mesh.
StabilityReport run_stability_suite(const BoxScene& box, const TriangleMesh& mesh, const StabilityOptions& options);

/// `hapticbox stability`'s defaults for `scene`: the Falcon profile, `sites` trajectories per
/// test, the generated objects refined as the scene is. The filter is left empty: the front
/// ends put the servo's own force path in it (hb::use_servo_force_path, device/).
StabilityOptions default_stability_options(const BoxScene& scene, const std::string& model_name, std::size_t sites);

/// Fills pass / exact_pass / verdict from the values and the rule.
void judge(StabilityMetric& m);

/// Generated test objects (model units: mm). A V-groove of interior angle `degrees` cut in a
/// block (walls 15 mm, the crease along y at the origin, the groove opening towards +z);
/// `welded`: the two walls share the crease's vertices with their averaged normal (smooth
/// shading), else every face has its own vertices (flat shading, a crisp crease).
TriangleMesh make_v_groove(float degrees, bool welded, int divisions = 8);
/// A plate of thickness `thickness_mm`, 30 x 30 mm, top face at z = thickness / 2.
TriangleMesh make_plate(float thickness_mm);

} // namespace hb
