// hapticbox subdivide MESH -o OUT [--levels K]: flat midpoint subdivision for scaling runs.
#include "cli_support.h"
#include "commands.h"
#include "mesh/mesh_io.h"
#include "mesh/subdivision.h"
#include <iostream>

void add_subdivide_command(CLI::App& app) {
  auto* cmd = app.add_subcommand("subdivide", "Split each triangle into four (shape unchanged), K times");
  struct Opts {
    hb::cli::ModelArgs model;
    std::string mesh, out;
    int levels = 1;
  };
  auto opts = std::make_shared<Opts>();
  hb::cli::add_model_options(*cmd, opts->model);
  cmd->add_option("MESH", opts->mesh, "Input mesh")->required();
  cmd->add_option("-o,--output", opts->out, "Output mesh (format from the extension)")->required();
  cmd->add_option("--levels", opts->levels, "Subdivision levels (x4 triangles each)")->check(CLI::Range(0, 8))->capture_default_str();
  cmd->callback([opts] {
    const hb::TriangleMesh mesh = hb::cli::load_mesh(opts->mesh, opts->model);
    const hb::TriangleMesh fine = hb::subdivide_midpoint(mesh, opts->levels);
    hb::write_mesh(fine, opts->out);
    std::cout << "subdivided " << opts->mesh << " (" << mesh.triangle_count() << " triangles) " << opts->levels
              << " times: " << opts->out << " (" << fine.triangle_count() << " triangles)\n";
  });
}
