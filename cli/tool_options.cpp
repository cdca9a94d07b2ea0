#include "tool_options.h"
#include "figure_text.h"
#include "model_args.h"
#include "exact/exact_query.h"
#include "scene/box_scene.h"
#include "tool/tool_spec.h"
#include "peers/sdf_peer.h"
#include <chrono>
#include <iomanip>
#include <ostream>

namespace hb::cli {

ToolSlideOptions ToolArgs::slide_options() const {
  ToolSlideOptions o;
  o.slides = slides;
  o.ticks = ticks;
  o.depth_m = depth_mm * 1e-3;
  o.speed_m_per_s = speed_mm_s * 1e-3;
  o.seed = seed;
  return o;
}

void add_tool_options(CLI::App& cmd, ToolArgs& args) {
  cmd.add_option("--tool", args.spec,
                 "A tool with volume: sphere,radius-mm=R,points=N | capsule,radius-mm=R,length-mm=L,points=N | "
                 "mesh=FILE,points=N[,margin-mm=M] (device millimetres at the workspace)");
  cmd.add_option("--tool-slides", args.slides, "Slides the tool is judged and timed on")
      ->check(CLI::Range(1, 10000))
      ->capture_default_str();
  cmd.add_option("--tool-ticks", args.ticks, "Ticks a slide (1 ms each)")->check(CLI::Range(1, 100000))->capture_default_str();
  cmd.add_option("--tool-depth-mm", args.depth_mm, "Depth a slide holds, device mm")
      ->check(CLI::Range(0.001, 10.0))
      ->capture_default_str();
  cmd.add_option("--tool-speed", args.speed_mm_s, "Gliding speed of a slide, device mm/s")
      ->check(CLI::Range(0.1, 1000.0))
      ->capture_default_str();
}

ToolShape load_tool(const std::string& spec) {
  return make_tool(parse_tool_spec(spec), [](const std::string& path) { return load_mesh(path); });
}

ToolRun run_tool(const ToolArgs& args, const BoxScene& scene, const ExactQuery& exact, const TriangleMesh& mesh,
                 const Workspace& workspace, const PerceptualJudge& judge, bool time, int rounds,
                 std::size_t peer_memory_bytes) {
  ToolRun run;
  run.tool = load_tool(args.spec);
  run.slides = tool_slides(mesh, exact, run.tool, workspace, args.slide_options());
  run.box = compare_tool_ticks(scene, exact, run.tool, run.slides, workspace, judge.thresholds);
  if (time) {
    run.timed = true;
    const OneAtATime single(exact);
    run.box_time = time_tool_ticks(scene, run.tool, run.slides, workspace, rounds);
    run.exact_stream_time = time_tool_ticks(exact, run.tool, run.slides, workspace, rounds);
    run.exact_single_time = time_tool_ticks(single, run.tool, run.slides, workspace, rounds);
  }
  if (peer_memory_bytes > 0) {
    SdfPeerOptions o;
    o.memory_bytes = peer_memory_bytes;
    o.inside_depth = 1e-3 / workspace.metres_per_unit;
    const auto t0 = std::chrono::steady_clock::now();
    const SdfPeer sdf(mesh, o);
    run.sdf_build_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    run.peer = true;
    run.sdf_memory_bytes = double(sdf.memory_bytes());
    run.sdf_voxel_mm = sdf.voxel() * workspace.metres_per_unit * 1e3;
    run.sdf = compare_tool_ticks(sdf, exact, run.tool, run.slides, workspace, judge.thresholds);
    if (time) run.sdf_time = time_tool_ticks(sdf, run.tool, run.slides, workspace, rounds);
  }
  return run;
}

nlohmann::json tool_json(const ToolRun& run) {
  nlohmann::json j = {{"tool", run.tool.spec},
                      {"tool_points", run.tool.size()},
                      {"tool_ticks", run.box.ticks},
                      {"tool_contact_ticks", run.box.contact_ticks},
                      {"tool_mean_contacts", run.box.mean_contacts},
                      {"tool_perceptible_tick_share", run.box.perceptible_share()},
                      {"tool_perceptible_ticks", run.box.perceptible_ticks},
                      {"tool_force_felt_ticks", run.box.force_felt},
                      {"tool_torque_felt_ticks", run.box.torque_felt},
                      {"tool_max_force_error_n", run.box.max_force_error_n},
                      {"tool_mean_force_error_n", run.box.mean_force_error_n},
                      {"tool_max_torque_error_nm", run.box.max_torque_error_nm},
                      {"box_tool_jumps", run.box.box_jumps},
                      {"exact_tool_jumps", run.box.exact_jumps}};
  if (run.timed) {
    j["box_tool_tick_p50_us"] = run.box_time.p50_us;
    j["box_tool_tick_p99_us"] = run.box_time.p99_us;
    j["exact_tool_tick_p50_us"] = run.exact_time().p50_us;
    j["exact_tool_tick_p99_us"] = run.exact_time().p99_us;
    j["exact_tool_api"] = run.exact_api();
    j["exact_stream_tool_tick_p99_us"] = run.exact_stream_time.p99_us;
    j["exact_single_tool_tick_p99_us"] = run.exact_single_time.p99_us;
  }
  if (run.peer) {
    j["sdf_perceptible_tick_share"] = run.sdf.perceptible_share();
    j["sdf_max_force_error_n"] = run.sdf.max_force_error_n;
    j["sdf_jumps"] = run.sdf.box_jumps;
    j["sdf_memory_bytes"] = run.sdf_memory_bytes;
    j["sdf_voxel_mm"] = run.sdf_voxel_mm;
    j["sdf_build_s"] = run.sdf_build_s;
    if (run.timed) {
      j["sdf_tool_tick_p50_us"] = run.sdf_time.p50_us;
      j["sdf_tool_tick_p99_us"] = run.sdf_time.p99_us;
    }
  }
  return j;
}

void print_tool_run(const ToolRun& run, std::ostream& out) {
  const ToolTickStats& s = run.box;
  out << "tool: " << describe_tool(run.tool) << "\n"
      << "  slides      " << run.slides.size() << " slides, " << s.ticks << " ticks (1 ms each), " << s.contact_ticks
      << " in contact, " << std::fixed << std::setprecision(1) << s.mean_contacts << " points touching a tick\n"
      << "  accuracy    " << percent(s.perceptible_share()) << " of contact ticks perceptibly different from exact ("
      << s.force_felt << " by the net force, " << s.torque_felt << " by the torque); force error mean "
      << std::setprecision(4) << s.mean_force_error_n << " N, max " << s.max_force_error_n << " N\n"
      << "  jumps       tick-to-tick force changes beyond the thresholds: box " << s.box_jumps << ", exact "
      << s.exact_jumps << "\n";
  if (run.timed) {
    const ToolTickTiming& e = run.exact_time();
    out << std::setprecision(1) << "  tick time   box p50 " << run.box_time.p50_us << " us, p99 " << run.box_time.p99_us
        << " us; exact (" << run.exact_api() << ", its faster API here) p50 " << e.p50_us << " us, p99 " << e.p99_us
        << " us (the other: p99 "
        << (&e == &run.exact_stream_time ? run.exact_single_time.p99_us : run.exact_stream_time.p99_us) << " us)\n"
        << "  verdict     at p99 the box is " << speed_verdict(run.box_time.p99_us, e.p99_us) << "; at p50 "
        << speed_verdict(run.box_time.p50_us, e.p50_us) << "\n";
  }
  if (run.peer) {
    out << std::setprecision(3) << "  peer        a signed distance field (OpenVDB, voxel " << run.sdf_voxel_mm << " mm at the device, "
        << bytes_text(std::uint64_t(run.sdf_memory_bytes)) << ", built in " << run.sdf_build_s << " s): "
        << percent(run.sdf.perceptible_share()) << " of contact ticks perceptibly different from exact, force error max "
        << run.sdf.max_force_error_n << " N, jumps " << run.sdf.box_jumps;
    if (run.timed)
      out << std::setprecision(1) << "; tick p50 " << run.sdf_time.p50_us << " us, p99 " << run.sdf_time.p99_us
          << " us (the box's p99 over the field's: " << std::setprecision(2)
          << (run.sdf_time.p99_us > 0 ? run.box_time.p99_us / run.sdf_time.p99_us : 0.0) << ")";
    out << "\n";
  }
}

} // namespace hb::cli
