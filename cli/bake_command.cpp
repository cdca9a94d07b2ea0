// hapticbox bake MESH -o BOX.hbox [-m 32] [-n 16] [--pieces auto|FILE|none] [--json]
#include "cli_support.h"
#include "commands.h"
#include "haptic_box/bake.h"
#include "haptic_box/box_file.h"
#include "mesh/mesh_io.h"
#include "pieces_option.h"
#include <filesystem>
#include <iostream>

void add_bake_command(CLI::App& app) {
  auto* cmd = app.add_subcommand("bake", "Bake a haptic box file from a mesh");
  struct Opts {
    std::string mesh, out;
    hb::BakeOptions bake;
    hb::cli::PiecesChoice pieces;
    bool json = false;
  };
  auto opts = std::make_shared<Opts>();
  cmd->add_option("MESH", opts->mesh, "Input mesh")->required();
  cmd->add_option("-o,--output", opts->out, "Output box file (.hbox)")->required();
  cmd->add_option("-m", opts->bake.params.m, "Position points per PBB face edge")
      ->check(CLI::Range(2, 1024))->capture_default_str();
  cmd->add_option("-n", opts->bake.params.n, "Directional points per sub-block face edge")
      ->check(CLI::Range(2, 256))->capture_default_str();
  cmd->add_option("--padding", opts->bake.obb.padding, "PBB padding, fraction of its diagonal")
      ->check(CLI::Range(0.0, 1.0))->capture_default_str();
  hb::cli::add_pieces_options(*cmd, opts->pieces);
  cmd->add_flag("--json", opts->json, "Print a JSON summary");
  cmd->callback([opts] {
    const hb::TriangleMesh mesh = hb::cli::load_mesh(opts->mesh);
    hb::SourceInfo source{opts->mesh, hb::hash_file(opts->mesh), mesh.triangle_count(), mesh.bounds().diagonal()};
    opts->bake.progress = hb::cli::terminal_progress("baking");
    hb::BakeStats stats;
    const auto pieces = hb::cli::resolve_pieces(mesh, opts->pieces, opts->bake.params.m);
    const hb::BoxScene scene = hb::bake_scene_from_lists(mesh, pieces, opts->bake, source, &stats);
    hb::save_box_file(scene, opts->out);
    const auto bytes = std::filesystem::file_size(opts->out);
    const nlohmann::json j = {{"mesh", opts->mesh},
                              {"output", opts->out},
                              {"triangles", mesh.triangle_count()},
                              {"boxes", scene.boxes().size()},
                              {"m", opts->bake.params.m},
                              {"n", opts->bake.params.n},
                              {"seconds", stats.seconds},
                              {"rays", stats.rays},
                              {"rays_per_second", stats.rays_per_second},
                              {"hit_fraction", stats.rays ? double(stats.hits) / double(stats.rays) : 0.0},
                              {"bytes", bytes}};
    if (opts->json) {
      hb::cli::print_json(j);
    } else {
      std::cout << "baked " << opts->out << ": " << scene.boxes().size() << " box(es), m=" << opts->bake.params.m
                << " n=" << opts->bake.params.n << ", " << stats.rays << " rays in " << stats.seconds << " s ("
                << stats.rays_per_second / 1e6 << " M rays/s), " << bytes / 1e6 << " MB\n";
    }
  });
}
