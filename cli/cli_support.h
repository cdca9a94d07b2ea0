#pragma once
// Small pieces the sub-commands share: the failure type that carries an exit code, the
// terminal progress bar, the force-law options and JSON output.
#include "codec/codec.h"
#include "contact/contact.h"
#include "contact/workspace.h"
#include "eval_json.h"
#include "evaluation/comparison.h"
#include "recipe/error_budget.h"
#include "parallel/communicator.h"
#include "progress.h"
#include "spec_parse.h"
#include <functional>
#include <type_traits>
#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>
#include <cstdint>
#include <optional>
#include <stdexcept>
#include <vector>
#include <string>

#include "haptic_box/box_scene.h"
#include "math/bounds.h"

namespace hb::cli {

/// Thrown by a command for a usage error the parser could not catch (exit code 2).
class UsageError : public std::runtime_error {
public:
  explicit UsageError(const std::string& what) : std::runtime_error(what) {}
};

/// Validator of a numeric option: a finite number in [lo, hi] (CLI::Range lets "nan" through,
/// since no comparison with NaN fails). The message names the value and the range.
CLI::Validator finite_range(double lo, double hi);

/// The ranks sharing this run: set by main (an MPI communicator under mpirun or srun, a
/// serial one otherwise). Commands pass it to the core functions that split their work.
Communicator& communicator();
void set_communicator(Communicator* communicator);

/// A progress callback drawing a bar on stderr when it is a terminal (silent otherwise, and
/// on every rank but 0: rank 0 reports for the whole job).
ProgressCallback terminal_progress(const std::string& label);
/// Erases the progress bar's line on a terminal (stderr), so that a line printed now (a table
/// row on stdout) starts at the left margin instead of after the bar; the bar comes back at
/// its next report.
void clear_progress_line();
/// The text after a terminal progress bar: elapsed time and, from 1 % and 1 s on, the time left
/// at the rate so far ("12.3 s elapsed, ETA 41.2 s"; "done in 53.5 s" at the end).
std::string progress_eta_text(double elapsed_seconds, double fraction);

/// Adds --max-error, --ratio (mutually exclusive) and --normal-bits to a command; returns the
/// --max-error option (to tell whether it was given).
/// `strict` (optional): adds --strict, failing the command when --ratio's target is not met.
CLI::Option* add_codec_bound_options(CLI::App& cmd, CodecOptions& options, bool* strict = nullptr);

/// One key of a spec option ("--codec block,ratio=20,strict"): its name and what it sets from
/// its value ("" for a bare key); `what` names the option and key for error messages.
struct SpecKey {
  std::string key;
  std::function<void(const std::string& value, const std::string& what)> set;
};
/// Parses "[head,]key=value,key,..." given to `option`: each item sets its key (any order, any
/// subset); `head` (when not null) receives a first item that is not one of the keys. Throws
/// UsageError (exit 2) naming the option and the unknown key (with the known ones) or the bad
/// value.
void parse_spec(const std::string& option, const std::string& spec, const std::vector<SpecKey>& keys,
                std::string* head = nullptr);
/// hb::spec_number, its hb::InvalidInput a UsageError.
double spec_number_or_usage(const std::string& text, const std::string& what, double lo, double hi);
/// A key setting a number in [lo, hi] (integers for integral fields).
template <class T>
SpecKey number_key(const std::string& key, T& field, double lo, double hi) {
  return {key, [&field, lo, hi](const std::string& v, const std::string& what) {
            const double x = spec_number_or_usage(v, what, lo, hi);
            if (std::is_integral<T>::value && x != double(static_cast<long long>(x)))
              throw UsageError(what + ": '" + v + "' is not a whole number");
            field = static_cast<T>(x);
          }};
}
/// A key setting a flag: bare or =1/on/yes true, =0/off/no false.
SpecKey flag_key(const std::string& key, bool& field);

/// Measurement-only switches (before/after comparisons, not a user's options): read from the
/// environment variable HB_MEASURE, one place, as "name[=value],..." (e.g.
/// HB_MEASURE=full-search,spin-us=0). The names are listed in measurement_names(); an unknown
/// one is a usage error. Empty optional: not given.
std::optional<std::string> measurement(const std::string& name);
const std::vector<std::string>& measurement_names();
/// A measurement switch's value among `allowed` (`fallback` when not given); a value outside
/// them is a usage error naming it.
std::string measurement_choice(const std::string& name, const std::string& fallback,
                               const std::vector<std::string>& allowed);
/// The automatic decomposition's phase callback of HB_MEASURE=decompose-times (each phase's
/// end on stderr), or an empty one.
std::function<void(const char*, double)> decompose_times();
/// Reads HB_MEASURE now (main, before parsing): an unknown switch fails every command alike.
void check_measurements();

/// --codec NAME[,max-error=E|ratio=R][,normal-bits=B][,strict]: the table codec and its bound,
/// into `codec` (name) and `options` (bound); `strict` (optional) allows the strict key,
/// failing the command when the ratio's target is not met. `given` (optional) is set when a
/// bound (max-error or ratio) was given. `allowed`: the codec names.
CLI::Option* add_codec_option(CLI::App& cmd, std::string& codec, CodecOptions& options, bool* strict,
                              bool* bound_given, const std::vector<std::string>& allowed, const std::string& help);

/// --samples N and --seed S, the probes (hb::sample_probes) of every command that measures: the
/// same count and seed give the same probes everywhere. `min_samples` 0 allows "no probes".
void add_probe_options(CLI::App& cmd, std::size_t& samples, std::uint64_t& seed, std::size_t min_samples = 1);

/// --cache DIR|none: the box cache directory (default hb::default_box_cache_dir()); "none":
/// bake without the cache and store nothing in it (`dir` is then empty).
void add_cache_option(CLI::App& cmd, std::string& dir);

/// The one scale every figure is judged at (hb::Workspace) and how differences are judged
/// (hb::PerceptualJudge), as the options of every command that computes forces give them.
struct WorkspaceArgs {
  double workspace_mm = WorkspaceOptions::kDefaultDiagonalM * 1000.0;
  bool real_size = false;
  double metres_per_unit = 0.0;  ///< > 0: an explicit scale.
  double stiffness = WorkspaceOptions::kDefaultStiffness;
  double max_force = WorkspaceOptions::kDefaultMaxForce;
  std::string perceptual = "nominal";

  WorkspaceOptions options() const;
  /// The workspace of a model of this diagonal (model units).
  Workspace workspace(double model_diagonal) const;
  /// The thresholds (--perceptual) and the force limit.
  PerceptualJudge judge() const;
};

/// The axis-aligned bounds of a scene's boxes (the union of their PBB corners), model units;
/// the servo loop centres the device's workspace on them. Empty bounds for no boxes.
Bounds scene_bounds(const BoxScene& scene);

/// The diagonal of the mesh a box file was baked from (SourceInfo::diagonal), or of its
/// boxes' bounds for a file that does not record it.
double model_diagonal(const BoxScene& scene);

/// Adds the workspace and judgement options to a command: --workspace (mm, real-size or
/// metres-per-unit; stiffness, max-force) and --perceptual.
void add_workspace_options(CLI::App& cmd, WorkspaceArgs& args);

/// The bake a command makes of a MESH it was given without a box file (report, field): the
/// default (budgeted) bake through the box cache, as `bake`, ./run.sh and the window make it,
/// or, when the user asked for a sampling (-m / -n), exactly one raw box of it, shared across
/// the ranks of an MPI job. `seconds` is the whole bake's wall time (0 from the cache).
struct ModelBake {
  BoxScene scene;
  bool from_cache = false;
  std::string cache_path;  ///< the cache entry the scene came from or went to (may be empty).
  double seconds = 0.0;
  bool default_recipe = true;
};
/// `params`: the sampling when `sampling_given`; `cache_dir` empty: no cache.
ModelBake bake_model(const TriangleMesh& mesh, const std::string& mesh_path, std::uint64_t mesh_hash,
                     bool sampling_given, const BoxParams& params, const std::string& cache_dir);


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

/// Checks, before any long work, that the output file `path` can be written: opens it for
/// appending (creating it, then removing it again when it did not exist). Throws hb::IoError
/// naming the path and the cause (no such folder, a folder, permission, read-only).
void check_output_file(const std::string& path);
/// The same for an output folder: creates it if needed and writes and removes a probe file.
void check_output_folder(const std::string& path);

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

namespace hb {
struct TriangleMesh;
struct MeshReadReport;
}

#ifdef HB_WITH_VTK
#include "model_loader.h"
#endif

namespace hb::cli {

/// How a model file becomes a mesh (--unit, --volume, --cad; see hb::vtk::ModelOptions).
/// Every command that takes a mesh takes these, so it also takes a volume, a CAD solid or a
/// glTF/3MF/FBX/Collada scene.
struct ModelArgs {
  std::optional<double> iso;
  std::optional<long> label;
  std::string unit;
  int smooth = 0;
  std::size_t target_triangles = 0;
  double chordal_mm = 0.0;
  double force_tolerance_n = 0.01;
  bool accept_lost_faces = false;  ///< CAD: keep a model some of whose faces failed to translate.
  /// Filled by load_mesh: what the loader found (format, unit, volume/CAD facts) and, for CAD
  /// solids, the face of each triangle (used by --pieces faces).
  mutable nlohmann::json facts;
  mutable std::vector<std::uint32_t> face_ids;
};

#ifdef HB_WITH_VTK
/// The loader's options for `args` (for the commands that run vtkHapticBoxMeshReader).
hb::vtk::ModelOptions to_model_options(const ModelArgs& args);
#endif

/// Adds --unit, --volume (iso, label, smooth, triangles) and --cad (chordal-mm, force-tolerance,
/// accept-lost-faces). The readers' limits come from $HB_READER_TIMEOUT_S and $HB_READER_MEMORY_MB.
void add_model_options(CLI::App& cmd, ModelArgs& args);

/// Reads a model (mesh, volume, CAD, scene; in millimetres), printing the reader's warnings to
/// stderr, and on stderr one line saying how a volume or CAD file became triangles.
TriangleMesh load_mesh(const std::string& path, const ModelArgs& args = {}, MeshReadReport* report = nullptr);
/// Reads a mesh with the default model options.
TriangleMesh load_mesh(const std::string& path, MeshReadReport* report);

/// hb::hash_model (mesh/file_hash.h) of `path` with the loader options of `args` (their text
/// when any differs from its default): the hash a box file records for its source.
std::uint64_t hash_model(const std::string& path, const ModelArgs& args = {});

/// A budgeted bake's report as JSON (null when the scene was not baked to a budget):
/// the budget, met, the fresh-probe figures and seed, the tuning figures, the per-piece choices.
nlohmann::json budget_json(const BudgetReport& report);

}
