// hapticbox report MESH|BOX [MESH] -o DIR [--m M --n N] [--samples N] [--seed S] ...
// Writes DIR/report.html (self-contained), DIR/summary.json and DIR/samples.csv. Runs with no
// display: the error-field image is rendered only when an X display opens (noted otherwise).
#include "cli_support.h"
#include "haptic_box/box_cache.h"
#include "commands.h"
#include "errors.h"
#include "haptic_box/bake_recipe.h"
#include "haptic_box/box_file.h"
#include "mesh/mesh_io.h"
#include "report.h"
#include "figure_text.h"
#include "summary_text.h"
#include "vtkHapticBoxErrorFieldImage.h"
#include "vtkHapticBoxReferenceQueries.h"
#include "vtkHapticBoxUtilities.h"
#include <vtkFloatArray.h>
#include <vtkPointData.h>
#include <vtkPolyData.h>
#include <algorithm>
#include <chrono>
#include <filesystem>
#include <iostream>
#include <set>

namespace {

// Around the report's own (m, n): m/4, m/2, m by n/2, n, without the box itself.
std::vector<hb::SweepConfig> default_sweep(int m, int n) {
  std::set<std::pair<int, int>> grid;
  for (int mm : {m / 4, m / 2, m})
    for (int nn : {n / 2, n})
      if (mm >= 2 && nn >= 2 && !(mm == m && nn == n)) grid.insert({mm, nn});
  std::vector<hb::SweepConfig> out;
  for (const auto& [mm, nn] : grid) out.push_back({mm, nn, "none"});
  return out;
}

} // namespace

void add_report_command(CLI::App& app) {
  auto* cmd = app.add_subcommand("report", "Write an error report (report.html, summary.json, samples.csv)");
  struct Opts {
    hb::cli::ModelArgs model;
    std::vector<std::string> inputs;
    std::string out;
    hb::BoxParams params;
    hb::ReportOptions report;
    std::vector<int> sweep_m, sweep_n;
    bool no_sweep = false;
    std::string cache = hb::default_box_cache_dir();
    bool no_cache = false;
    bool no_image = false;
    bool stability = false;
    bool force = false;
    std::string save_box;
  };
  auto opts = std::make_shared<Opts>();
  hb::cli::add_model_options(*cmd, opts->model);
  cmd->add_option("INPUT", opts->inputs, "MESH (baked for the report), or BOX [MESH] (MESH defaults to the box's source)")
      ->required()
      ->expected(1, 2);
  cmd->add_option("-o,--output", opts->out, "Output directory")->required();
  cmd->add_option("-m,--m", opts->params.m, "Position density m when baking")->check(CLI::Range(2, 4096))->capture_default_str();
  cmd->add_option("-n,--n", opts->params.n, "Directional density n when baking")->check(CLI::Range(2, 1024))->capture_default_str();
  cmd->add_option("--samples", opts->report.samples, "Probes (as eval)")->check(CLI::Range(std::size_t(1), std::size_t(10000000)))->capture_default_str();
  cmd->add_option("--seed", opts->report.probes.seed, "Probe seed (as eval)")->capture_default_str();
  cmd->add_option("--rounds", opts->report.timing_rounds, "Timing passes")->check(CLI::Range(1, 1000))->capture_default_str();
  cmd->add_option("--sweep-m", opts->sweep_m, "Extra configurations for the chart: m values (default m/4, m/2, m)")->delimiter(',');
  cmd->add_option("--sweep-n", opts->sweep_n, "Extra configurations for the chart: n values (default n/2, n)")->delimiter(',');
  cmd->add_flag("--no-sweep", opts->no_sweep, "Only the box itself and the references in the chart");
  cmd->add_option("--cache", opts->cache, "Directory of cached sweep boxes")->capture_default_str();
  cmd->add_flag("--no-cache", opts->no_cache, "Cache no sweep boxes");
  cmd->add_option("--field-probes", opts->report.error_field_probes_per_vertex, "Error-field probes per vertex (0: none)")
      ->check(CLI::Range(0, 10000))->capture_default_str();
  cmd->add_flag("--no-image", opts->no_image, "Do not render the error field even with a display");
  cmd->add_option("--tol-median", opts->report.tolerances.force_error_median, "Tolerance: median force error (fraction)")->check(hb::cli::finite_range(0.0, 1e6))->capture_default_str();
  cmd->add_option("--tol-p95", opts->report.tolerances.force_error_p95, "Tolerance: p95 force error (fraction)")->check(hb::cli::finite_range(0.0, 1e6))->capture_default_str();
  cmd->add_option("--tol-agreement", opts->report.tolerances.contact_agreement, "Tolerance: min contact agreement")->check(hb::cli::finite_range(0.0, 1e6))->capture_default_str();
  cmd->add_option("--compression-curve", opts->report.compression_codec,
                  "Also draw this codec's compression curve (haar or block)");
  cmd->add_flag("--force", opts->force, "Report even when BOX was baked from a different mesh (its hash differs)");
  cmd->add_option("--save-box", opts->save_box, "When baking, also save the box file here");
  cmd->add_flag("--stability", opts->stability, "Also run the trajectory stability suite (as `stability`, 6 sites)");
  hb::cli::add_force_law_options(*cmd, opts->report.law);
  cmd->callback([opts] {
    const auto t0 = std::chrono::steady_clock::now();
    std::string mesh_path, box_path;
    const bool first_is_box = hb::cli::is_box_file(opts->inputs[0]);
    hb::BoxScene scene;
    if (first_is_box) {
      box_path = opts->inputs[0];
      scene = hb::load_box_file(box_path);
      mesh_path = opts->inputs.size() > 1 ? opts->inputs[1] : scene.source().mesh_path;
      if (mesh_path.empty()) throw hb::cli::UsageError(box_path + ": records no mesh; give MESH after BOX");
    } else {
      if (opts->inputs.size() > 1) throw hb::cli::UsageError("give MESH alone, or BOX then MESH");
      mesh_path = opts->inputs[0];
    }
    const hb::TriangleMesh mesh = hb::cli::load_mesh(mesh_path, opts->model);
    const std::uint64_t mesh_hash = hb::cli::hash_model(mesh_path, opts->model);
    double bake_seconds = 0.0;
    if (first_is_box) {
      hb::cli::check_same_mesh(scene, box_path, mesh_path, mesh_hash, opts->force);
    } else {
      hb::BakeRecipe recipe;
      recipe.options.params = opts->params;
      recipe.options.progress = hb::cli::terminal_progress("bake");
      // Baked across the ranks of an MPI job; every rank needs the scene for the evaluation.
      recipe.options.communicator = &hb::cli::communicator();
      recipe.options.scene_on_every_rank = true;
      hb::SourceInfo source{mesh_path, mesh_hash, mesh.triangle_count(), mesh.bounds().diagonal()};
      hb::BakeResult baked = hb::bake(mesh, recipe, source);
      scene = std::move(baked.scene);
      bake_seconds = baked.stats.seconds;
      if (!opts->save_box.empty()) {
        if (hb::cli::communicator().is_root()) hb::save_box_file(scene, opts->save_box);
        box_path = opts->save_box;
      }
    }
    hb::ReportOptions& ro = opts->report;
    const hb::BoxParams own = scene.boxes().front().params();
    // Sweep configurations are baked as one box: with a multi-box scene they would not compare
    // like with like, so the default sweep is skipped then (explicit --sweep-m/-n still run).
    const bool explicit_sweep = !opts->sweep_m.empty() || !opts->sweep_n.empty();
    if (scene.boxes().size() > 1 && !explicit_sweep && !opts->no_sweep && hb::cli::communicator().is_root())
      std::cerr << "hapticbox: note: " << scene.boxes().size()
                << " boxes: the default sweep (one box per configuration) is skipped\n";
    if (!opts->no_sweep && (scene.boxes().size() == 1 || explicit_sweep)) {
      if (!explicit_sweep) {
        ro.sweep_configs = default_sweep(own.m, own.n);
      } else {
        const std::vector<int> ms = opts->sweep_m.empty() ? std::vector<int>{own.m} : opts->sweep_m;
        const std::vector<int> ns = opts->sweep_n.empty() ? std::vector<int>{own.n} : opts->sweep_n;
        for (const hb::SweepConfig& c : hb::sweep_grid(ms, ns))
          if (!(c.m == own.m && c.n == own.n)) ro.sweep_configs.push_back(c);
      }
    }
    ro.cache_dir = opts->no_cache ? "" : opts->cache;
    ro.progress = hb::cli::terminal_progress("report");
    ro.communicator = &hb::cli::communicator();

    const vtkHapticBoxReferenceQueries refs(mesh);
    hb::ReportData data = hb::compute_report(mesh, {}, scene, bake_seconds, refs.References(), ro);
    if (!hb::cli::communicator().is_root()) return;  // rank 0 holds the figures and writes the report
    data.product_version = HB_VERSION;
    data.command_line = hb::cli::command_line();
    data.mesh_path = mesh_path;
    data.mesh_hash = mesh_hash;
    data.box_path = box_path;
    data.box_hash = box_path.empty() ? 0 : hb::hash_file(box_path);
    if (opts->stability)
      data.stability = std::make_shared<hb::StabilityReport>(hb::cli::default_stability(
          scene, mesh, std::filesystem::path(mesh_path).filename().string(), 6));

    // The error-field image needs X (Debian's VTK has no headless rendering).
    std::filesystem::create_directories(opts->out);
    if (data.error_field.size() == 0) {
      data.error_field_note = "error field disabled (--field-probes 0)";
    } else if (opts->no_image) {
      data.error_field_note = "image not requested (--no-image)";
    } else if (std::string why; !vtkHapticBoxErrorFieldImage::DisplayAvailable(&why)) {
      data.error_field_note = why;
    } else {
      // Write the report without the image first: a display that vanishes mid-render can take
      // the process down inside Xlib, and the figures must survive that.
      data.error_field_note = "rendering the error field did not finish";
      hb::write_report(data, opts->out);
      vtkSmartPointer<vtkPolyData> pd = vtkHapticBoxUtilities::ToPolyData(mesh);
      // Drawn in percent, as the report's text gives it (NaN stays NaN: no data, grey).
      std::vector<float> percent(data.error_field.force_error);
      for (float& v : percent) v *= 100.f;
      pd->GetPointData()->AddArray(vtkHapticBoxUtilities::ToScalarArray("RelativeForceErrorPercent", percent));
      const std::string png = (std::filesystem::path(opts->out) / "charts" / "error_field.png").string();
      std::filesystem::create_directories(std::filesystem::path(png).parent_path());
      const double range = 100.0 * std::max(ro.tolerances.force_error_p95, data.error_field_p95);
      if (vtkHapticBoxErrorFieldImage::Render(pd, "RelativeForceErrorPercent", range,
                                              "relative force error, %   (grey: no data)", png, 1200, 700,
                                              &data.error_field_note)) {
        data.error_field_image = png;
        data.error_field_note.clear();  // rendered: nothing to explain
      }
    }
    hb::write_report(data, opts->out);
    const double total = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    std::cout << "report " << opts->out << "/report.html (" << hb::count_text(double(mesh.triangle_count()))
              << " triangles, " << hb::densities_text(data) << "; " << (data.pass() ? "within" : "OUTSIDE")
              << " tolerances; " << hb::duration_text(total) << ")\n"
              << hb::report_summary_text(data, opts->out) << "\n";
    if (data.error_field_image.empty()) std::cout << "  no error-field image: " << data.error_field_note << "\n";
  });
}
