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
    double deviation = 1.5e-5;
    double shading = 2.0;
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
  cmd->add_flag("--json", opts->json, "Print the figures as JSON");
  cmd->callback([opts] {
    const hb::TriangleMesh mesh = hb::cli::load_mesh(opts->mesh, opts->model);
    const double diagonal = mesh.bounds().diagonal();
    hb::DecimationOptions o;
    o.max_deviation = opts->deviation * diagonal;
    o.max_shading_deviation_deg = opts->shading;
    const hb::DecimationResult r = hb::decimate(mesh, o);
    const hb::SurfaceDeviation d = hb::measure_deviation(mesh, r.mesh, 100000, 0.002 * diagonal);
    hb::write_mesh(r.mesh, opts->out);
    if (opts->json) {
      nlohmann::json j{{"triangles", mesh.triangle_count()},    {"simplified_triangles", r.mesh.triangle_count()},
                       {"deviation_bound", o.max_deviation},    {"deviation_bound_fraction", opts->deviation},
                       {"deviation_mean", d.mean},              {"deviation_p99", d.p99},
                       {"deviation_max", d.max},                {"chunks", r.chunks},
                       {"unmanifold_kept", r.unmanifold_kept},  {"seconds", r.seconds}};
      std::cout << j.dump(2) << "\n";
      return;
    }
    std::cout << "simplified " << opts->mesh << " (" << mesh.triangle_count() << " triangles) to "
              << r.mesh.triangle_count() << " triangles in " << hb::duration_text(r.seconds) << " (" << r.chunks
              << " chunk(s)); bound " << hb::sig(o.max_deviation, 3) << " (" << hb::sig(opts->deviation * 100.0, 3)
              << "% of the diagonal); measured along the normals over " << d.samples << " points: mean "
              << hb::sig(d.mean, 3) << ", p99 " << hb::sig(d.p99, 3) << ", max " << hb::sig(d.max, 3)
              << ": " << opts->out << "\n";
  });
}
