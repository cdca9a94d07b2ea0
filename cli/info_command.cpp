// hapticbox info FILE [--verify] [--json]: the facts of a mesh or a box file (codec, bytes per
// table, compression ratio and the error statistics stored at compression).
#include "cli_support.h"
#ifdef HB_WITH_VTK
#include <vtkOutputWindow.h>
#endif
#include "commands.h"
#include "errors.h"
#include "figure_text.h"
#include "store/box_file.h"
#include "scene/density_range.h"
#include "scene/scene_codec_stats.h"
#include "mesh/file_hash.h"
#include "mesh/mesh_io.h"
#include <algorithm>
#include <filesystem>
#include <iostream>
#include <string>
#include <vector>

namespace {

/// An integer with its thousands separated by commas from 10,000 up, as hb::sig does.
std::string integer_text(long long v) {
  std::string digits = std::to_string(v < 0 ? -v : v);
  if (digits.size() > 4)
    for (int at = int(digits.size()) - 3; at > 0; at -= 3) digits.insert(std::size_t(at), ",");
  return (v < 0 ? "-" : "") + digits;
}

/// A value of the text form: floating-point figures with 4 significant digits (the JSON form
/// keeps full precision), integers with thousands separators as figures are, arrays and
/// objects element by element, strings bare.
std::string info_text(const nlohmann::json& v) {
  if (v.is_string()) return v.get<std::string>();
  if (v.is_number_float()) return hb::sig(v.get<double>(), 4);
  if (v.is_number_unsigned()) return integer_text(static_cast<long long>(v.get<std::uint64_t>()));
  if (v.is_number_integer()) return integer_text(v.get<long long>());
  if (v.is_array()) {
    std::string out = "[";
    for (std::size_t i = 0; i < v.size(); ++i) out += (i ? ", " : "") + info_text(v[i]);
    return out + "]";
  }
  if (v.is_object()) {
    std::string out = "{";
    bool first = true;
    for (auto it = v.begin(); it != v.end(); ++it, first = false) out += (first ? "" : ", ") + it.key() + ": " + info_text(*it);
    return out + "}";
  }
  return v.dump();
}

/// The order the text form prints keys in: the JSON object's (alphabetical), except that a
/// pair's minimum comes before its maximum (bounds_min, bounds_max).
std::vector<std::string> text_order(const nlohmann::json& j) {
  std::vector<std::string> keys;
  for (auto it = j.begin(); it != j.end(); ++it) keys.push_back(it.key());
  for (std::size_t i = 0; i + 1 < keys.size(); ++i) {
    const std::string& k = keys[i];
    if (k.size() > 4 && k.compare(k.size() - 4, 4, "_max") == 0) {
      const std::string min = k.substr(0, k.size() - 4) + "_min";
      const auto at = std::find(keys.begin() + std::ptrdiff_t(i), keys.end(), min);
      if (at != keys.end()) {
        keys.erase(at);
        keys.insert(keys.begin() + std::ptrdiff_t(i), min);
        ++i;
      }
    }
  }
  return keys;
}

nlohmann::json mesh_info(const std::string& path, const hb::cli::ModelArgs& args) {
  hb::MeshReadReport report;
  const hb::TriangleMesh mesh = hb::cli::load_mesh(path, args, &report);
  const hb::Bounds b = mesh.bounds();
  nlohmann::json j = {{"kind", "mesh"},
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
          // The hash box files and the cache record for this model, as the report prints it.
          {"mesh_hash", hb::hash_text(hb::cli::hash_model(path, args))},
          {"warnings", report.warnings}};
  // Volumes, CAD solids and scenes: what the loader read (dimensions, spacing, value range,
  // labels, iso-value; solids, faces, chordal deviation; unit), after the mesh's own facts.
  for (auto it = args.facts.begin(); it != args.facts.end(); ++it)
    if (it.key() != "model_bounds_mm") j[it.key()] = *it;
  return j;
}

nlohmann::json box_info(const std::string& path, bool verify) {
  const hb::BoxScene scene = hb::load_box_file(path, hb::LoadOptions{verify});
  nlohmann::json boxes = nlohmann::json::array();
  std::uint64_t id_bytes = 0;
  std::size_t refined = 0;
  for (const hb::HapticBox& box : scene.parts().boxes) {
    id_bytes += box.triangle_id_bytes();
    refined += box.refines() ? 1 : 0;
    const hb::Obb& o = box.obb();
    const hb::CodecStats& cs = box.codec_stats();
    const std::string name = hb::codec_name(box.codec());
    boxes.push_back({{"m", box.params().m},
                     {"n", box.params().n},
                     {"samples", box.params().sample_count()},
                     {"codec", name},
                     {"table_bytes", box.table_bytes()},
                     {"raw_table_bytes", box.raw_table_bytes()},
                     {"table", box.has_table()},  // false: a frame (the scene answered by exact Embree)
                     {"compression_ratio", box.has_table() ? double(box.raw_table_bytes()) / double(box.table_bytes()) : 0.0},
                     {"max_error_bound", cs.max_error_bound},
                     {"t_error_mean", cs.t_error_mean},
                     {"t_error_max", cs.t_error_max},
                     {"normal_error_mean_deg", cs.normal_error_mean_deg},
                     {"normal_error_max_deg", cs.normal_error_max_deg},
                     {"hit_miss_flips", cs.hit_miss_flips},
                     {"refine", box.refines()},
                     {"center", {o.center.x(), o.center.y(), o.center.z()}},
                     {"half_extents", {o.half.x(), o.half.y(), o.half.z()}}});
  }
  const auto& first = scene.parts().boxes.front();
  const hb::DensityRange densities = hb::density_range(scene);
  const hb::SceneCodecStats codec = hb::scene_codec_stats(scene);
  const double table_bytes = double(scene.bytes().tables);
  const char* frames = "yes (exact Embree over the surface; box frames, no tables, no triangle ids)";
  return {{"kind", "box"},
          {"file", path},
          {"bytes", std::filesystem::file_size(path)},
          {"table_bytes", scene.bytes().tables},
          {"boxes", scene.parts().boxes.size()},
          {"m", first.params().m},  // the first box's; a scene's boxes differ: m_min..m_max
          {"n", first.params().n},
          {"m_min", densities.m_min},
          {"m_max", densities.m_max},
          {"n_min", densities.n_min},
          {"n_max", densities.n_max},
          {"codec", codec.codec},
          {"raw_table_bytes", codec.raw_bytes},
          {"compression_ratio", table_bytes > 0 ? double(codec.raw_bytes) / table_bytes : 0.0},
          {"max_error_bound", codec.max_error_bound},
          {"t_error_mean", codec.t_error_mean},
          {"t_error_max", codec.t_error_max},
          {"normal_error_mean_deg", codec.normal_error_mean_deg},
          {"normal_error_max_deg", codec.normal_error_max_deg},
          {"tables", has_tables(scene.parts()) ? "yes"
                     : "none: box frames only (exact Embree over the surface answers; the bake dropped the tables and "
                       "ids that route never reads)"},
          {"refine", !has_tables(scene.parts())               ? frames
                     : refined == scene.parts().boxes.size() ? "yes"
                     : refined > 0                  ? "some boxes"
                     : scene.refines()              ? "yes (the surface cells; no triangle ids)"
                                                    : "no"},
          {"triangle_id_bytes", id_bytes},
          {"surface_bytes", scene.bytes().refinement - id_bytes},
          {"normal_map_side", scene.parts().surface ? scene.parts().surface->normal_map_side() : 0},
          {"normal_map_bytes", scene.parts().surface ? scene.parts().surface->normal_map_bytes() : 0},
          {"stroke_route", strokes_by_full_mesh(scene)
                               ? "exact Embree over the full mesh (" + hb::count_text(double(stroke_mesh(scene)->triangle_count())) +
                                     " triangles, " + hb::bytes_text(scene.bytes().embree) +
                                     "): a probe's successive queries, where the bake measured it faster than the cells"
                               : std::string(answerer_name(answerer(scene)))},
          {"scene_grid_bytes", scene.parts().grid ? scene.parts().grid->bytes() : 0},
          {"scene_grid_cells", scene.parts().grid ? scene.parts().grid->codes().size() : 0},
          {"verified", verify},
          {"source_mesh", scene.parts().source.mesh_path},
          {"source_mesh_hash", hb::hash_text(scene.parts().source.mesh_hash)},  // hex, as the report
          {"source_triangles", scene.parts().source.triangles},
          {"source_diagonal", scene.parts().source.diagonal},
          {"budget", scene.parts().budget.summary()},
          {"workspace", hb::model_diagonal(scene) > 0
                            ? hb::make_workspace(hb::model_diagonal(scene)).describe() +
                                  " (the default every command judges at; --workspace-mm, --real-size to change)"
                            : std::string("none (no boxes)")},
          {"budget_report", hb::cli::budget_json(scene.parts().budget)},
          {"box_list", boxes}};
}

} // namespace

void add_info_command(CLI::App& app) {
  auto* cmd = app.add_subcommand("info", "Show the facts of a mesh or a box file");
  struct Opts {
    std::string file;
    bool json = false;
    bool verify = false;
    hb::cli::ModelArgs model;
  };
  auto opts = std::make_shared<Opts>();
  hb::cli::add_model_options(*cmd, opts->model);
  cmd->add_option("FILE", opts->file, "Model (mesh, volume, DICOM directory, CAD, scene) or box file (.hbox)")->required();
  cmd->add_flag("--json", opts->json, "Print JSON");
  cmd->add_flag("--verify", opts->verify, "Box files: check every table's checksum (reads the whole file)");
  cmd->callback([opts] {
#ifdef HB_WITH_VTK
    // JSON on stdout is only JSON: whatever VTK has to say (a filter's warning) goes to stderr.
    if (opts->json) vtkOutputWindow::GetInstance()->SetDisplayModeToAlwaysStdErr();
#endif
    if (!std::filesystem::exists(opts->file)) throw hb::IoError(opts->file + ": no such file");
    const nlohmann::json j = hb::cli::is_box_file(opts->file) ? box_info(opts->file, opts->verify) : mesh_info(opts->file, opts->model);
    if (opts->json) {
      hb::cli::print_json(j);
      return;
    }
    const bool scene = j.value("boxes", 0) > 1;
    for (const std::string& key : text_order(j)) {
      const auto it = j.find(key);
      if (key == "box_list" || key == "budget_report") continue;
      if (key == "m_min" || key == "m_max" || key == "n_min" || key == "n_max") continue;
      if (scene && (key == "m" || key == "n")) {
        // A scene's boxes each have their own densities: the range, never the first box's.
        const int lo = j[key + "_min"].get<int>(), hi = j[key + "_max"].get<int>();
        std::cout << key << ": " << hb::range_text(lo, hi) << " (over " << j["boxes"].get<int>() << " boxes)\n";
        continue;
      }
      std::cout << key << ": " << info_text(*it) << "\n";
    }
    if (j.contains("box_list") && j["box_list"].size() > 1) {
      for (std::size_t b = 0; b < j["box_list"].size(); ++b) {
        const auto& x = j["box_list"][b];
        if (!x["table"].get<bool>()) {
          std::cout << "box " << b << ": m " << x["m"].get<int>() << " n " << x["n"].get<int>() << ", centre "
                    << info_text(x["center"]) << ", half extents " << info_text(x["half_extents"]) << ", a frame (no table)\n";
          continue;
        }
        std::cout << "box " << b << ": m " << x["m"].get<int>() << " n " << x["n"].get<int>() << ", centre "
                  << info_text(x["center"]) << ", half extents " << info_text(x["half_extents"]) << ", codec "
                  << x["codec"].get<std::string>() << ", " << hb::bytes_text(x["table_bytes"].get<std::uint64_t>())
                  << ", ratio " << hb::sig(x["compression_ratio"].get<double>()) << ":1, t error mean "
                  << info_text(x["t_error_mean"]) << " max " << info_text(x["t_error_max"]) << "\n";
      }
    }
  });
}
