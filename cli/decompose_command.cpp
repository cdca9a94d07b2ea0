// hapticbox decompose MESH -o PIECES.txt [--threshold T] [--max-pieces K] [--plane P ...] [--json]
// Automatic decomposition (or a split by user planes) into pieces, written as a piece id per
// triangle (.txt; .ply with a face property; .vtp, VTK XML PolyData with the cell array
// PieceId, which ParaView colours by); prints the pieces' sizes and pocket scores.
#include "cli_support.h"
#include "commands.h"
#include "decomposition/auto_decomposition.h"
#include "decomposition/piece_file.h"
#include "decomposition/plane_split.h"
#include "decomposition/pocket_measure.h"
#include "mesh/mesh_io.h"
#ifdef HB_WITH_VTK
#include "polydata_files.h"
#include <vtkFieldData.h>
#include <vtkPolyData.h>
#endif
#include <chrono>
#include <iomanip>
#include <iostream>
#include <sstream>

namespace {

hb::CutPlane parse_plane(const std::string& text) {
  std::vector<float> v;
  std::stringstream ss(text);
  std::string item;
  while (std::getline(ss, item, ',')) {
    try {
      std::size_t used = 0;
      v.push_back(std::stof(item, &used));
      if (used != item.size()) throw std::invalid_argument(item);
    } catch (const std::exception&) {
      throw hb::cli::UsageError("--plane '" + text + "': expected six numbers px,py,pz,nx,ny,nz");
    }
  }
  if (v.size() != 6) throw hb::cli::UsageError("--plane '" + text + "': expected six numbers px,py,pz,nx,ny,nz");
  return {hb::Vec3(v[0], v[1], v[2]), hb::Vec3(v[3], v[4], v[5])};
}

} // namespace

void add_decompose_command(CLI::App& app) {
  auto* cmd = app.add_subcommand("decompose", "Cut a mesh into quasi-convex pieces (a piece id per triangle)");
  struct Opts {
    hb::cli::ModelArgs model;
    std::string mesh, out;
    hb::AutoDecompositionOptions automatic;
    std::vector<std::string> planes;
    int score_lines = 8192;
    bool json = false;
  };
  auto opts = std::make_shared<Opts>();
  hb::cli::add_model_options(*cmd, opts->model);
  cmd->add_option("MESH", opts->mesh, "Input mesh")->required();
  cmd->add_option("-o,--output", opts->out, "Piece file: .txt (one id per line), .ply (face property 'piece') or .vtp (cell array PieceId)")
      ->required();
  cmd->add_option("--threshold", opts->automatic.threshold, "Largest pocket probability of a piece")
      ->check(hb::cli::finite_range(0.0, 1.0))->capture_default_str();
  cmd->add_option("--max-pieces", opts->automatic.max_pieces, "Most pieces")
      ->check(CLI::Range(1, 4096))->capture_default_str();
  cmd->add_option("--min-area", opts->automatic.min_area_fraction, "Smallest piece, fraction of the surface area")
      ->check(hb::cli::finite_range(0.0, 0.99))->capture_default_str();
  cmd->add_option("--leaves", opts->automatic.leaves, "Leaf clusters of the initial tree")
      ->check(CLI::Range(1, 1000000))->capture_default_str();
  cmd->add_option("--lines", opts->automatic.lines, "Random lines of the pocket estimate")
      ->check(CLI::Range(1000, 100000000))->capture_default_str();
  cmd->add_option("--seed", opts->automatic.seed, "Seed of the random lines")->capture_default_str();
  cmd->add_option("--plane", opts->planes,
                  "Manual split by a plane px,py,pz,nx,ny,nz (repeatable; replaces the automatic decomposition)");
  cmd->add_option("--score-lines", opts->score_lines, "Lines per piece for the reported pocket scores (0: skip)")
      ->check(CLI::Range(0, 10000000))->capture_default_str();
  cmd->add_flag("--json", opts->json, "Print JSON");
  cmd->callback([opts] {
    const std::string ext = hb::cli::lower_extension(opts->out);
#ifdef HB_WITH_VTK
    if (ext != ".txt" && ext != ".ply" && ext != ".vtp")
      throw hb::cli::UsageError("-o " + opts->out + ": unknown piece file type '" + ext +
                                "'; write .txt (one id per line), .ply (face property piece) or .vtp (cell array PieceId)");
#else
    if (ext != ".txt" && ext != ".ply")
      throw hb::cli::UsageError("-o " + opts->out + ": unknown piece file type '" + ext +
                                "'; write .txt or .ply (.vtp needs the VTK build)");
#endif
    std::vector<hb::CutPlane> planes;
    for (const auto& p : opts->planes) planes.push_back(parse_plane(p));
    const hb::TriangleMesh mesh = hb::cli::load_mesh(opts->mesh, opts->model);
    const auto start = std::chrono::steady_clock::now();
    std::vector<std::uint32_t> ids;
    std::size_t count = 0;
    if (!planes.empty()) {
      ids = hb::split_by_planes(mesh, planes);
      count = hb::compact_piece_ids(ids);
    } else {
      opts->automatic.progress = hb::cli::terminal_progress("decomposing");
      opts->automatic.on_phase = hb::cli::decompose_times();
      hb::Decomposition d = hb::decompose_auto(mesh, opts->automatic);
      ids = std::move(d.piece_of_triangle);
      count = d.piece_count;
    }
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
#ifdef HB_WITH_VTK
    if (ext == ".vtp") {
      vtkSmartPointer<vtkPolyData> pd = hb::vtk::piece_polydata(mesh, ids);
      hb::vtk::add_provenance(pd->GetFieldData(), {{{"HapticBoxVersion", HB_VERSION}, {"Mesh", opts->mesh}},
                                                  {{"Pieces", double(count)}}});
      hb::vtk::write_polydata_xml(pd, opts->out);
    } else
#endif
      hb::write_piece_file(opts->out, mesh, ids);

    std::vector<std::vector<std::uint32_t>> pieces(count);
    for (std::uint32_t t = 0; t < ids.size(); ++t) pieces[ids[t]].push_back(t);
    nlohmann::json list = nlohmann::json::array();
    hb::PocketOptions pocket;
    pocket.lines = opts->score_lines;
    for (std::size_t p = 0; p < count; ++p) {
      nlohmann::json j = {{"piece", p}, {"triangles", pieces[p].size()}};
      if (opts->score_lines > 0) {
        const hb::PocketScore s = hb::measure_pockets(mesh, pieces[p], pocket);
        j["pocket_probability"] = s.probability;
        j["pocket_mean_depth"] = s.mean_depth;
        j["pocket_max_depth"] = s.max_depth;
      }
      list.push_back(j);
    }
    const nlohmann::json j = {{"mesh", opts->mesh},
                              {"output", opts->out},
                              {"triangles", mesh.triangle_count()},
                              {"method", planes.empty() ? "auto" : "planes"},
                              {"threshold", opts->automatic.threshold},
                              {"pieces", count},
                              {"seconds", seconds},
                              {"piece_list", list}};
    if (opts->json) {
      hb::cli::print_json(j);
      return;
    }
    std::cout << "decomposed " << opts->mesh << " (" << mesh.triangle_count() << " triangles) into " << count
              << " pieces in " << std::fixed << std::setprecision(2) << seconds << " s -> " << opts->out << "\n";
    std::cout << "  piece  triangles  pocket-prob  mean-depth  max-depth\n";
    for (const auto& p : list) {
      std::cout << "  " << std::setw(5) << p["piece"].get<std::size_t>() << "  " << std::setw(9)
                << p["triangles"].get<std::size_t>();
      if (p.contains("pocket_probability"))
        std::cout << "  " << std::setw(10) << std::setprecision(3) << 100.0 * p["pocket_probability"].get<double>()
                  << "%  " << std::setw(10) << p["pocket_mean_depth"].get<double>() << "  " << std::setw(9)
                  << p["pocket_max_depth"].get<double>();
      std::cout << "\n";
    }
  });
}
