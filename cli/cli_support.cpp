#include "cli_support.h"
#include "evaluation/segments_csv.h"
#include "errors.h"
#include "figure_text.h"
#include "haptic_box/box_scene.h"
#include <algorithm>
#include <cctype>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <iostream>
#include <memory>
#include <optional>
#include <unistd.h>

namespace hb::cli {
namespace {
Communicator* the_communicator = nullptr;
std::string the_command_line;
}

const std::string& command_line() { return the_command_line; }

void set_command_line(int argc, char** argv) {
  the_command_line.clear();
  for (int i = 0; i < argc; ++i) {
    std::string a = i == 0 ? std::string("hapticbox") : std::string(argv[i]);
    if (a.find_first_of(" \t'\"") != std::string::npos) a = "'" + a + "'";
    the_command_line += (i ? " " : "") + a;
  }
}

void check_same_mesh(const BoxScene& scene, const std::string& box_path, const std::string& mesh_path,
                     std::uint64_t mesh_hash, bool force) {
  if (scene.source().mesh_hash == 0 || scene.source().mesh_hash == mesh_hash) return;
  const std::string what = box_path + " was baked from a different mesh than " + mesh_path + " (recorded source " +
                           (scene.source().mesh_path.empty() ? std::string("unknown") : scene.source().mesh_path) +
                           ", hashes differ)";
  if (!force) throw InvalidInput(what + ": the comparison would measure nothing; give the mesh it was baked from, or --force");
  if (communicator().is_root()) std::cerr << "hapticbox: warning: " << what << "; going on (--force)\n";
}

void check_ratio_target(double target, double achieved, double bound, double t_error_mean, bool strict,
                        nlohmann::json& j) {
  if (!(target > 0.0)) return;
  const bool reached = achieved >= target * (1.0 - 1e-3);
  j["ratio_target"] = target;
  j["ratio_reached"] = reached;
  if (reached) return;
  const std::string what = "--ratio " + hb::sig(target) + ": target not reached; the codec ends at " + hb::sig(achieved) +
                           ":1 with its error bound at its maximum, " + hb::percent(bound) +
                           " of the box diagonal (t error mean " + hb::percent(t_error_mean) + ")";
  if (strict) throw Error(what + " (--strict)");
  if (communicator().is_root())
    std::cerr << "hapticbox: warning: " << what << "; the file was written (--strict makes this an error)\n";
}

std::string lower_extension(const std::string& path) {
  const std::size_t slash = path.find_last_of('/');
  const std::size_t dot = path.find_last_of('.');
  if (dot == std::string::npos || (slash != std::string::npos && dot < slash)) return {};
  std::string ext = path.substr(dot);
  for (char& c : ext) c = char(std::tolower((unsigned char)c));
  return ext;
}

Communicator& communicator() { return communicator_or_serial(the_communicator); }

void set_communicator(Communicator* communicator) { the_communicator = communicator; }

std::string progress_eta_text(double elapsed, double fraction) {
  // Padded to one width: the line is redrawn in place, a shorter text would leave a tail.
  std::string text;
  if (fraction >= 1.0) {
    text = "done in " + duration_text(elapsed);
  } else if (fraction < 0.01 || elapsed < 1.0) {
    text = duration_text(elapsed) + " elapsed";  // too early for a fair estimate
  } else {
    const double left = elapsed * (1.0 - fraction) / fraction;
    text = duration_text(elapsed) + " elapsed, ETA " + (left < 60.0 ? duration_text(left)
                                                                 : std::to_string(int(left / 60.0)) + " min " +
                                                                       std::to_string(int(left) % 60) + " s");
  }
  if (text.size() < 36) text.append(36 - text.size(), ' ');
  return text;
}

ProgressCallback terminal_progress(const std::string& label) {
  if (!isatty(STDERR_FILENO) || !communicator().is_root()) return {};
  // The clock starts at the first report: a bar made before other work (a bake's, made before
  // the decomposition runs) does not count that work in its rate.
  auto start = std::make_shared<std::optional<std::chrono::steady_clock::time_point>>();
  return [label, start](double fraction) {
    if (!*start) *start = std::chrono::steady_clock::now();
    const int width = 40;
    fraction = std::min(1.0, std::max(0.0, fraction));
    const int filled = int(fraction * width + 0.5);
    std::fprintf(stderr, "\r%s [%s%s] %3d%% %s", label.c_str(), std::string(std::size_t(filled), '#').c_str(),
                 std::string(std::size_t(width - filled), '.').c_str(), int(fraction * 100.0 + 0.5),
                 progress_eta_text(std::chrono::duration<double>(std::chrono::steady_clock::now() - **start).count(), fraction)
                     .c_str());
    if (fraction >= 1.0) std::fprintf(stderr, "\n");
    std::fflush(stderr);
    return true;
  };
}

CLI::Validator finite_range(double lo, double hi) {
  const auto show = [](double v) {
    char text[32];
    std::snprintf(text, sizeof text, "%g", v);
    return std::string(text);
  };
  const std::string range = "[" + show(lo) + ", " + show(hi) + "]";
  return CLI::Validator(
      [lo, hi, range](std::string& text) -> std::string {
        float v = 0.f;
        if (!parse_finite_float(text, v)) return "'" + text + "' is not a finite number";
        if (!(double(v) >= lo && double(v) <= hi)) return "'" + text + "' is outside " + range;
        return {};
      },
      "FINITE in " + range);
}

CLI::Option* add_codec_bound_options(CLI::App& cmd, CodecOptions& options, bool* strict) {
  if (strict) cmd.add_flag("--strict", *strict, "With --ratio: fail (exit 1) when the codec cannot reach the ratio");
  auto* max_error = cmd.add_option("--max-error", options.max_error,
                                   "Bound on |t1 - t0| / box diagonal for every hit sample")
                        ->check(finite_range(1e-5, 0.1))
                        ->capture_default_str();
  auto* ratio = cmd.add_option("--ratio", options.ratio,
                               "Target compression ratio (finds the tightest bound reaching it)")
                    ->check(finite_range(1.0, 1e6));
  max_error->excludes(ratio);
  cmd.add_option("--normal-bits", options.normal_bits, "Octahedral normal bits per coordinate")
      ->check(CLI::Range(6, 14))
      ->capture_default_str();
  return max_error;
}

void add_force_law_options(CLI::App& cmd, ForceLaw& law) {
  // Bounded so that k x depth x metres per unit stays finite for any model within
  // kMaxCoordinate (1e7 x 4e15 x 1e6 < 3.4e38).
  cmd.add_option("--stiffness", law.stiffness_n_per_m, "Spring stiffness k in N/m")
      ->check(finite_range(1e-6, 1e7))
      ->capture_default_str();
  cmd.add_option("--metres-per-unit", law.metres_per_unit, "Model units to metres")
      ->check(finite_range(1e-12, 1e6))
      ->capture_default_str();
}

void add_route_option(CLI::App& cmd, std::string& route) {
  cmd.add_option("--route", route,
                 "Refined scenes: cells (default: the first crossing among the surface cells' triangles answers, no "
                 "box asked) or boxes (the grid's boxes answer from their triangle ids, the cells' triangles confirm)")
      ->check(CLI::IsMember({"boxes", "cells"}))
      ->capture_default_str();
}

void apply_route(BoxScene& scene, const std::string& route) {
  if (route == "boxes" && scene.refines() && !scene.has_triangle_ids())
    throw UsageError("--route boxes: this scene holds no triangle ids (the default bake drops them: the cells route "
                     "does not read them); bake it with --keep-ids to compare the routes");
  scene.set_route(route == "cells" ? SceneRoute::cells : SceneRoute::boxes);
  if (route == "cells" && scene.answering_route() != SceneRoute::cells && scene.refines())
    std::fprintf(stderr, "warning: --route cells: this scene has no surface cells (no grid, or no shared refined "
                         "surface); the boxes answer\n");
}

void print_json(const nlohmann::json& j) {
  nlohmann::json out = j;
  if (out.is_object() && !out.contains("ranks")) out["ranks"] = communicator().size();
  if (communicator().is_root()) std::cout << out.dump(2) << std::endl;
}

bool is_box_file(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  char magic[8] = {};
  in.read(magic, 8);
  return in.gcount() == 8 && std::string(magic, 8) == "HBOXFILE";
}

} // namespace hb::cli

#include "errors.h"
#include "mesh/mesh_io.h"
#include <algorithm>
#include <filesystem>
#include <new>
#include <sstream>
#include <stdexcept>
#ifdef HB_WITH_VTK
#include "model_loader.h"
#endif

namespace hb::cli {

void add_model_options(CLI::App& cmd, ModelArgs& args) {
  auto* iso = cmd.add_option("--iso", args.iso,
                             "Volumes: iso-value of the surface, in the file's calibrated units (HU for CT); "
                             "default: Otsu threshold (see `info`)");
  auto* label = cmd.add_option("--label", args.label, "Volumes (label maps): the surface of the voxels with this label");
  iso->excludes(label);
  cmd.add_option("--unit", args.unit,
                 "Length of one model unit: mm, cm, m, um, in, ft (default: the file's unit, else mm); the model is "
                 "scaled to mm");
  cmd.add_option("--smooth", args.smooth, "Volumes: windowed-sinc smoothing iterations (0: none)")
      ->check(CLI::Range(0, 1000));
  cmd.add_option("--target-triangles", args.target_triangles, "Volumes: decimate to about this many triangles (0: keep all)");
  cmd.add_option("--chordal-mm", args.chordal_mm,
                 "CAD: chordal deviation of the tessellation in mm (default: --force-tolerance / stiffness 500 N/m)")
      ->check(CLI::NonNegativeNumber);
  cmd.add_option("--force-tolerance", args.force_tolerance_n,
                 "CAD: force error in N the tessellation may cause; sets the chordal deviation")
      ->check(CLI::PositiveNumber)
      ->capture_default_str();
  cmd.add_flag("--accept-lost-faces", args.accept_lost_faces,
               "CAD: keep a model some of whose faces failed to translate or tessellate (default: refuse it)");
  cmd.add_option("--reader-timeout", args.reader_timeout_s,
                 "Seconds a third-party reader (volumes, CAD, scenes, VTK files) may run before it is stopped "
                 "(default: $HB_READER_TIMEOUT_S, else 120)")
      ->check(CLI::Range(0.1, 1e6));
  cmd.add_option("--reader-memory-mb", args.reader_memory_mb,
                 "Megabytes of memory a third-party reader may use (default: $HB_READER_MEMORY_MB, else 8192)")
      ->check(CLI::Range(16, 1 << 24));
}

namespace {
bool has_model_args(const ModelArgs& a) {
  return a.iso || a.label || !a.unit.empty() || a.smooth || a.target_triangles || a.chordal_mm > 0 || a.accept_lost_faces;
}
std::string args_text(const ModelArgs& a) {
  std::ostringstream o;
  o << "iso=" << (a.iso ? std::to_string(*a.iso) : "-") << " label=" << (a.label ? std::to_string(*a.label) : "-")
    << " unit=" << a.unit << " smooth=" << a.smooth << " target=" << a.target_triangles << " chordal=" << a.chordal_mm
    << " ftol=" << a.force_tolerance_n;
  return o.str();
}
} // namespace

TriangleMesh load_mesh(const std::string& path, MeshReadReport* report) { return load_mesh(path, ModelArgs{}, report); }

#ifdef HB_WITH_VTK
hb::vtk::ModelOptions to_model_options(const ModelArgs& args) {
  hb::vtk::ModelOptions options;
  options.unit = args.unit;
  options.volume.iso = args.iso;
  options.volume.label = args.label;
  options.volume.smooth_iterations = args.smooth;
  options.volume.target_triangles = args.target_triangles;
  options.cad.chordal_deviation_mm = args.chordal_mm;
  options.cad.force_tolerance_n = args.force_tolerance_n;
  options.cad.accept_lost_faces = args.accept_lost_faces;
  options.reader_timeout_s = args.reader_timeout_s;
  options.reader_memory_mb = args.reader_memory_mb;
  return options;
}
#endif

namespace {
TriangleMesh load_mesh_unguarded(const std::string& path, const ModelArgs& args, MeshReadReport* report);
} // namespace

TriangleMesh load_mesh(const std::string& path, const ModelArgs& args, MeshReadReport* report) {
  // A size in a damaged file that no allocation can meet names the file, never a bare
  // "std::bad_alloc" or "vector::reserve".
  try {
    return load_mesh_unguarded(path, args, report);
  } catch (const std::bad_alloc&) {
    throw InvalidInput(path + ": out of memory while reading the file (a damaged size in it?)");
  } catch (const std::length_error& e) {
    throw InvalidInput(path + ": the file asks for an impossible size (" + std::string(e.what()) + ")");
  }
}

namespace {
TriangleMesh load_mesh_unguarded(const std::string& path, const ModelArgs& args, MeshReadReport* report) {
#ifdef HB_WITH_VTK
  hb::vtk::LoadedModel model = hb::vtk::load_model(path, to_model_options(args));
  for (const std::string& w : model.report.warnings) std::cerr << "hapticbox: warning: " << w << "\n";
  if (model.kind == hb::vtk::ModelKind::Volume) {
    std::cerr << "hapticbox: " << path << ": " << model.format << " "
              << model.facts["dimensions"].dump() << " voxels, spacing " << model.facts["spacing_mm"].dump() << " mm, ";
    if (model.facts.contains("label")) std::cerr << "label " << model.facts["label"].dump();
    else std::cerr << "iso " << model.facts["iso"].dump() << (args.iso ? "" : " (automatic; set --iso)");
    std::cerr << ": " << model.mesh.triangle_count() << " triangles in mm\n";
  } else if (model.kind == hb::vtk::ModelKind::Cad) {
    std::cerr << "hapticbox: " << path << ": " << model.format << ", " << model.facts.value("faces", 0) << " faces, chordal deviation "
              << model.facts.value("chordal_deviation_mm", 0.0) << " mm: " << model.mesh.triangle_count() << " triangles in mm\n";
  } else if (model.unit_source != "default (the format has no unit)") {
    std::cerr << "hapticbox: " << path << ": " << model.format << ", unit " << model.unit << " (" << model.unit_source
              << "), scaled to mm\n";
  }
  args.facts = model.facts;
  args.face_ids = model.face_ids;
  if (report) *report = model.report;
  return std::move(model.mesh);
#else
  if (has_model_args(args)) throw UsageError("--iso, --label, --unit and the CAD options need the VTK pipelines (HB_BUILD_VTK)");
  MeshReadReport local;
  TriangleMesh mesh = read_mesh(path, &local);
  for (const std::string& w : local.warnings) std::cerr << "hapticbox: warning: " << w << "\n";
  if (report) *report = local;
  return mesh;
#endif
}
} // namespace

std::uint64_t hash_model(const std::string& path, const ModelArgs& args) {
  return hb::hash_model(path, has_model_args(args) ? args_text(args) : std::string());
}

nlohmann::json budget_json(const BudgetReport& r) {
  if (!r.present) return nullptr;
  nlohmann::json pieces = nlohmann::json::array();
  for (const PieceChoice& p : r.pieces)
    pieces.push_back({{"cell", p.cell}, {"n", p.n}, {"refine", p.refine}, {"tuning_probes", p.probes}});
  nlohmann::json j = {{"budget", budget_spec(r.budget)},
          {"met", r.met},
          {"fresh_probes", r.probes},
          {"fresh_seed", r.seed},
          {"contact_agreement", r.agreement},
          {"force_error_median", r.force_median},
          {"force_error_p95", r.force_p95},
          {"angle_error_p99_deg", r.direction_p99_deg},
          {"tuning_probes", r.tuning_probes},
          {"tuning_seed", r.tuning_seed},
          {"tuning_contact_agreement", r.tuning_agreement},
          {"tuning_force_error_median", r.tuning_force_median},
          {"tuning_force_error_p95", r.tuning_force_p95},
          {"tuning_angle_error_p99_deg", r.tuning_direction_p99_deg},
          {"sampling_bakes", r.candidates_tried},
          {"pieces", pieces},
          {"surface", r.surface_triangles == 0 ? nlohmann::json("full mesh")
                                               : nlohmann::json{{"full_triangles", r.full_triangles},
                                                                {"triangles", r.surface_triangles},
                                                                {"deviation_bound", r.surface_bound},
                                                                {"deviation_mean", r.surface_deviation_mean},
                                                                {"deviation_p99", r.surface_deviation_p99},
                                                                {"deviation_max", r.surface_deviation_max},
                                                                {"normal_median_deg", r.surface_normal_median_deg},
                                                                {"normal_p99_deg", r.surface_normal_p99_deg},
                                                                {"normal_map_side", r.surface_map_side}}}};
  // Wall times are this run's (bake --json) or an older file's; a file written now holds none.
  if (r.seconds > 0) j["seconds"] = r.seconds;
  if (r.surface_triangles > 0 && r.simplify_seconds > 0) j["surface"]["seconds"] = r.simplify_seconds;
  if (r.surface_rejected > 0) j["surface_rejected_triangles"] = r.surface_rejected;
  if (!r.surface_rejected_why.empty()) j["surface_rejected_why"] = r.surface_rejected_why;
  if (!r.stage_seconds.empty()) {
    nlohmann::json stages = nlohmann::json::array();  // an array: the step order is the point
    for (const auto& st : r.stage_seconds) stages.push_back({{"stage", st.first}, {"seconds", st.second}});
    j["stage_seconds"] = stages;
  }
  return j;
}

} // namespace hb::cli
