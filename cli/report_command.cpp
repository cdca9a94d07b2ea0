// hapticbox report MESH|BOX [MESH] -o DIR [--m M --n N] [--samples N] [--seed S] ...
// From a MESH the report bakes the default (budgeted) bake through the box cache, or with -m / -n
// one raw box of exactly that sampling.
// Writes DIR/report.html (self-contained), DIR/summary.json and DIR/samples.csv. Runs with no
// display: the error-field image is rendered only when an X display opens (noted otherwise).
#include "cli_support.h"
#include "recipe/box_cache.h"
#include "commands.h"
#include "errors.h"
#include "recipe/bake_recipe.h"
#include "store/box_file.h"
#include "mesh/mesh_io.h"
#include "figure_text.h"
#include "report_request.h"
#include "summary_text.h"
#include "vtkHapticBoxErrorFieldImage.h"
#include "vtkHapticBoxReferenceQueries.h"
#include <chrono>
#include <filesystem>
#include <iostream>
#include <optional>
#include <sstream>

namespace {

struct ReportOpts {
  hb::cli::ModelArgs model;
  std::vector<std::string> inputs;
  std::string out;
  hb::BoxParams params;
  hb::ReportOptions report;
  hb::cli::WorkspaceArgs workspace;
  std::vector<int> sweep_m, sweep_n;
  bool no_sweep = false;
  std::string cache;
  bool no_image = false;
  bool stability = false;
  bool force = false;
  std::string save_box;
};

// report's --sweep: "none", or m=A/B/C,n=D/E (the extra configurations' densities).
void parse_sweep_spec(ReportOpts& o, const std::string& spec) {
  const auto list = [](std::vector<int>& out, int hi) {
    return [&out, hi](const std::string& v, const std::string& what) {
      out.clear();
      std::stringstream ss(v);
      std::string item;
      while (std::getline(ss, item, '/')) {
        const double x = hb::cli::spec_number_or_usage(item, what, 2, hi);
        if (x != double(int(x))) throw hb::cli::UsageError(what + ": '" + item + "' is not a whole number");
        out.push_back(int(x));
      }
    };
  };
  std::string head;
  hb::cli::parse_spec("--sweep", spec, {{"m", list(o.sweep_m, 4096)}, {"n", list(o.sweep_n, 1024)}}, &head);
  if (head == "none") o.no_sweep = true;
  else if (!head.empty()) throw hb::cli::UsageError("--sweep: '" + head + "' is neither none nor m=.../n=...");
}

// What the report is of: the box given (and its mesh), or the mesh baked for it.
struct ReportInput {
  hb::TriangleMesh mesh;
  std::uint64_t mesh_hash = 0;
  hb::BoxScene scene;
  std::string mesh_path, box_path;
  double bake_seconds = 0.0;
};

ReportInput load_or_bake(const ReportOpts& o, const hb::SamplingGiven& sampling) {
  ReportInput in;
  const bool first_is_box = hb::cli::is_box_file(o.inputs[0]);
  if (first_is_box) {
    in.box_path = o.inputs[0];
    in.scene = hb::load_box_file(in.box_path);
    in.mesh_path = o.inputs.size() > 1 ? o.inputs[1] : in.scene.parts().source.mesh_path;
    if (in.mesh_path.empty()) throw hb::cli::UsageError(in.box_path + ": records no mesh; give MESH after BOX");
  } else {
    if (o.inputs.size() > 1) throw hb::cli::UsageError("give MESH alone, or BOX then MESH");
    in.mesh_path = o.inputs[0];
  }
  in.mesh = hb::cli::load_mesh(in.mesh_path, o.model);
  in.mesh_hash = hb::cli::hash_model(in.mesh_path, o.model);
  if (first_is_box) {
    hb::cli::check_same_mesh(in.scene, in.box_path, in.mesh_path, in.mesh_hash, o.force);
  } else {
    // Without -m and -n, the default bake through the box cache; with either, exactly that
    // sampling, one raw box (hb::choose_recipe, as `bake`, `field` and the window decide).
    hb::cli::ModelBake baked = hb::cli::bake_model(in.mesh, in.mesh_path, in.mesh_hash, sampling, o.params,
                                                   o.cache);
    in.scene = std::move(baked.scene);
    if (baked.from_cache) in.box_path = baked.cache_path;  // the box file the report is of
    in.bake_seconds = baked.seconds;
    if (!o.save_box.empty()) {
      if (hb::cli::communicator().is_root()) hb::save_box_file(in.scene, o.save_box);
      in.box_path = o.save_box;
    }
  }
  return in;
}

void run_report(ReportOpts& o, const hb::SamplingGiven& sampling) {
  const auto t0 = std::chrono::steady_clock::now();
  if (hb::cli::communicator().is_root()) hb::cli::check_output_folder(o.out);  // before the bake, not after
  ReportInput in = load_or_bake(o, sampling);
  const hb::TriangleMesh& mesh = in.mesh;
  const hb::BoxScene& scene = in.scene;
  const std::string& mesh_path = in.mesh_path;
  // One request, as the window's Export Error Report builds it (report/report_request.h).
  const vtkHapticBoxReferenceQueries refs(mesh);
  hb::ReportRequest request;
  request.mesh = &mesh;
  request.scene = &scene;
  request.mesh_path = mesh_path;
  request.mesh_hash = in.mesh_hash;
  request.box_path = in.box_path;
  request.bake_seconds = in.bake_seconds;
  request.references = refs.References();
  request.options = o.report;
  request.options.workspace = o.workspace.options();
  request.options.judge = o.workspace.judge();
  request.options.cache_dir = o.cache;
  request.options.progress = hb::cli::terminal_progress("report");
  request.options.communicator = &hb::cli::communicator();
  request.sweep.enabled = !o.no_sweep;
  request.sweep.m = o.sweep_m;
  request.sweep.n = o.sweep_n;
  request.product_version = HB_VERSION;
  request.command_line = hb::cli::command_line();
  // The error-field image needs X (Debian's VTK has no headless rendering).
  if (o.no_image) request.no_image_note = "image not requested (--field image=off)";
  else request.render_error_field = &vtkHapticBoxErrorFieldImage::RenderField;
  std::string sweep_note;
  hb::report_sweep_configs(scene, request.sweep, &sweep_note);
  if (!sweep_note.empty() && hb::cli::communicator().is_root()) std::cerr << "hapticbox: note: " << sweep_note << "\n";
  hb::ReportData data = hb::compute_report(request);
  if (!hb::cli::communicator().is_root()) return;  // rank 0 holds the figures and writes the report
  if (o.stability)
    data.stability = std::make_shared<hb::StabilityReport>(hb::cli::default_stability(
        scene, mesh, std::filesystem::path(mesh_path).filename().string(), 6));
  hb::write_report(request, data, o.out);
  const double total = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  std::cout << "report " << o.out << "/report.html (" << hb::count_text(double(mesh.triangle_count()))
            << " triangles, " << hb::densities_text(data) << "; " << (data.pass() ? "within" : "OUTSIDE")
            << " tolerances; " << hb::duration_text(total) << ")\n"
            << hb::report_summary_text(data, o.out) << "\n";
  if (data.error_field_image.empty()) std::cout << "  no error-field image: " << data.error_field_note << "\n";
}

} // namespace

void add_report_command(CLI::App& app) {
  auto* cmd = app.add_subcommand("report", "Write an error report (report.html, summary.json, samples.csv)");
  auto opts = std::make_shared<ReportOpts>();
  hb::cli::add_model_options(*cmd, opts->model);
  cmd->add_option("INPUT", opts->inputs, "MESH (baked for the report), or BOX [MESH] (MESH defaults to the box's source)")
      ->required()
      ->expected(1, 2);
  cmd->add_option("-o,--output", opts->out, "Output directory")->required();
  cmd->add_option("-m,--m", opts->params.m,
                  "From a MESH: bake one raw box of exactly this position density (n 16 unless -n is given); without "
                  "-m and -n the report is of the default, budgeted bake, as `bake MESH -o BOX` makes it")
      ->check(CLI::Range(2, 4096));
  cmd->add_option("-n,--n", opts->params.n,
                  "From a MESH: bake one raw box of exactly this directional density (m 32 unless -m is given)")
      ->check(CLI::Range(2, 1024));
  hb::cli::add_probe_options(*cmd, opts->report.samples, opts->report.probes.seed);
  cmd->add_option("--rounds", opts->report.timing_rounds, "Timing passes")->check(CLI::Range(1, 1000))->capture_default_str();
  cmd->add_option_function<std::string>(
         "--sweep",
         [opts](const std::string& spec) { parse_sweep_spec(*opts, spec); },
         "The chart's extra configurations: m=A/B/C (default m/4/m/2/m), n=D/E (default n/2/n), or none (only "
         "the box itself and the references)")
      ->type_name("none|m=A/B,n=C/D");
  hb::cli::add_cache_option(*cmd, opts->cache);
  cmd->add_option_function<std::string>(
         "--field",
         [opts](const std::string& spec) {
           bool image = true;
           hb::cli::parse_spec("--field", spec,
                               {hb::cli::number_key("probes", opts->report.error_field_probes_per_vertex, 0, 10000),
                                hb::cli::flag_key("image", image)});
           opts->no_image = !image;
         },
         "The error field: probes=N per vertex (0: none; default " +
             std::to_string(hb::ReportOptions{}.error_field_probes_per_vertex) +
             "), image=off (do not render it even with a display)")
      ->type_name("probes=N,image=on|off");
  cmd->add_option("--tol-perceptible", opts->report.tolerances.perceptible,
                  "The verdict: at most this share of probes perceptibly different from exact (fraction)")
      ->check(hb::cli::finite_range(0.0, 1.0))
      ->capture_default_str();
  cmd->add_option("--compression-curve", opts->report.compression_codec,
                  "Also draw this codec's compression curve (haar or block)");
  cmd->add_flag("--force", opts->force, "Report even when BOX was baked from a different mesh (its hash differs)");
  cmd->add_option("--save-box", opts->save_box, "When baking, also save the box file here");
  cmd->add_flag("--stability", opts->stability, "Also run the trajectory stability suite (as `stability`, 6 sites)");
  hb::cli::add_workspace_options(*cmd, opts->workspace);
  cmd->callback([opts, cmd] { run_report(*opts, hb::cli::sampling_given(*cmd)); });
}
