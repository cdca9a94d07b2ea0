#include "cli_support.h"
#include "contact/perceptible.h"
#include "evaluation/segments_csv.h"
#include "errors.h"
#include "figure_text.h"
#include "recipe/box_cache.h"
#include "haptic_box/box_scene.h"
#include <algorithm>
#include <limits>
#include <cctype>
#include <chrono>
#include <cstdio>
#include <cerrno>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <memory>
#include <optional>
#include <sstream>
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

void clear_progress_line() {
  if (!isatty(STDERR_FILENO) || !communicator().is_root()) return;
  std::fputs("\r\033[K", stderr);  // back to the line's start, erase it: the bar is drawn again at its next report
  std::fflush(stderr);
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

double spec_number_or_usage(const std::string& text, const std::string& what, double lo, double hi) {
  try {
    return spec_number(text, what, lo, hi);
  } catch (const InvalidInput& e) {
    throw UsageError(e.what());
  }
}

SpecKey flag_key(const std::string& key, bool& field) {
  return {key, [&field](const std::string& v, const std::string& what) {
            if (v.empty() || v == "1" || v == "on" || v == "yes") field = true;
            else if (v == "0" || v == "off" || v == "no") field = false;
            else throw UsageError(what + ": '" + v + "' is not on or off");
          }};
}

void parse_spec(const std::string& option, const std::string& spec, const std::vector<SpecKey>& keys,
                std::string* head) {
  const auto known = [&] {
    std::string k;
    for (const SpecKey& key : keys) k += (k.empty() ? "" : ", ") + key.key;
    return k;
  };
  std::stringstream ss(spec);
  std::string item;
  bool first = true;
  while (std::getline(ss, item, ',')) {
    item = spec_trim(item);
    const auto eq = item.find('=');
    const std::string key = spec_trim(item.substr(0, eq)), value = eq == std::string::npos ? "" : item.substr(eq + 1);
    const auto it = std::find_if(keys.begin(), keys.end(), [&](const SpecKey& k) { return k.key == key; });
    if (it == keys.end() && first && head) {
      *head = item;
      first = false;
      continue;
    }
    first = false;
    if (item.empty()) continue;
    if (it == keys.end())
      throw UsageError(option + ": unknown key '" + key + "' (keys: " + known() + ")");
    it->set(value, option + " " + key);
  }
}

namespace {
struct Measurements {
  std::vector<std::pair<std::string, std::string>> given;
};
const Measurements& measurements() {
  static const Measurements m = [] {
    Measurements out;
    const char* env = std::getenv("HB_MEASURE");
    if (!env) return out;
    std::stringstream ss(env);
    std::string item;
    while (std::getline(ss, item, ',')) {
      item = spec_trim(item);
      if (item.empty()) continue;
      const auto eq = item.find('=');
      const std::string name = item.substr(0, eq);
      const auto& names = measurement_names();
      if (std::find(names.begin(), names.end(), name) == names.end()) {
        std::string k;
        for (const auto& n : names) k += (k.empty() ? "" : ", ") + n;
        throw UsageError("HB_MEASURE: unknown switch '" + name + "' (switches: " + k + ")");
      }
      out.given.emplace_back(name, eq == std::string::npos ? "" : item.substr(eq + 1));
    }
    return out;
  }();
  return m;
}
} // namespace

void check_measurements() { (void)measurements(); }

std::function<void(const char*, double)> decompose_times() {
  if (!measurement("decompose-times")) return {};
  return [](const char* phase, double seconds) { std::fprintf(stderr, "decompose %s at %.2f s\n", phase, seconds); };
}

std::string measurement_choice(const std::string& name, const std::string& fallback,
                               const std::vector<std::string>& allowed) {
  const auto v = measurement(name);
  if (!v) return fallback;
  if (std::find(allowed.begin(), allowed.end(), *v) == allowed.end()) {
    std::string k;
    for (const auto& a : allowed) k += (k.empty() ? "" : " or ") + a;
    throw UsageError("HB_MEASURE " + name + ": '" + *v + "' is not " + k);
  }
  return *v;
}

const std::vector<std::string>& measurement_names() {
  // bake: the searches and shading checks kept for before/after figures; bench: the routes
  // and the heap without the grid, the walk or huge pages; servo: the loop without priming or
  // with another busy-wait; stability: the other depth law, safety response and ghost rule;
  // decompose-times: each phase of an automatic decomposition on stderr.
  static const std::vector<std::string> names = {
      "full-search", "keep-ids",  "simplify-shading", "simplify-shading-check", "no-grid",     "refine-walk",
      "no-huge-pages", "no-prime", "spin-us",         "depth-law",              "safety",      "unconfirmed",
      "decompose-times"};
  return names;
}

std::optional<std::string> measurement(const std::string& name) {
  for (const auto& g : measurements().given)
    if (g.first == name) return g.second;
  return std::nullopt;
}

CLI::Option* add_codec_option(CLI::App& cmd, std::string& codec, CodecOptions& options, bool* strict,
                              bool* bound_given, const std::vector<std::string>& allowed, const std::string& help) {
  return cmd.add_option_function<std::string>(
      "--codec",
      [&codec, &options, strict, bound_given, allowed](const std::string& spec) {
        std::string name = codec;
        bool max_error = false, ratio = false;
        std::vector<SpecKey> keys = {
            {"max-error", [&](const std::string& v, const std::string& what) {
               options.max_error = float(spec_number_or_usage(v, what, 1e-5, 0.1));
               max_error = true;
             }},
            {"ratio", [&](const std::string& v, const std::string& what) {
               options.ratio = float(spec_number_or_usage(v, what, 1.0, 1e6));
               ratio = true;
             }},
            number_key("normal-bits", options.normal_bits, 6, 14)};
        bool strict_given = false;
        if (strict) keys.push_back(flag_key("strict", strict_given));
        parse_spec("--codec", spec, keys, &name);
        if (std::find(allowed.begin(), allowed.end(), name) == allowed.end()) {
          std::string k;
          for (const auto& a : allowed) k += (k.empty() ? "" : ", ") + a;
          throw UsageError("--codec: '" + name + "' is not a codec (" + k + ")");
        }
        if (max_error && ratio) throw UsageError("--codec: max-error and ratio exclude each other (give one)");
        if (strict) *strict = strict_given;
        if (bound_given) *bound_given = max_error || ratio;
        codec = name;
      },
      help);
}

void add_probe_options(CLI::App& cmd, std::size_t& samples, std::uint64_t& seed, std::size_t min_samples) {
  cmd.add_option("--samples", samples,
                 "Probes (segments sampled over the mesh; the same count and seed give the same probes in every "
                 "command" + std::string(min_samples == 0 ? "; 0: none)" : ")"))
      ->check(CLI::Range(min_samples, std::size_t(100000000)))
      ->capture_default_str();
  cmd.add_option("--seed", seed, "Probe seed")->capture_default_str();
}

void add_cache_option(CLI::App& cmd, std::string& dir) {
  dir = default_box_cache_dir();
  cmd.add_option_function<std::string>(
         "--cache", [&dir](const std::string& d) { dir = d == "none" ? std::string() : d; },
         "Box cache directory, shared by bake, sweep, report, field and the window (default " +
             default_box_cache_dir() + "); none: bake without it and store nothing")
      ->type_name("DIR|none");
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

WorkspaceOptions WorkspaceArgs::options() const {
  WorkspaceOptions o;
  o.fit = metres_per_unit > 0 ? WorkspaceFit::scale : real_size ? WorkspaceFit::real_size : WorkspaceFit::device;
  o.diagonal_m = workspace_mm * 1e-3;
  o.metres_per_unit = metres_per_unit;
  o.stiffness_n_per_m = stiffness;
  o.max_force_n = max_force;
  return o;
}

Bounds scene_bounds(const BoxScene& scene) {
  Bounds b;
  if (scene.boxes().empty()) return b;
  b.min = Vec3::Constant(std::numeric_limits<float>::max());
  b.max = -b.min;
  for (const auto& box : scene.boxes()) {
    const Obb& o = box.obb();
    for (int c = 0; c < 8; ++c) {
      const Vec3 corner = o.to_world(Vec3((c & 1) ? o.half.x() : -o.half.x(), (c & 2) ? o.half.y() : -o.half.y(),
                                          (c & 4) ? o.half.z() : -o.half.z()));
      b.min = b.min.cwiseMin(corner);
      b.max = b.max.cwiseMax(corner);
    }
  }
  return b;
}

double model_diagonal(const BoxScene& scene) {
  if (scene.source().diagonal > 0.f) return scene.source().diagonal;
  return scene.boxes().empty() ? 0.0 : double(scene_bounds(scene).diagonal());
}

Workspace WorkspaceArgs::workspace(double model_diagonal) const { return make_workspace(model_diagonal, options()); }

PerceptualJudge WorkspaceArgs::judge() const {
  PerceptualJudge j;
  j.thresholds = parse_thresholds(perceptual);
  j.max_force_n = max_force;
  return j;
}

void add_workspace_options(CLI::App& cmd, WorkspaceArgs& args) {
  const std::string group = "Workspace (the scale forces are computed and judged at)";
  const WorkspaceArgs d;
  // Bounded so that k x depth x metres per unit stays finite for any model within
  // kMaxCoordinate (1e5 x 4e15 x 1e6 < 3.4e38).
  cmd.add_option_function<std::string>(
         "--workspace",
         [&args](const std::string& spec) {
           bool mm = false, mpu = false, real = false;
           parse_spec("--workspace", spec,
                      {{"mm", [&](const std::string& v, const std::string& what) {
                          args.workspace_mm = spec_number_or_usage(v, what, 1.0, 4000.0);
                          mm = true;
                        }},
                       {"real-size", [&](const std::string& v, const std::string& what) {
                          flag_key("real-size", args.real_size).set(v, what);
                          real = args.real_size;
                        }},
                       {"metres-per-unit", [&](const std::string& v, const std::string& what) {
                          args.metres_per_unit = spec_number_or_usage(v, what, 1e-12, 1e6);
                          mpu = true;
                        }},
                       {"stiffness", [&](const std::string& v, const std::string& what) {
                          args.stiffness = spec_number_or_usage(v, what, 1e-3, 1e5);
                        }},
                       {"max-force", [&](const std::string& v, const std::string& what) {
                          args.max_force = spec_number_or_usage(v, what, 1e-3, 500.0);
                        }}});
           if (int(mm) + int(mpu) + int(real) > 1)
             throw UsageError("--workspace: mm, real-size and metres-per-unit exclude each other (give one)");
         },
         "Where the model sits at the device: mm=D (the diagonal of its bounding box, mm; default " +
             spec_format(d.workspace_mm) +
             ": the Falcon's workspace sphere), real-size (1 model unit = 1 mm: anatomy at true scale) or "
             "metres-per-unit=S (an explicit scale); stiffness=K (the spring, N/m; default " +
             spec_format(d.stiffness) + ": half the Falcon's stable 3000), max-force=F (the largest force the device "
             "renders, N; forces are judged clamped to it; default " + spec_format(d.max_force) + ")")
      ->type_name("KEY=VALUE,...")
      ->group(group);
  cmd.add_option("--perceptual", args.perceptual,
                 "When a difference is perceptible: nominal (w=10,f0=0.04,theta=25,fmin=0.2), strict "
                 "(w=7,f0=0.03,theta=18) or key=value list: w percent, f0 N, theta degrees, fmin N "
                 "(docs/perception.md)")
      ->check([](const std::string& v) {
        try {
          parse_thresholds(v);
          return std::string();
        } catch (const std::exception& e) {
          return std::string(e.what());
        }
      })
      ->capture_default_str()
      ->group(group);
}

ModelBake bake_model(const TriangleMesh& mesh, const std::string& mesh_path, std::uint64_t mesh_hash,
                     bool sampling_given, const BoxParams& params, const std::string& cache_dir) {
  Communicator& comm = communicator();
  BakeRecipe recipe;
  if (sampling_given) {
    recipe.options.params = params;
    // Baked across the ranks of an MPI job; every rank needs the scene for the evaluation.
    recipe.options.communicator = &comm;
    recipe.options.scene_on_every_rank = true;
  } else {
    recipe = default_recipe();  // one process's bake: each rank of a job bakes it alone
  }
  recipe.options.progress = terminal_progress("bake");
  // The cache only for the default and one process: ranks must not evaluate different scenes
  // (a cached one and a fresh one of another build).
  std::optional<BoxCache> cache;
  if (!sampling_given && !cache_dir.empty() && comm.size() == 1) cache.emplace(cache_dir);
  const SourceInfo source{mesh_path, mesh_hash, mesh.triangle_count(), mesh.bounds().diagonal()};
  const auto start = std::chrono::steady_clock::now();
  CachedBake baked = bake_cached(mesh, recipe, source, cache ? &*cache : nullptr);
  if (!baked.warning.empty() && comm.is_root()) std::cerr << "hapticbox: warning: " << baked.warning << "\n";
  ModelBake out{std::move(baked.result.scene), baked.from_cache, baked.path, 0.0, !sampling_given};
  out.seconds = baked.from_cache ? 0.0 : std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return out;
}


void add_route_option(CLI::App& cmd, std::string& route) {
  cmd.add_option("--route", route,
                 "Refined scenes: auto (default: the route the bake chose and stored), cells (the first crossing "
                 "among the surface cells' triangles answers, no box asked), embree (exact Embree over the scene's "
                 "surface) or boxes (the grid's boxes answer from their triangle ids, the cells' triangles confirm)")
      ->check(CLI::IsMember({"auto", "boxes", "cells", "embree"}))
      ->capture_default_str();
}

void apply_route(BoxScene& scene, const std::string& route) {
  if (route == "auto") return;
  if (route == "boxes" && scene.refines() && !scene.has_triangle_ids())
    throw UsageError("--route boxes: this scene holds no triangle ids (the default bake drops them: the cells route "
                     "does not read them); bake it with HB_MEASURE=keep-ids to compare the routes");
  if (route == "embree") {
    try {
      scene.set_route(SceneRoute::embree);
    } catch (const InvalidInput& e) {
      throw UsageError(std::string("--route embree: ") + e.what());
    }
    return;
  }
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

void check_output_file(const std::string& path) {
  namespace fs = std::filesystem;
  std::error_code ec;
  if (fs::is_directory(path, ec)) throw IoError(path + ": is a folder, not an output file");
  const fs::path parent = fs::path(path).parent_path().empty() ? fs::path(".") : fs::path(path).parent_path();
  if (!fs::is_directory(parent, ec)) throw IoError(path + ": cannot write (no folder " + parent.string() + ")");
  // Only rank 0 writes the output, so only rank 0 looks. An existing file is opened for append
  // (its bytes untouched); a new one is tried under a name of this process's own, so the output
  // path never exists before the command has written it, whatever ends the job meanwhile.
  if (!communicator().is_root()) return;
  if (fs::exists(path, ec)) {
    std::ofstream probe(path, std::ios::app | std::ios::binary);
    if (!probe) throw IoError(path + ": cannot write (" + std::strerror(errno) + ")");
    return;
  }
  const std::string trial = path + ".write-check-" + std::to_string(::getpid());
  {
    std::ofstream probe(trial, std::ios::binary);
    if (!probe) throw IoError(path + ": cannot write (" + std::strerror(errno) + ")");
  }
  fs::remove(trial, ec);
}

void check_output_folder(const std::string& path) {
  namespace fs = std::filesystem;
  std::error_code ec;
  if (fs::exists(path, ec) && !fs::is_directory(path, ec)) throw IoError(path + ": is a file, not an output folder");
  fs::create_directories(path, ec);
  if (ec) throw IoError(path + ": cannot create the folder (" + ec.message() + ")");
  const fs::path probe = fs::path(path) / ".hapticbox-write-check";
  {
    std::ofstream out(probe);
    if (!out) throw IoError(path + ": cannot write in the folder (" + std::strerror(errno) + ")");
  }
  fs::remove(probe, ec);
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
#include "model_options_key.h"
#endif

namespace hb::cli {

void add_model_options(CLI::App& cmd, ModelArgs& args) {
  const std::string group = "Reading the model";
  cmd.add_option("--unit", args.unit,
                 "Length of one model unit: mm, cm, m, um, in, ft (default: the file's unit, else mm); the model is "
                 "scaled to mm")
      // An unknown unit is a usage error (exit 2), said before any file is read.
      ->check(CLI::Validator(
          [](std::string& unit) -> std::string {
            static const char* const known[] = {"mm", "millimetre", "millimeter", "cm", "centimetre", "centimeter",
                                                "m", "metre", "meter", "um", "micrometre", "micron", "in", "inch",
                                                "ft", "foot"};
            std::string u = unit;
            std::transform(u.begin(), u.end(), u.begin(), [](unsigned char c) { return char(std::tolower(c)); });
            for (const char* k : known)
              if (u == k) return {};
            return "unknown unit '" + unit + "' (use mm, cm, m, um, in or ft)";
          },
          "UNIT"))
      ->group(group);
  cmd.add_option_function<std::string>(
         "--volume",
         [&args](const std::string& spec) {
           parse_spec("--volume", spec,
                      {{"iso", [&args](const std::string& v, const std::string& what) {
                          args.iso = spec_number_or_usage(v, what, -1e30, 1e30);
                        }},
                       {"label", [&args](const std::string& v, const std::string& what) {
                          const double x = spec_number_or_usage(v, what, -9.2e18, 9.2e18);
                          if (x != std::floor(x)) throw UsageError(what + ": '" + v + "' is not a whole number");
                          args.label = long(x);
                        }},
                       number_key("smooth", args.smooth, 0, 1000),
                       number_key("triangles", args.target_triangles, 0, 1e15)});
           if (args.iso && args.label) throw UsageError("--volume: iso and label exclude each other (give one)");
         },
         "Volumes: iso=V (the surface's iso-value in the file's calibrated units, HU for CT; default: the Otsu "
         "threshold, see `info`) or label=L (label maps: the voxels with this label), smooth=N (windowed-sinc "
         "iterations, 0-1000; default 0), triangles=N (decimate to about N; default 0: keep all). Reader limits: "
         "$HB_READER_TIMEOUT_S (default 120 s), $HB_READER_MEMORY_MB (default 8192)")
      ->type_name("iso=V|label=L,smooth=N,triangles=N")
      ->group(group);
  cmd.add_option_function<std::string>(
         "--cad",
         [&args](const std::string& spec) {
           parse_spec("--cad", spec,
                      {{"chordal-mm", [&args](const std::string& v, const std::string& what) {
                          args.chordal_mm = spec_number_or_usage(v, what, 0.0, 1e30);
                        }},
                       {"force-tolerance", [&args](const std::string& v, const std::string& what) {
                          args.force_tolerance_n = spec_number_or_usage(v, what, 1e-30, 1e30);
                        }},
                       flag_key("accept-lost-faces", args.accept_lost_faces)});
         },
         "CAD (STEP, IGES): chordal-mm=D (the tessellation's chordal deviation in mm; default: force-tolerance / "
         "stiffness 500 N/m), force-tolerance=N (the force error in N it may cause; default 0.01), "
         "accept-lost-faces (keep a model some of whose faces failed to translate or tessellate; default: refuse "
         "it)")
      ->type_name("chordal-mm=D,force-tolerance=N,accept-lost-faces")
      ->group(group);
}

#ifndef HB_WITH_VTK
namespace {
bool has_model_args(const ModelArgs& a) {
  return a.iso || a.label || !a.unit.empty() || a.smooth || a.target_triangles || a.chordal_mm > 0 || a.accept_lost_faces;
}
} // namespace
#endif

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
    // Figures as the rest of the tool prints them (4 significant digits), not raw doubles.
    const auto list = [](const nlohmann::json& v, const char* sep) {
      std::string out;
      for (std::size_t i = 0; v.is_array() && i < v.size(); ++i)
        out += (i ? sep : "") + (v[i].is_number() ? sig(v[i].get<double>(), 4) : v[i].dump());
      return out;
    };
    std::cerr << "hapticbox: " << path << ": " << model.format << " " << list(model.facts["dimensions"], " x ")
              << " voxels, spacing " << list(model.facts["spacing_mm"], " x ") << " mm, ";
    if (model.facts.contains("label")) std::cerr << "label " << model.facts["label"].dump();
    else std::cerr << "iso " << sig(model.facts["iso"].get<double>(), 4) << (args.iso ? "" : " (automatic; set --iso)");
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
  if (has_model_args(args)) throw UsageError("--volume, --unit and --cad need the VTK pipelines (HB_BUILD_VTK)");
  MeshReadReport local;
  TriangleMesh mesh = read_mesh(path, &local);
  for (const std::string& w : local.warnings) std::cerr << "hapticbox: warning: " << w << "\n";
  if (report) *report = local;
  return mesh;
#endif
}
} // namespace

std::uint64_t hash_model(const std::string& path, const ModelArgs& args) {
#ifdef HB_WITH_VTK
  // The window keys its bakes by the same text (hb::vtk::model_options_key).
  return hb::hash_model(path, hb::vtk::model_options_key(to_model_options(args)));
#else
  (void)args;  // without VTK no option shapes the surface (load_mesh refuses them)
  return hb::hash_model(path);
#endif
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
          {"perceptible_share", r.perceptible},
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
  // What answers, and why: the raw samplings tried, in the perceptual currency.
  j["answer"] = r.answer.empty() ? "cells" : r.answer;
  nlohmann::json raw = nlohmann::json::array();
  for (const BudgetReport::RawTried& t : r.raw_tried)
    raw.push_back({{"m", t.m}, {"n", t.n}, {"bytes", t.bytes}, {"probes_felt", t.probes_felt},
                   {"slide_ticks_felt", t.ticks_felt < 0 ? nlohmann::json(nullptr) : nlohmann::json(t.ticks_felt)},
                   {"outcome", t.outcome}});
  j["raw_tried"] = raw;
  // Query times at bake time (this run's, bake --json only).
  if (r.answer_ns > 0) j["answer_ns"] = r.answer_ns, j["exact_ns"] = r.exact_ns;
  if (r.cells_ns > 0) j["cells_ns"] = r.cells_ns, j["embree_ns"] = r.embree_ns;
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
