#pragma once
// The stability suite of a tool with volume (docs/tools.md): the tool's virtual coupling
// (ToolCoupling) driven along prescribed device paths, once over the box and once over exact,
// each test with its pass criteria. On the model: slides, fast pushes, resting contact, a
// press and release; on objects of their own, at true size (1 model unit = 1 mm): a thin plate
// pushed through at 0.5 m/s, a sphere centred in a narrow channel, a peg in a hole with 0.5 mm
// clearance (each baked as a refined box and answered exactly too).
#include "perception/perceptible.h"
#include "contact/workspace.h"
#include "tool/tool_coupling.h"
#include <functional>
#include <string>
#include <vector>

namespace hb {

struct TriangleMesh;

/// One test over one answerer.
struct ToolStabilityResult {
  std::string test;          ///< "slide", "fast-push", "rest", "press-release", "thin-plate", "channel", "peg-in-hole".
  std::string method;        ///< "box" or "exact".
  std::string criterion;     ///< what passing means, in words.
  bool pass = false;
  std::size_t ticks = 0;
  std::size_t pop_throughs = 0;  ///< ticks the coupling let go while the device pressed (see the .cpp).
  std::size_t ghost_ticks = 0;   ///< force above the floor with no surface at the device.
  std::size_t jumps = 0;         ///< tick-to-tick force changes beyond the thresholds.
  double max_force_n = 0;
  double figure = 0;             ///< the test's own figure (see `figure_name`).
  std::string figure_name;
};

class BoxScene;

struct ToolStabilityOptions {
  std::size_t slides = 10, slide_ticks = 300;
  std::size_t pushes = 10;
  double rest_seconds = 10.0;
  std::uint64_t seed = 7;
  /// How the generated objects are baked for the box's side (a front end passes the default
  /// bake); empty: one refined box (m 12, n 6), which cannot see a closed cavity.
  std::function<BoxScene(const TriangleMesh&)> bake_object;
};

/// Runs the suite with `tool` over `box` and `exact` (both answering `mesh`'s model at
/// `workspace`). Throws hb::InvalidInput on a bad mesh or options.
std::vector<ToolStabilityResult> run_tool_stability(const ContactQuery& box, const ContactQuery& exact,
                                                    const TriangleMesh& mesh, const ToolShape& tool,
                                                    const Workspace& workspace, const PerceptualThresholds& thresholds,
                                                    const ToolStabilityOptions& options = {});

} // namespace hb
