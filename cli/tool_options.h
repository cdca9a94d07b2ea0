#pragma once
// The tool options the commands share (--tool SPEC and the slides it is judged and timed on),
// and the tool section of `bench` and `eval`: the slides, both answers on every tick, the
// times (docs/tools.md).
#include "contact/workspace.h"
#include "evaluation/comparison.h"
#include "evaluation/tool_ticks.h"
#include "tool/tool_shape.h"
#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>
#include <string>

namespace hb {
class BoxScene;
class ExactQuery;
}

namespace hb::cli {

struct ToolArgs {
  std::string spec;              ///< --tool; empty: no tool.
  std::size_t slides = 20;       ///< --tool-slides
  std::size_t ticks = 250;       ///< --tool-ticks (a slide)
  double depth_mm = 0.5;         ///< --tool-depth-mm
  double speed_mm_s = 30.0;      ///< --tool-speed (mm/s)
  std::uint64_t seed = 1;
  bool given() const { return !spec.empty(); }
  ToolSlideOptions slide_options() const;
};

/// Adds --tool SPEC and the slide options to a command.
void add_tool_options(CLI::App& cmd, ToolArgs& args);

/// The tool of a spec, a mesh tool read by the product's readers (every format).
ToolShape load_tool(const std::string& spec);

/// What `bench --tool` and `eval --tool` measure of a tool on a scene against exact.
struct ToolRun {
  ToolShape tool;
  std::vector<std::vector<ToolPose>> slides;
  ToolTickStats box;                 ///< the scene against exact.
  ToolTickTiming box_time, exact_stream_time, exact_single_time;
  bool timed = false;
  /// The distance-field peer (peers/sdf_peer.h) at the box file's memory, when asked for.
  bool peer = false;
  ToolTickStats sdf;
  ToolTickTiming sdf_time;
  double sdf_memory_bytes = 0, sdf_voxel_mm = 0, sdf_build_s = 0;
  const ToolTickTiming& exact_time() const {
    return exact_single_time.p99_us < exact_stream_time.p99_us ? exact_single_time : exact_stream_time;
  }
  const char* exact_api() const { return exact_single_time.p99_us < exact_stream_time.p99_us ? "single rays" : "ray stream"; }
};

/// Slides on `mesh`, both answers on every tick; with `time`, every tick timed on one core
/// (the box, exact's ray stream and its single rays, `rounds` times each). With
/// `peer_memory_bytes` > 0, the distance-field peer built at that memory (its field 1 mm deep
/// inside at the device) is judged and, with `time`, timed on the same ticks.
ToolRun run_tool(const ToolArgs& args, const BoxScene& scene, const ExactQuery& exact, const TriangleMesh& mesh,
                 const Workspace& workspace, const PerceptualJudge& judge, bool time, int rounds,
                 std::size_t peer_memory_bytes = 0);

/// The JSON of a tool run (the keys `bench --tool --json` documents).
nlohmann::json tool_json(const ToolRun& run);
/// The text of a tool run.
void print_tool_run(const ToolRun& run, std::ostream& out);

} // namespace hb::cli
