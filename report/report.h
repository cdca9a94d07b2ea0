#pragma once
// Error reports: the figures a user asks for ("how much accuracy for how much speed and memory,
// and where is it wrong?") computed once and written as report.html (self-contained, charts
// embedded), summary.json (every figure and parameter, versions and hashes) and samples.csv
// (one row per probe with both answers). The CLI's `report` and the desktop window call these.
#include "contact/workspace.h"
#include "evaluation/comparison.h"
#include "evaluation/error_field.h"
#include "stability/stability_suite.h"
#include "recipe/sweep.h"
#include "evaluation/worst_probes.h"
#include "scene/box_scene.h"
#include "scene/density_range.h"
#include <memory>
#include <string>
#include <utility>
#include <vector>

namespace hb {

/// Stated tolerances a report checks. The verdict (pass) is the headline's: at most this
/// share of the probes perceptibly different from exact (the default bake's budget, 0.1 %);
/// the relative figures are checked as secondary columns and do not decide it.
struct ReportTolerances {
  double perceptible = 0.001;        ///< max share of probes perceptibly different (hb::perceive).
  double force_error_median = 0.02;  ///< max median relative force error (the budget's).
  double force_error_p95 = 0.07;     ///< max 95th percentile (the budget's).
  double contact_agreement = 0.995;  ///< min fraction of probes where contact flags agree (the budget's).
};

/// Options of compute_report.
struct ReportOptions {
  std::size_t samples = 20000;       ///< probes for accuracy and timing (hb::sample_probes).
  ProbeOptions probes;               ///< the default probe distribution (eval's).
  /// The scale forces are computed and judged at (hb::make_workspace on the mesh's diagonal:
  /// ReportData::workspace) and what a hand tells apart.
  WorkspaceOptions workspace;
  PerceptualJudge judge;
  int timing_rounds = 5;
  ReportTolerances tolerances;
  /// Extra box configurations measured for the speed-vs-accuracy chart (the report's own
  /// box is always a row). Empty: none.
  std::vector<SweepConfig> sweep_configs;
  std::string cache_dir;             ///< sweep box cache (see SweepOptions::cache_dir).
  int error_field_probes_per_vertex = 1; ///< 0: no error field.
  /// Codec whose compression curve (ratio against median force error versus the raw tables,
  /// over the codec's error bounds) the report draws: "" for none, "haar" or "block" (another
  /// name: hb::InvalidInput). Needs a raw (uncompressed) scene.
  std::string compression_codec;
  ProgressCallback progress;         ///< [0, 1], calling thread; false cancels.
  /// The ranks sharing the report (nullptr: this process alone). Every rank calls
  /// compute_report with the same arguments (and the whole scene); the evaluation, the sweep
  /// and the error field split their probes and bakes across the ranks (see compare_queries,
  /// SweepOptions::communicator, ErrorFieldOptions::communicator). The ReportData is complete
  /// on rank 0 only, which writes the report; the figures are one process's, timings aside.
  Communicator* communicator = nullptr;
};

/// Everything a report shows.
struct ReportData {
  std::string product_version;
  std::string mesh_path, box_path;       ///< box_path empty when baked for the report.
  std::uint64_t mesh_hash = 0, box_hash = 0;
  std::size_t vertices = 0, triangles = 0, pieces = 0;
  float diagonal = 0.f;
  BoxParams params;                      ///< the first box's (see `densities` for all boxes).
  DensityRange densities;                ///< m and n over the scene's boxes.
  std::string codec = "none";
  bool refine = false;                   ///< the boxes refine exactly (bake --refine).
  hb::Answerer route = hb::Answerer::boxes;  ///< what answered the queries the figures were measured on.
  /// What answers a probe's successive queries (the servo loop, the window): Answerer::embree
  /// when the bake kept Embree over the full mesh for them (BoxScene::stroke_route), else
  /// `route`; and the two times the bake measured along strokes (ns; 0: not timed).
  hb::Answerer stroke_route = hb::Answerer::boxes;
  double stroke_cells_ns = 0.0, stroke_embree_ns = 0.0;
  std::size_t memory_bytes = 0;          ///< box tables, plus triangle ids and surface when refining.
  double bake_seconds = 0.0;             ///< 0 when loaded from a file.
  ComparisonStats stats;                 ///< the report's box against the exact reference.
  ComparisonStats light_touch;           ///< as many light touches at any angle (light_touch_probe_options).
  std::vector<WorstProbe> worst;         ///< the worst probes of `records` (hb::worst_probes).
  std::vector<ProbeRecord> records;      ///< one per probe (samples.csv).
  std::vector<SweepRow> rows;            ///< references, sweep configurations and the box itself.
  double box_ns = 0.0;                   ///< query time of the report's box.
  bool pass_perceptible = false, pass_median = false, pass_p95 = false, pass_agreement = false;
  Workspace workspace;                   ///< the scale of every force in the report.
  ErrorField error_field;                ///< per vertex (empty when disabled).
  double error_field_median = 0.0, error_field_p95 = 0.0; ///< over vertices with data.
  std::string error_field_image;         ///< PNG path of the rendered field, or empty.
  std::string error_field_note;          ///< why there is no image, when there is none.
  std::vector<std::pair<double, double>> compression_curve; ///< empty when no codec.
  /// The stability suite's results (hapticbox report --stability), or null: the stability
  /// section of report.html and "stability" in summary.json (report/stability_section.h).
  std::shared_ptr<const StabilityReport> stability;
  ReportOptions options;
  std::string generated_at;              ///< UTC date and time, ISO 8601 (set by compute_report).
  std::string machine;                   ///< host, CPU model and cores (set by compute_report).
  std::string command_line;              ///< how the report was asked for (the caller's), or empty.
  double compute_seconds = 0.0;
  int ranks = 1;                         ///< ranks that shared the computation.
  bool pass() const { return pass_perceptible; }
};

/// Evaluates `scene` against the first reference (exact Embree) on the same probes as
/// `hapticbox eval` (same count, same seed: same figures), times every method on one core,
/// measures the extra sweep configurations (baked from `mesh` and `pieces`) and computes the
/// per-vertex error field. `bake_seconds`: how long `scene` took to bake (0: loaded). Fills
/// everything but the paths, hashes, version and image, which the caller knows. Throws hb::InvalidInput, hb::Cancelled.
ReportData compute_report(const TriangleMesh& mesh, const std::vector<std::uint32_t>& pieces,
                          const BoxScene& scene, double bake_seconds,
                          const std::vector<SweepReference>& references, const ReportOptions& options);

/// The JSON summary (what summary.json holds); `eval` carries the keys of `hapticbox eval --json`.
std::string report_json(const ReportData& data);

/// Writes DIR/report.html, DIR/summary.json, DIR/samples.csv (and the chart PNGs under
/// DIR/charts/); creates DIR. Throws hb::IoError.
void write_report(const ReportData& data, const std::string& dir);

} // namespace hb
