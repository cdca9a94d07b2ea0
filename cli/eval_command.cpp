// hapticbox eval BOX MESH [--samples N] [--seed S] [--json] [workspace options]
#include "cli_support.h"
#include "commands.h"
#include "tool_options.h"
#include "eval_json.h"
#include "figure_text.h"
#include "perceptible_text.h"
#include "evaluation/comparison.h"
#include "evaluation/probe_sampling.h"
#include "exact/exact_query.h"
#include "store/box_file.h"
#include "mesh/mesh_io.h"
#include <iomanip>
#include <optional>
#include <iostream>

void add_eval_command(CLI::App& app) {
  auto* cmd = app.add_subcommand("eval", "Compare a box file against the exact answer on its mesh");
  struct Opts {
    hb::cli::ModelArgs model;
    std::string box, mesh;
    std::size_t samples = 20000;
    hb::ProbeOptions probes;
    hb::cli::WorkspaceArgs workspace;
    bool json = false;
    bool force = false;
    std::string route = "auto";
    hb::cli::ToolArgs tool;
  };
  auto opts = std::make_shared<Opts>();
  hb::cli::add_model_options(*cmd, opts->model);
  cmd->add_option("BOX", opts->box, "Box file (.hbox)")->required();
  cmd->add_option("MESH", opts->mesh, "The mesh the box was baked from")->required();
  hb::cli::add_probe_options(*cmd, opts->samples, opts->probes.seed);
  hb::cli::add_workspace_options(*cmd, opts->workspace);
  cmd->add_flag("--json", opts->json, "Print JSON");
  cmd->add_flag("--force", opts->force, "Evaluate even when the box was baked from a different mesh (its hash differs)");
  hb::cli::add_route_option(*cmd, opts->route);
  hb::cli::add_tool_options(*cmd, opts->tool);
  cmd->callback([opts] {
    hb::BoxScene scene = hb::load_box_file(opts->box);
    hb::cli::apply_route(scene, opts->route);
    const hb::TriangleMesh mesh = hb::cli::load_mesh(opts->mesh, opts->model);
    hb::cli::check_same_mesh(scene, opts->box, opts->mesh, hb::cli::hash_model(opts->mesh, opts->model), opts->force);
    const hb::ExactQuery exact(mesh);
    const auto probes = hb::sample_probes(mesh, opts->samples, opts->probes);
    const float diag = mesh.bounds().diagonal();
    const hb::Workspace ws = opts->workspace.workspace(diag);
    const hb::PerceptualJudge judge = opts->workspace.judge();
    // Probes dealt across the ranks of an MPI job; the figures are one process's.
    const hb::ComparisonStats s = hb::compare_queries(scene, exact, probes, ws.law(), diag, nullptr,
                                                      &hb::cli::communicator(), nullptr, judge);
    // The same count of light touches at any angle: its perceptible share, a second figure.
    const hb::ComparisonStats light = hb::compare_light_touches(scene, exact, mesh, opts->samples, opts->probes.seed,
                                                                ws.law(), diag, &hb::cli::communicator(), judge);
    nlohmann::json j = hb::eval_json(s, opts->box, opts->mesh, opts->probes.seed, answerer_name(answerer(scene)));
    j["workspace"] = hb::workspace_json(ws, judge);
    j["light_touch"] = hb::light_touch_json(light);
    // A tool with volume: its net force and torque along slides, tick by tick.
    std::optional<hb::cli::ToolRun> tool;
    if (opts->tool.given()) {
      tool = hb::cli::run_tool(opts->tool, scene, exact, mesh, ws, judge, false, 1);
      j["tool"] = hb::cli::tool_json(*tool);
    }
    if (opts->json) {
      hb::cli::print_json(j);
      return;
    }
    std::cout << "eval " << opts->box << " vs " << opts->mesh << " (" << s.samples << " probes, seed "
              << opts->probes.seed << ", route " << answerer_name(answerer(scene)) << ")\n"
              << "  workspace           " << ws.describe() << "\n"
              << hb::perceptible_lines(s)
              << "  contact agreement   " << hb::agreement_percent(s.contact_agreement) << "  (false "
              << s.false_contacts << ", missed " << s.missed_contacts << ", exact contacts " << s.exact_contacts << ")\n"
              << "  force error         median " << hb::percent(s.force_error_median) << ", p95 "
              << hb::percent(s.force_error_p95) << ", max " << hb::percent(s.force_error_max) << "\n"
              << "  direction error     median " << hb::sig(s.angle_error_median_deg) << " deg, p99 "
              << hb::sig(s.angle_error_p99_deg) << " deg\n"
              << "  depth RMS / diag    " << hb::sig(s.depth_rms_over_diag) << "\n"
              << "  light touch, any angle (" << hb::light_touch_words() << "): " << hb::perceptible_headline(light)
              << "\n";
    if (tool) hb::cli::print_tool_run(*tool, std::cout);
  });
}
