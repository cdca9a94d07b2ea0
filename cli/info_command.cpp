// hapticbox info FILE [--json]: the facts of a mesh or a box file.
#include "cli_support.h"
#include "commands.h"
#include "errors.h"
#include "haptic_box/box_file.h"
#include "mesh/mesh_io.h"
#include <filesystem>
#include <iostream>

namespace {

nlohmann::json mesh_info(const std::string& path) {
  hb::MeshReadReport report;
  const hb::TriangleMesh mesh = hb::cli::load_mesh(path, &report);
  const hb::Bounds b = mesh.bounds();
  return {{"kind", "mesh"},
          {"file", path},
          {"vertices", mesh.vertex_count()},
          {"triangles", mesh.triangle_count()},
          {"input_faces", report.input_faces},
          {"polygons_triangulated", report.polygons_triangulated},
          {"degenerate_dropped", report.degenerate_dropped},
          {"faces_rejected", report.faces_rejected},
          {"open", report.open},
          {"non_manifold", report.non_manifold},
          {"bounds_min", {b.min.x(), b.min.y(), b.min.z()}},
          {"bounds_max", {b.max.x(), b.max.y(), b.max.z()}},
          {"diagonal", b.diagonal()},
          {"area", mesh.area()},
          {"warnings", report.warnings}};
}

nlohmann::json box_info(const std::string& path) {
  const hb::BoxScene scene = hb::load_box_file(path);
  nlohmann::json boxes = nlohmann::json::array();
  for (const hb::HapticBox& box : scene.boxes()) {
    const hb::Obb& o = box.obb();
    boxes.push_back({{"m", box.params().m},
                     {"n", box.params().n},
                     {"samples", box.params().sample_count()},
                     {"table_bytes", box.table_bytes()},
                     {"center", {o.center.x(), o.center.y(), o.center.z()}},
                     {"half_extents", {o.half.x(), o.half.y(), o.half.z()}}});
  }
  const auto& first = scene.boxes().front();
  return {{"kind", "box"},
          {"file", path},
          {"bytes", std::filesystem::file_size(path)},
          {"table_bytes", scene.table_bytes()},
          {"boxes", scene.boxes().size()},
          {"m", first.params().m},
          {"n", first.params().n},
          {"codec", "none"},
          {"source_mesh", scene.source().mesh_path},
          {"source_mesh_hash", scene.source().mesh_hash},
          {"source_triangles", scene.source().triangles},
          {"source_diagonal", scene.source().diagonal},
          {"box_list", boxes}};
}

} // namespace

void add_info_command(CLI::App& app) {
  auto* cmd = app.add_subcommand("info", "Show the facts of a mesh or a box file");
  struct Opts {
    std::string file;
    bool json = false;
  };
  auto opts = std::make_shared<Opts>();
  cmd->add_option("FILE", opts->file, "Mesh (.off .obj .ply .stl .om) or box file (.hbox)")->required();
  cmd->add_flag("--json", opts->json, "Print JSON");
  cmd->callback([opts] {
    if (!std::filesystem::exists(opts->file)) throw hb::IoError(opts->file + ": no such file");
    const nlohmann::json j = hb::cli::is_box_file(opts->file) ? box_info(opts->file) : mesh_info(opts->file);
    if (opts->json) {
      hb::cli::print_json(j);
      return;
    }
    for (auto it = j.begin(); it != j.end(); ++it) {
      if (it.key() == "box_list") continue;
      std::cout << it.key() << ": " << (it->is_string() ? it->get<std::string>() : it->dump()) << "\n";
    }
    if (j.contains("box_list") && j["box_list"].size() > 1) {
      std::size_t k = 0;
      for (const auto& b : j["box_list"])
        std::cout << "box " << k++ << ": centre " << b["center"].dump() << ", half extents " << b["half_extents"].dump()
                  << ", " << b["table_bytes"].get<std::size_t>() / 1e6 << " MB\n";
    }
  });
}
