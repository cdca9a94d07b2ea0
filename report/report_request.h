#pragma once
// One report as every front end asks for it: the command line's `hapticbox report` and the
// window's Export Error Report fill a ReportRequest (what is reported on, the references, the
// options, how the error field is pictured) and call compute_report(request) and
// write_report(request, data, dir), so both give the same report for the same input.
// The VTK-only parts (the vtkStaticCellLocator reference, rendering the error field) are
// passed in by the front end: this layer includes no VTK.
#include "report.h"
#include <functional>
#include <memory>
#include <string>
#include <vector>

namespace hb {

/// The extra box configurations a report measures for its speed-vs-accuracy chart.
struct ReportSweep {
  bool enabled = true;  ///< false: the box itself and the references only.
  /// Given values (either may be empty: the box's own m or n). Both empty: the default,
  /// m/4, m/2, m by n/2, n around the box's own (m, n) for a one-box scene; none for a scene
  /// of several boxes (sweep configurations are baked as one box and would not compare).
  std::vector<int> m, n;
};

/// Renders the per-vertex perceptible ratios `perceptible_ratio` (ErrorField::perceptible_ratio:
/// the difference over what a hand feels) over `mesh` into the PNG `path` on the scale anchored
/// at 1 (below it nothing shows; `range` is the ratio the scale's top stands for); returns false
/// with `note` saying why when it cannot (no display). Supplied by the front end:
/// vtkHapticBoxErrorFieldImage::RenderField.
using ErrorFieldRenderer = std::function<bool(const TriangleMesh& mesh, const std::vector<float>& perceptible_ratio,
                                              double range, const std::string& path, std::string* note)>;

/// Everything one report needs.
struct ReportRequest {
  /// What is reported on (both required, alive until the report is written).
  const TriangleMesh* mesh = nullptr;
  const BoxScene* scene = nullptr;
  std::string mesh_path;         ///< the model file, as given.
  std::uint64_t mesh_hash = 0;   ///< its hash (hb::cli::hash_model: file plus loader options).
  std::string box_path;          ///< the box file, or empty when baked for the report and not saved.
  double bake_seconds = 0.0;     ///< how long `scene` took to bake (0: loaded from a file).
  /// The reference methods, exact Embree first (vtkHapticBoxReferenceQueries::References(),
  /// with their real memory and build times).
  std::vector<SweepReference> references;
  /// Probes, force law, tolerances, error field, compression curve, cache, progress, ranks.
  /// `options.sweep_configs` is ignored: `sweep` decides them (report_sweep_configs).
  ReportOptions options;
  ReportSweep sweep;
  /// The stability suite's results to include, or null.
  std::shared_ptr<const StabilityReport> stability;
  std::string product_version;
  std::string command_line;      ///< how the report was asked for (stamped on it).
  /// The error-field picture: a PNG already rendered (the window's view of the field), else
  /// `render_error_field` is called, else there is none and `no_image_note` says why.
  std::string error_field_image;
  ErrorFieldRenderer render_error_field;
  std::string no_image_note = "no renderer was given";
};

/// The sweep configurations `sweep` asks for around `scene`'s own box (its own (m, n) left
/// out: the report's box is always a row). `note`, when given, says why a default sweep was
/// skipped (empty otherwise).
std::vector<SweepConfig> report_sweep_configs(const BoxScene& scene, const ReportSweep& sweep,
                                              std::string* note = nullptr);

/// Computes the report of `request`: compute_report on its mesh, scene (its piece ids for the
/// sweep bakes), references and options, with the sweep of report_sweep_configs, and the
/// provenance (paths, hashes, version, stability) filled in. Every rank of
/// `options.communicator` calls it; the result is complete on rank 0. Throws
/// hb::InvalidInput (no mesh, scene or exact reference), hb::Cancelled.
ReportData compute_report(const ReportRequest& request);

/// Writes the report of `request` (computed by compute_report(request)) into `dir`: the error
/// field's image as the request says (rendering after a first write, so the figures survive a
/// renderer that takes the process down), then write_report(data, dir). Throws hb::IoError.
void write_report(const ReportRequest& request, ReportData& data, const std::string& dir);

} // namespace hb
