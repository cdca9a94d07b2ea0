#pragma once
// Speed against accuracy: bake, evaluate and time a grid of box configurations next to
// reference methods measured in the same run on the same probe segments.
#include "evaluation/comparison.h"
#include "evaluation/probe_sampling.h"
#include "recipe/bake_recipe.h"
#include "recipe/error_budget.h"
#include "progress.h"
#include <functional>
#include <string>
#include <vector>

namespace hb {

/// One box configuration: densities and the table codec ("none": plain 8-byte samples; "haar"
/// or "block": compressed at the codec's default error bound; other names are rejected with
/// hb::InvalidInput).
struct SweepConfig {
  int m = 32;
  int n = 16;
  std::string codec = "none";
  bool refine = false;  ///< bake with triangle ids: queries refine exactly (BakeOptions::refine).
};

/// Throws hb::InvalidInput when m or n is below 2 or the codec is unknown to this build.
void check_sweep_config(const SweepConfig& config);

/// The grid ms x ns x codecs x refines, in that nesting order (m slowest).
std::vector<SweepConfig> sweep_grid(const std::vector<int>& ms, const std::vector<int>& ns,
                                    const std::vector<std::string>& codecs = {"none"},
                                    const std::vector<bool>& refines = {false});

/// A method measured by the sweep that is not a box: the exact reference (Embree), VTK's
/// locator, ... `query` must outlive the sweep.
struct SweepReference {
  std::string method;              ///< e.g. "exact_embree", "vtk_static_cell_locator".
  const ContactQuery* query = nullptr;
  std::size_t memory_bytes = 0;    ///< what the method keeps in memory (estimate where noted).
  double build_seconds = 0.0;      ///< acceleration-structure build time.
};

/// One row of the sweep table.
struct SweepRow {
  std::string method;              ///< "haptic_box" or a reference's name.
  int m = 0, n = 0;                ///< 0 for references.
  std::string codec;               ///< empty for references.
  bool refine = false;             ///< the box refines exactly (SweepConfig::refine).
  double query_ns = 0.0;           ///< median ns per query, one core (hb::median_query_ns).
  std::size_t memory_bytes = 0;    ///< tables (+ triangle ids and surface when refining) for boxes; the reference's figure otherwise.
  double bake_seconds = 0.0;       ///< bake (or build) time; 0 when the box came from the cache.
  bool from_cache = false;         ///< the box was loaded from the cache directory.
  double force_error_median = 0.0; ///< against the exact reference, both-contact probes.
  double force_error_p95 = 0.0;
  double contact_agreement = 0.0;
  double angle_error_median_deg = 0.0;
  double angle_error_p99_deg = 0.0;
  /// The headline: share of the probes whose difference a hand would feel (hb::perceive at
  /// SweepOptions::judge, forces at the workspace's scale).
  double perceptible_share = 0.0;
  /// Every figure within SweepOptions::budget (hb::meets_budget: agreement, median and p95
  /// force error, direction p99); the references count too (exact is within any budget).
  bool within_budget = false;
  bool pareto = false;             ///< on the Pareto front (see mark_pareto_front).
  /// A raw sampling a budgeted bake tried, read off its budget report (hb::bake_chart_points:
  /// its time at bake time, its share of the bake's tuning probes), not a row this sweep measured.
  bool tried_by_the_bake = false;
  /// The accuracy figures above from `s` (a comparison against the exact reference), and
  /// within_budget by `budget`: one place for `sweep`'s rows and the report's own row.
  void set_accuracy(const ComparisonStats& s, const ErrorBudget& budget);
  /// What charts call a row that is not one (m, n) configuration, e.g. a report's own scene
  /// of several boxes ("scene: 19 boxes, m 8-26, n 6-8"); empty: "m<m> n<n>".
  std::string label;
};

/// Options of run_sweep.
struct SweepOptions {
  std::vector<SweepConfig> configs = sweep_grid({8, 16, 32, 64}, {4, 8, 16});
  std::size_t samples = 20000;     ///< probes (hb::sample_probes) for accuracy and timing.
  int timing_rounds = 5;           ///< passes of median_query_ns.
  ProbeOptions probes;             ///< the default probe distribution.
  ForceLaw law;                    ///< the workspace's (hb::Workspace::law).
  PerceptualJudge judge;           ///< what a hand tells apart (SweepRow::perceptible_share).
  /// The budget each row is checked against (SweepRow::within_budget); the default budget's.
  ErrorBudget budget;
  /// The bake every configuration starts from: pieces (cut once for the whole sweep), seams,
  /// padding; each configuration sets m, n and refinement, and its codec is applied to the
  /// raw scene in memory. Its progress callbacks are replaced by `progress`.
  BakeRecipe recipe;
  /// Box cache directory (hb::BoxCache; raw scenes keyed by the mesh hash and each
  /// configuration's whole recipe); empty: no cache. Used only with `source.mesh_hash` != 0.
  std::string cache_dir;
  /// Progress in [0, 1] from the calling thread; false cancels (throws hb::Cancelled).
  ProgressCallback progress;
  /// Called with each row as soon as it is measured (e.g. to print it); on rank 0 only.
  std::function<void(const SweepRow&)> on_row;
  /// The ranks sharing the sweep (nullptr: this process alone). Every rank calls run_sweep
  /// with the same arguments. Each configuration is baked across all ranks (its position
  /// points dealt, the tables gathered on every rank, BakeOptions::scene_on_every_rank),
  /// evaluated across all ranks (the probes dealt, the answers gathered on rank 0,
  /// compare_queries) and timed on one core of one rank (configuration k on rank k % ranks),
  /// so every rank has its share of every configuration, however unequal the configurations
  /// (m = 64 alone is half the rays of the default grid). The rows are one process's, timings
  /// aside; rank 0 saves the cache files.
  Communicator* communicator = nullptr;
  /// Also measure the product's default bake (hb::default_recipe: what `hapticbox bake MESH -o
  /// BOX` and the window's Bake make, the budgeted bake) on the same probes, after the
  /// configurations: one row labelled "default bake: N box(es)", through the cache like them.
  /// The budgeted bake is one process's: every rank bakes it alone (the same scene), rank 0
  /// alone reads and fills the cache.
  bool default_bake = false;
  /// When given, receives on rank 0 each rank's share: `work` rays cast plus probes answered
  /// plus queries timed, `seconds` busy (its bake and evaluation shares and its timings),
  /// `bytes_sent`.
  std::vector<RankWork>* rank_work = nullptr;
};

/// Runs the sweep: the references first (the first one is the ground truth, normally exact
/// Embree; its own row has zero error), then each configuration: bake (or load from the
/// cache, saving new bakes to it), evaluate on the same probes, time on one core.
/// Pieces (options.recipe.pieces) give one box per piece, the pieces sharing their seams as
/// `hapticbox bake` does (hb::bake); cached scenes are keyed by the pieces. Only one
/// configuration is held in memory at a time. Returns the rows with the Pareto front marked.
/// Throws hb::InvalidInput (no reference, bad configuration or codec), hb::IoError (cache),
/// hb::Cancelled.
std::vector<SweepRow> run_sweep(const TriangleMesh& mesh, const SourceInfo& source, const std::vector<SweepReference>& references,
                                const SweepOptions& options);

/// Marks the Pareto front over query_ns and accuracy: the perceptible share, then the median
/// relative force error where the shares are equal: a row is on it when no other row is at
/// least as fast and at least as accurate, and strictly better in one.
void mark_pareto_front(std::vector<SweepRow>& rows);

/// What a haptic-box row is, in words: its label (a scene, the default bake) or "m<m> n<n>",
/// then its codec unless "none" and " ref" when it refines ("m16 n8 block ref").
std::string configuration_name(const SweepRow& row);

/// The fastest haptic-box row within its budget (SweepRow::within_budget), or null: the
/// cheapest configuration that models no more than the budget asks.
const SweepRow* fastest_within_budget(const std::vector<SweepRow>& rows);

} // namespace hb
