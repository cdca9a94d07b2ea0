// hapticbox sweep MESH [--m 8,16,32,64] [--n 4,8,16] [--codec none] [--refine] [--pieces none|auto|FILE] [--samples N]
//                 [--no-default-bake] [--json]
// Speed against accuracy: every configuration baked (or taken from the cache), evaluated and
// timed on the same probes next to exact Embree and VTK's vtkStaticCellLocator, and the
// default (budgeted) bake the product recommends.
#include "cli_support.h"
#include "recipe/box_cache.h"
#include "commands.h"
#include "errors.h"
#include "recipe/sweep.h"
#include "figure_text.h"
#include "perceptible_text.h"
#include "exact/exact_query.h"
#include "mesh/mesh_io.h"
#include "pieces_option.h"
#include "report_charts.h"
#include "vtkHapticBoxReferenceQueries.h"
#include <algorithm>
#include <cstdio>
#include <iomanip>
#include <iostream>

namespace {

void print_row(const hb::SweepRow& r, bool pareto_known) {
  char line[256];
  const bool box = r.method == "haptic_box";
  const std::string codec = r.codec + (r.refine ? "+ref" : "");
  // A row that is not one (m, n) configuration (the default bake) says what it is at the end.
  const bool one_config = box && r.label.empty();
  std::snprintf(line, sizeof line, "%-24s %4s %4s %-10s %10.1f %12.2f %9.3f%s %8.3f %9.2f %9.2f %9.2f %6s %s%s%s",
                r.method.c_str(), one_config ? std::to_string(r.m).c_str() : "-", one_config ? std::to_string(r.n).c_str() : "-",
                box ? codec.c_str() : "-", r.query_ns, double(r.memory_bytes) / (1024.0 * 1024.0), r.bake_seconds,
                r.from_cache ? "c" : " ", 100.0 * r.perceptible_share, 100.0 * r.force_error_median, 100.0 * r.force_error_p95,
                100.0 * r.contact_agreement, r.within_budget ? "yes" : "-", pareto_known ? (r.pareto ? "*" : "") : "",
                r.label.empty() ? "" : "  ",
                r.label.c_str());
  std::cout << line << std::endl;
}

void print_header() {
  std::cout << "method                      m    n codec        query_ns   memory_MiB   bake_s   felt_%  median_%    p95_%  agree_% budget pareto\n";
}

} // namespace

void add_sweep_command(CLI::App& app) {
  auto* cmd = app.add_subcommand("sweep", "Speed against accuracy over box configurations, with exact and VTK references");
  struct Opts {
    hb::cli::ModelArgs model;
    std::string mesh;
    std::vector<int> m{8, 16, 32, 64};
    std::vector<int> n{4, 8, 16};
    std::vector<std::string> codecs{"none"};
    bool refine = false;
    hb::cli::PiecesArgs pieces;
    std::string cache;
    std::string chart;
    hb::SweepOptions sweep;
    hb::cli::WorkspaceArgs workspace;
    bool json = false;
    bool no_default_bake = false;
  };
  auto opts = std::make_shared<Opts>();
  hb::cli::add_model_options(*cmd, opts->model);
  cmd->add_option("MESH", opts->mesh, "Mesh file")->required();
  cmd->add_option("-m,--m", opts->m, "Position densities m (comma separated)")->delimiter(',')->check(CLI::Range(2, 4096))->capture_default_str();
  cmd->add_option("-n,--n", opts->n, "Directional densities n (comma separated)")->delimiter(',')->check(CLI::Range(2, 1024))->capture_default_str();
  cmd->add_option("--codec", opts->codecs, "Table codecs (comma separated: none, haar, block)")->delimiter(',')->capture_default_str();
  hb::cli::add_pieces_options(*cmd, opts->pieces);
  cmd->add_flag("--refine", opts->refine,
                "Also measure every configuration refined exactly on the mesh's triangles (codec+ref rows)");
  hb::cli::add_probe_options(*cmd, opts->sweep.samples, opts->sweep.probes.seed);
  cmd->add_option("--rounds", opts->sweep.timing_rounds, "Timing passes")->check(CLI::Range(1, 1000))->capture_default_str();
  hb::cli::add_cache_option(*cmd, opts->cache);
  cmd->add_flag("--no-default-bake", opts->no_default_bake,
                "Leave out the row of the default bake (`bake MESH -o BOX` with no option: the budgeted bake the "
                "product recommends), which is measured after the configurations otherwise");
  cmd->add_option("--chart", opts->chart, "Also write the speed-vs-accuracy chart (PNG)");
  hb::cli::add_workspace_options(*cmd, opts->workspace);
  cmd->add_flag("--json", opts->json, "Print JSON");
  cmd->callback([opts] {
    for (const std::string& c : opts->codecs) {
      try {
        hb::check_sweep_config({2, 2, c});
      } catch (const hb::InvalidInput& e) {
        throw hb::cli::UsageError(std::string("--codec: ") + e.what());
      }
    }
    hb::MeshReadReport read;
    const hb::TriangleMesh mesh = hb::cli::load_mesh(opts->mesh, opts->model, &read);
    hb::SourceInfo source;
    source.mesh_path = opts->mesh;
    source.mesh_hash = hb::cli::hash_model(opts->mesh, opts->model);
    source.triangles = mesh.triangle_count();
    source.diagonal = mesh.bounds().diagonal();
    const vtkHapticBoxReferenceQueries refs(mesh);
    hb::SweepOptions& so = opts->sweep;
    const hb::Workspace ws = opts->workspace.workspace(source.diagonal);
    so.law = ws.law();
    so.judge = opts->workspace.judge();
    so.configs = hb::sweep_grid(opts->m, opts->n, opts->codecs,
                                opts->refine ? std::vector<bool>{false, true} : std::vector<bool>{false});
    so.cache_dir = opts->cache;
    so.default_bake = !opts->no_default_bake;
    so.progress = hb::cli::terminal_progress("sweep");
    if (!opts->json) {
      std::cout << "sweep " << opts->mesh << " (" << mesh.triangle_count() << " triangles, " << so.samples
                << " probes, seed " << so.probes.seed << ", one core for timing)\n  workspace: " << ws.describe()
                << "; felt_%: probes perceptibly different from exact (" << hb::thresholds_text(so.judge.thresholds)
                << ")\n";
      print_header();
      so.on_row = [](const hb::SweepRow& r) {
        hb::cli::clear_progress_line();  // a row of its own, not after the bar
        print_row(r, false);
        std::cout.flush();
      };
    }
    opts->pieces.apply_tuning(so.recipe);
    hb::cli::apply_pieces_spec(opts->pieces.spec, so.recipe);
    hb::Communicator& comm = hb::cli::communicator();
    std::vector<hb::RankWork> work;
    so.communicator = &comm;  // every configuration's bake and evaluation shared by the ranks
    so.rank_work = &work;
    std::vector<hb::SweepRow> rows = hb::run_sweep(mesh, source, refs.References(), so);
    if (!comm.is_root()) return;
    if (!opts->chart.empty()) hb::plot_speed_accuracy(rows, opts->chart);
    double busiest = 0, mean = 0;
    for (const hb::RankWork& w : work) {
      busiest = std::max(busiest, w.seconds);
      mean += w.seconds / double(work.size());
    }
    if (opts->json) {
      nlohmann::json j = {{"mesh", opts->mesh}, {"triangles", mesh.triangle_count()}, {"samples", so.samples},
                          {"seed", so.probes.seed}, {"rows", nlohmann::json::array()},
                          {"workspace", hb::workspace_json(ws, so.judge)},
                          {"load_balance", mean > 0 ? busiest / mean : 1.0}, {"rank_work", nlohmann::json::array()}};
      for (const hb::RankWork& w : work)
        j["rank_work"].push_back({{"rank", w.rank}, {"work", w.work}, {"seconds", w.seconds}, {"bytes_sent", w.bytes_sent}});
      for (const hb::SweepRow& r : rows)
        j["rows"].push_back({{"method", r.method}, {"label", r.label}, {"m", r.m}, {"n", r.n}, {"codec", r.codec},
                             {"refine", r.refine}, {"query_ns", r.query_ns}, {"memory_bytes", r.memory_bytes},
                             {"bake_seconds", r.bake_seconds}, {"from_cache", r.from_cache},
                             {"force_error_median", r.force_error_median}, {"force_error_p95", r.force_error_p95},
                             {"contact_agreement", r.contact_agreement}, {"angle_error_p99_deg", r.angle_error_p99_deg},
                             {"perceptible_share", r.perceptible_share},
                             {"within_budget", r.within_budget}, {"pareto", r.pareto}});
      hb::cli::print_json(j);
      return;
    }
    std::cout << "\nPareto front (no configuration both faster and more accurate), fastest first:\n";
    print_header();
    std::vector<hb::SweepRow> front;
    for (const hb::SweepRow& r : rows)
      if (r.pareto) front.push_back(r);
    std::sort(front.begin(), front.end(), [](const hb::SweepRow& a, const hb::SweepRow& b) { return a.query_ns < b.query_ns; });
    for (const hb::SweepRow& r : front) print_row(r, true);
    std::cout << "(c: box from the cache; memory of references: mesh arrays and index, not Embree's BVH; budget: "
              << hb::budget_spec(so.budget) << ")\n";
    // The cheapest configuration that models no more than the budget asks, against exact.
    if (const hb::SweepRow* best = hb::fastest_within_budget(rows)) {
      std::cout << "fastest within the budget: " << hb::configuration_name(*best) << ", " << hb::sig(best->query_ns) << " ns a query against exact's "
                << hb::sig(rows.front().query_ns) << " ns: " << hb::speed_verdict(best->query_ns, rows.front().query_ns)
                << "\n";
    } else {
      std::cout << "fastest within the budget: no box configuration meets it\n";
    }
    if (comm.size() > 1) {
      std::cout << comm.size() << " ranks, busy seconds per rank:";
      for (const hb::RankWork& w : work) std::cout << " " << w.seconds;
      std::cout << " (busiest " << busiest / mean << " x the mean)\n";
    }
  });
}
