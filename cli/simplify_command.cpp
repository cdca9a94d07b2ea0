// hapticbox simplify MESH -o OUT [--deviation F] [--json]: the mesh simplified within a
// deviation bound (hb::decimate, what the default bake refines against on large models),
// and the deviation measured from the full surface (hb::measure_deviation).
#include "cli_support.h"
#include "figure_text.h"
#include "commands.h"
#include "evaluation/surface_deviation.h"
#include "mesh/decimation.h"
#include "mesh/mesh_io.h"
#include <nlohmann/json.hpp>
#include <iostream>

void add_simplify_command(CLI::App& app) {
  auto* cmd = app.add_subcommand("simplify", "Simplify a mesh within a deviation bound (quadric decimation)");
  struct Opts {
    hb::cli::ModelArgs model;
    std::string mesh, out;
    double deviation = 3.75e-6;
    double shading = 2.0;
    std::string shading_check = "ring";
    bool fit_shading = false;
    bool json = false;
  };
  auto opts = std::make_shared<Opts>();
  hb::cli::add_model_options(*cmd, opts->model);
  cmd->add_option("MESH", opts->mesh, "Input mesh")->required();
  cmd->add_option("-o,--output", opts->out, "Output mesh (format from the extension)")->required();
  cmd->add_option("--deviation", opts->deviation, "Largest deviation, fraction of the mesh diagonal")
      ->check(CLI::Range(0.0, 0.1))
      ->capture_default_str();
  cmd->add_option("--shading", opts->shading, "Largest shaded-normal difference around a removed vertex, degrees (180: none)")
      ->check(CLI::Range(0.0, 180.0))
      ->capture_default_str();
  cmd->add_option("--shading-check", opts->shading_check,
                  "How --shading is checked: ring (a removed vertex's neighbours' normals within it of its own) or fit "
                  "(each face's corner normals fitted to the shading of the vertices it replaced, within it)")
      ->check(CLI::IsMember({"ring", "fit"}))
      ->capture_default_str();
  cmd->add_flag("--fit-shading", opts->fit_shading,
                "Also fit each simplified triangle's corner normals to the full mesh's shading (what the budgeted bake "
                "refines with, hb::fit_shading) and report the shaded-normal differences after the fit (the file "
                "written keeps the shared vertices and their normals)");
  cmd->add_flag("--json", opts->json, "Print the figures as JSON");
  cmd->callback([opts] {
    const hb::TriangleMesh mesh = hb::cli::load_mesh(opts->mesh, opts->model);
    const double diagonal = mesh.bounds().diagonal();
    hb::DecimationOptions o;
    o.max_deviation = opts->deviation * diagonal;
    o.max_shading_deviation_deg = opts->shading;
    o.shading_check = opts->shading_check == "fit" ? hb::DecimationOptions::ShadingCheck::fit
                                                   : hb::DecimationOptions::ShadingCheck::ring;
    const hb::DecimationResult r = hb::decimate(mesh, o);
    const hb::SurfaceDeviation d = hb::measure_deviation(mesh, r.mesh, 100000, 0.002 * diagonal);
    hb::SurfaceDeviation fitted;
    hb::ShadingFitStats fit_stats;
    if (opts->fit_shading)
      fitted = hb::measure_deviation(mesh, hb::fit_shading(mesh, r.mesh, 0.002 * diagonal, 6, &fit_stats), 100000,
                                     0.002 * diagonal);
    hb::write_mesh(r.mesh, opts->out);
    if (opts->json) {
      nlohmann::json j{{"triangles", mesh.triangle_count()},    {"simplified_triangles", r.mesh.triangle_count()},
                       {"deviation_bound", o.max_deviation},    {"deviation_bound_fraction", opts->deviation},
                       {"deviation_mean", d.mean},              {"deviation_p99", d.p99},
                       {"deviation_max", d.max},                {"chunks", r.chunks},
                       {"unmanifold_kept", r.unmanifold_kept},  {"seconds", r.seconds},
                       {"normal_median_deg", d.normal_median_deg}, {"normal_p95_deg", d.normal_p95_deg},
                       {"normal_p99_deg", d.normal_p99_deg}};
      if (opts->fit_shading)
        j["fitted"] = {{"normal_median_deg", fitted.normal_median_deg}, {"normal_p95_deg", fitted.normal_p95_deg},
                       {"normal_p99_deg", fitted.normal_p99_deg},       {"triangles_fitted", fit_stats.fitted},
                       {"seconds", fit_stats.seconds}};
      std::cout << j.dump(2) << "\n";
      return;
    }
    std::cout << "simplified " << opts->mesh << " (" << mesh.triangle_count() << " triangles) to "
              << r.mesh.triangle_count() << " triangles in " << hb::duration_text(r.seconds) << " (" << r.chunks
              << " chunk(s)); bound " << hb::sig(o.max_deviation, 3) << " (" << hb::sig(opts->deviation * 100.0, 3)
              << "% of the diagonal); measured along the normals over " << d.samples << " points: mean "
              << hb::sig(d.mean, 3) << ", p99 " << hb::sig(d.p99, 3) << ", max " << hb::sig(d.max, 3)
              << "; shaded normals differ by median " << hb::sig(d.normal_median_deg, 3) << " deg, p95 "
              << hb::sig(d.normal_p95_deg, 3) << ", p99 " << hb::sig(d.normal_p99_deg, 3) << ": " << opts->out << "\n";
    if (opts->fit_shading)
      std::cout << "fitted corner normals (" << fit_stats.fitted << " of " << fit_stats.triangles << " triangles, "
                << hb::duration_text(fit_stats.seconds) << "): shaded normals differ by median "
                << hb::sig(fitted.normal_median_deg, 3) << " deg, p95 " << hb::sig(fitted.normal_p95_deg, 3) << ", p99 "
                << hb::sig(fitted.normal_p99_deg, 3) << "\n";
  });
}
