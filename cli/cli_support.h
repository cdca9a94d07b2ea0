#pragma once
// What the sub-commands share: the ranks of the run, the command line as typed, the probe,
// cache and route options, the bake of a model given without a box file, JSON output and the
// checks of a box file against its mesh. Each shared option group has its own header, included
// here so that a command includes one file.
#include "budget_json.h"
#include "codec_options.h"
#include "eval_json.h"
#include "measurement_switches.h"
#include "model_args.h"
#include "output_checks.h"
#include "spec_option.h"
#include "terminal_progress.h"
#include "workspace_options.h"
#include "codec/codec.h"
#include "contact/contact.h"
#include "contact/workspace.h"
#include "evaluation/comparison.h"
#include "scene/box_scene.h"
#include "scene/scene_extent.h"
#include "math/bounds.h"
#include "parallel/communicator.h"
#include "progress.h"
#include "recipe/error_budget.h"
#include "recipe/recipe_choice.h"
#include "spec_parse.h"
#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>
#include <cstdint>
#include <functional>
#include <optional>
#include <stdexcept>
#include <string>
#include <type_traits>
#include <vector>

namespace hb::cli {

/// The ranks sharing this run: set by main (an MPI communicator under mpirun or srun, a
/// serial one otherwise). Commands pass it to the core functions that split their work.
Communicator& communicator();
void set_communicator(Communicator* communicator);

/// --samples N and --seed S, the probes (hb::sample_probes) of every command that measures: the
/// same count and seed give the same probes everywhere. `min_samples` 0 allows "no probes".
void add_probe_options(CLI::App& cmd, std::size_t& samples, std::uint64_t& seed, std::size_t min_samples = 1);

/// --cache DIR|none: the box cache directory (default hb::default_box_cache_dir()); "none":
/// bake without the cache and store nothing in it (`dir` is then empty).
void add_cache_option(CLI::App& cmd, std::string& dir);

/// The sampling options (-m, -n, --cell, --refine) given to `cmd`, for hb::choose_recipe; an
/// option the command does not define counts as not given.
SamplingGiven sampling_given(const CLI::App& cmd);

/// The bake a command makes of a MESH it was given without a box file (report, field): the
/// default (budgeted) bake through the box cache, as `bake`, ./run.sh and the window make it,
/// or, when the user gave a sampling option (hb::choose_recipe), exactly one raw box of it,
/// shared across the ranks of an MPI job. `seconds` is the whole bake's wall time (0 from the cache).
struct ModelBake {
  BoxScene scene;
  bool from_cache = false;
  std::string cache_path;  ///< the cache entry the scene came from or went to (may be empty).
  double seconds = 0.0;
  bool default_recipe = true;
};
/// `params`: the sampling when `given` has any; `cache_dir` empty: no cache.
ModelBake bake_model(const TriangleMesh& mesh, const std::string& mesh_path, std::uint64_t mesh_hash,
                     const SamplingGiven& given, const BoxParams& params, const std::string& cache_dir);

/// Adds --route boxes|cells (hb::SceneRoute) to a command; `route` holds the name.
void add_route_option(CLI::App& cmd, std::string& route);
/// Sets `scene`'s route from --route's name; warns on stderr when the scene has no surface
/// cells (then every query takes the boxes' path).
void apply_route(BoxScene& scene, const std::string& route);

/// Prints JSON to stdout (indented), with `ranks`: how many ranks shared the work (only rank
/// 0 prints: the other ranks' standard output is discarded by main).
void print_json(const nlohmann::json& j);

/// True when `path` names a box file (by its magic bytes, not its extension).
bool is_box_file(const std::string& path);

/// Fails (hb::InvalidInput, exit 1) when `scene` records a source hash that differs from
/// `mesh_hash`: evaluating a box against another mesh measures nothing. With `force`, warns on
/// stderr instead and goes on.
void check_same_mesh(const BoxScene& scene, const std::string& box_path, const std::string& mesh_path,
                     std::uint64_t mesh_hash, bool force);

/// After a bake or compress with --ratio R: when the codec ended below R (at its largest error
/// bound), warns on stderr with what it reached, and throws hb::Error (exit 1) when `strict`.
/// Sets j["ratio_target"], j["ratio_reached"]. No-op when no ratio was asked (target <= 0).
void check_ratio_target(double target, double achieved, double bound, double t_error_mean, bool strict,
                        nlohmann::json& j);

/// The command line as typed (set by main; arguments with spaces quoted), for reports.
const std::string& command_line();
void set_command_line(int argc, char** argv);

/// Lower-case extension of a path with its dot (".vtp"), or empty.
std::string lower_extension(const std::string& path);

} // namespace hb::cli
