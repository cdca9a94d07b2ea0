// hapticbox stability BOX MESH [--json] [--device falcon|touch] [--tests T1,...] ...
// The trajectory stability suite (src/evaluation/stability_suite.h) with the servo's own
// force path (hb::device: energy guard and safety) as the filter of T6 and T8.
#include "cli_support.h"
#include "commands.h"
#include "device/safety_tick_filter.h"
#include "stability/stability_suite.h"
#include "stability/tool_stability.h"
#include "exact/exact_query.h"
#include "recipe/bake_recipe.h"
#include "tool_options.h"
#include "store/box_file.h"
#include "mesh/mesh_io.h"
#include "stability_json.h"
#include <cmath>
#include <cstdio>
#include <iostream>

namespace {

std::string figure(double v) {
  if (std::isnan(v)) return "-";
  char b[32];
  if (v != 0 && (std::fabs(v) < 1e-3 || std::fabs(v) >= 1e5)) std::snprintf(b, sizeof b, "%.3g", v);
  else std::snprintf(b, sizeof b, "%.4f", v);
  return b;
}

const char* rule_text(hb::StabilityRule r) {
  switch (r) {
    case hb::StabilityRule::at_most: return "<=";
    case hb::StabilityRule::at_least: return ">=";
    case hb::StabilityRule::within: return "=";
    case hb::StabilityRule::difference_at_most: return "diff <=";
    case hb::StabilityRule::info: return "";
  }
  return "?";
}

void print_table(const std::vector<hb::StabilityMetric>& ms) {
  std::printf("  %-5s %-28s %-72s %10s %10s %10s %14s  %s\n", "test", "scene", "metric", "box", "exact", "diff",
              "threshold", "verdict");
  for (const auto& m : ms) {
    std::string thr = m.rule == hb::StabilityRule::info ? "-" : std::string(rule_text(m.rule)) + " " + figure(m.threshold);
    if (m.rule == hb::StabilityRule::within) thr += " +- " + figure(m.tolerance);
    std::string name = m.metric + (m.unit.empty() ? "" : " [" + m.unit + "]");
    std::printf("  %-5s %-28s %-72s %10s %10s %10s %14s  %s\n", m.test.c_str(), m.scene.c_str(), name.c_str(),
                figure(m.box).c_str(), figure(m.exact).c_str(),
                std::isnan(m.exact) ? "-" : figure(m.difference()).c_str(), thr.c_str(), m.verdict.c_str());
  }
}

} // namespace

hb::StabilityReport hb::cli::default_stability(const hb::BoxScene& scene, const hb::TriangleMesh& mesh,
                                               const std::string& model_name, std::size_t sites) {
  hb::StabilityOptions so = hb::default_stability_options(scene, model_name, sites);
  hb::use_servo_force_path(so.filter, so.filter_name, so.device);
  return hb::run_stability_suite(scene, mesh, so);
}

// The tool suite (evaluation/tool_stability.h): the table, then the verdict last.
void run_tool_suite(const hb::BoxScene& scene, const hb::TriangleMesh& mesh, const std::string& box_path,
                    const std::string& mesh_path, const std::string& spec, std::uint64_t seed, bool json, bool strict) {
  const hb::ToolShape tool = hb::cli::load_tool(spec);
  const hb::ExactQuery exact(mesh);
  const hb::Workspace ws = hb::make_workspace(mesh.bounds().diagonal());
  hb::ToolStabilityOptions so;
  so.seed = seed;
  so.bake_object = [](const hb::TriangleMesh& m) { return hb::bake(m, hb::default_recipe()).scene; };
  const auto results = hb::run_tool_stability(scene, exact, mesh, tool, ws, hb::PerceptualThresholds{}, so);
  std::size_t passed = 0, box_only = 0;
  for (std::size_t i = 0; i + 1 < results.size(); i += 2) {
    passed += results[i].pass + results[i + 1].pass;
    box_only += !results[i].pass && results[i + 1].pass;
  }
  if (json) {
    nlohmann::json j = {{"box", box_path}, {"mesh", mesh_path}, {"tool", tool.spec}, {"tool_points", tool.size()},
                        {"workspace", ws.describe()}, {"passed", passed}, {"failed", results.size() - passed},
                        {"box_failed_where_exact_passed", box_only}};
    for (const auto& r : results)
      j["tests"].push_back({{"test", r.test}, {"method", r.method}, {"pass", r.pass}, {"criterion", r.criterion},
                            {"ticks", r.ticks}, {"pop_throughs", r.pop_throughs}, {"ghost_ticks", r.ghost_ticks},
                            {"jumps", r.jumps}, {"max_force_n", r.max_force_n}, {r.figure_name, r.figure}});
    hb::cli::print_json(j);
  } else {
    std::printf("stability %s vs %s, tool %s, %s\n", box_path.c_str(), mesh_path.c_str(),
                hb::describe_tool(tool).c_str(), ws.describe().c_str());
    std::printf("  %-14s %-6s %7s %5s %6s %6s %9s  %-28s %10s  %s\n", "test", "method", "ticks", "pops", "ghosts",
                "jumps", "max F (N)", "figure", "value", "verdict");
    for (const auto& r : results)
      std::printf("  %-14s %-6s %7zu %5zu %6zu %6zu %9.3f  %-28s %10s  %s\n", r.test.c_str(), r.method.c_str(),
                  r.ticks, r.pop_throughs, r.ghost_ticks, r.jumps, r.max_force_n, r.figure_name.c_str(),
                  figure(r.figure).c_str(), r.pass ? "pass" : "FAIL");
    std::printf("criteria:\n");
    for (std::size_t i = 0; i < results.size(); i += 2)
      std::printf("  %-14s %s\n", results[i].test.c_str(), results[i].criterion.c_str());
    std::printf("verdict: %zu of %zu pass; %zu failed by the box where exact passed\n", passed, results.size(),
                box_only);
  }
  if (strict && box_only > 0) throw std::runtime_error("stability: a tool test failed because of the box (--strict)");
}

void add_stability_command(CLI::App& app) {
  auto* cmd = app.add_subcommand("stability",
                                 "Trajectory stability suite: box and exact side by side (calibration gate, T1-T8)");
  struct Opts {
    std::string box, mesh, device = "falcon", tests, safety = "hold", depth = "normal",
                law = "penalty", route = "auto", tool;
    std::size_t sites = 12;
    std::uint64_t seed = 1;
    bool json = false, no_generated = false, energy_guard = false, strict = false;
    hb::cli::ModelArgs model;
  };
  auto o = std::make_shared<Opts>();
  hb::cli::add_model_options(*cmd, o->model);
  cmd->add_option("BOX", o->box, "Box file (.hbox)")->required();
  cmd->add_option("MESH", o->mesh, "The mesh the box was baked from")->required();
  cmd->add_option("--device", o->device, "Device profile: falcon (8 N, 3000 N/m) or touch (3.3 N, 400 N/m)")
      ->check(CLI::IsMember({"falcon", "touch"}))
      ->capture_default_str();
  cmd->add_option("--tests", o->tests, "Comma-separated tests to run (T1..T8; default all)");
  cmd->add_option("--sites", o->sites, "Trajectories per test on the model")
      ->check(CLI::Range(std::size_t(1), std::size_t(1000)))
      ->capture_default_str();
  cmd->add_option("--seed", o->seed, "Site seed")->capture_default_str();
  cmd->add_flag("--energy-guard", o->energy_guard, "Switch the passivity observer / controller on in T6/T8");
  cmd->add_option("--law", o->law,
                  "How answers become forces along a trajectory: penalty (default: the depth law on each answer) "
                  "or proxy (a god-object over the same answerer, box and exact alike)")
      ->check(CLI::IsMember({"penalty", "proxy"}))
      ->capture_default_str();
  cmd->add_flag_callback("--proxy", [o] { o->law = "proxy"; }, "Same as --law proxy");
  hb::cli::add_route_option(*cmd, o->route);
  cmd->add_flag("--no-generated", o->no_generated, "Skip the generated walls, plates and grooves");
  cmd->add_flag("--strict", o->strict, "Exit 1 when a test fails because of the box (not the law)");
  cmd->add_flag("--json", o->json, "Print JSON");
  cmd->add_option("--tool", o->tool,
                  "Run the tool suite instead: a tool with volume (sphere,radius-mm=R,points=N | capsule,... | "
                  "mesh=FILE,points=N) through its virtual coupling, box and exact side by side");
  cmd->callback([o] {
    // Measurement-only (HB_MEASURE): safety=hold|zero|none (the servo's fault response in T6/T8:
    // hold and ramp, zero and ramp, no safety filter) and depth-law=normal|along (the paper's
    // eq. 2).
    o->safety = hb::cli::measurement_choice("safety", "hold", {"hold", "zero", "none"});
    o->depth = hb::cli::measurement_choice("depth-law", "normal", {"normal", "along"});
    hb::BoxScene scene = hb::load_box_file(o->box);
    const hb::TriangleMesh mesh = hb::cli::load_mesh(o->mesh, o->model);
    hb::Communicator& comm = hb::cli::communicator();
    if (comm.is_root() && scene.parts().source.mesh_hash != 0 && scene.parts().source.mesh_hash != hb::cli::hash_model(o->mesh, o->model))
      std::cerr << "hapticbox: warning: " << o->box << " was baked from a different file than " << o->mesh << "\n";
    hb::cli::apply_route(scene, o->route);  // the generated walls, plates and grooves take the same route
    if (!o->tool.empty()) return run_tool_suite(scene, mesh, o->box, o->mesh, o->tool, o->seed, o->json, o->strict);
    hb::StabilityOptions so;
    so.device = hb::device_profile(o->device);
    so.sites = o->sites;
    so.seed = o->seed;
    so.depth_law = o->depth == "along" ? hb::DepthLaw::along_segment : hb::DepthLaw::normal;
    so.contact_law = hb::contact_law(o->law);
    so.generated = !o->no_generated;
    so.generated_refine = scene.refines();
    so.model_name = o->mesh.substr(o->mesh.find_last_of('/') + 1);
    for (std::size_t a = 0; a < o->tests.size();) {
      const std::size_t b = std::min(o->tests.find(',', a), o->tests.size());
      if (b > a) so.tests.push_back(o->tests.substr(a, b - a));
      a = b + 1;
    }
    for (const auto& t : so.tests)
      if (t.size() != 2 || t[0] != 'T' || t[1] < '1' || t[1] > '8')
        throw hb::cli::UsageError("--tests: '" + t + "' is not a test (T1 .. T8)");
    if (o->safety != "none") {
      so.filter = hb::safety_tick_filter_factory(
          so.device, o->safety == "zero" ? hb::FaultResponse::zero_and_ramp : hb::FaultResponse::hold_and_ramp,
          o->energy_guard);
      so.filter_name = std::string("safety ") + (o->safety == "zero" ? "zero-and-ramp" : "hold-and-ramp") +
                       (o->energy_guard ? " + energy guard" : "");
    } else if (o->energy_guard) {
      throw hb::cli::UsageError("--energy-guard needs the safety filter (not HB_MEASURE safety=none)");
    }
    so.communicator = &comm;  // the tasks (gate, each test on each scene) dealt across the ranks of an MPI job
    const hb::StabilityReport rep = hb::run_stability_suite(scene, mesh, so);
    bool box_failed = false;
    for (const auto& m : rep.metrics) box_failed |= !m.pass && m.exact_pass;
    if (o->json) {
      nlohmann::json j = hb::stability_json(rep);
      j["box"] = o->box;
      j["mesh"] = o->mesh;
      j["route"] = hb::route_name(scene.route());
      j["contact_law"] = rep.contact_law;
      hb::cli::print_json(j);
    } else if (comm.is_root()) {
      std::printf("stability %s vs %s: device %s, contact law %s, depth law %s, route %s, T6/T8 filter: %s\n",
                  o->box.c_str(), o->mesh.c_str(), rep.device.c_str(), rep.contact_law.c_str(), rep.depth_law.c_str(),
                  hb::route_name(scene.route()), rep.filter.c_str());
      print_table(rep.calibration);
      print_table(rep.metrics);
      // The verdict last, where a reader of the output looks for it.
      std::printf("calibration gate: %s\n", rep.calibration_pass ? "pass" : "FAIL (the harness is wrong)");
      std::printf("tests: %zu pass, %zu fail (%zu of them exact fails too: the law, not the box), %.1f s\n",
                  rep.passed, rep.failed, rep.failed_law, rep.seconds);
    }
    if (!rep.calibration_pass) throw std::runtime_error("stability: the calibration gate failed");
    if (o->strict && box_failed) throw std::runtime_error("stability: a test failed because of the box (--strict)");
  });
}
