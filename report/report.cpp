// A report in four steps:
//  1. the report's box against the exact reference on eval's probes (same count and seed as
//     `hapticbox eval`, so the figures are the same);
//  2. the references and the extra sweep configurations on the same probes (hb::run_sweep),
//     plus the box's own row, and the Pareto front;
//  3. the per-vertex error field;
//  4. writing: charts through PLplot (SVG files), then report.html (report_html.cpp: the SVGs
//     embedded as data URIs, one self-contained file), summary.json, summary.txt and samples.csv.
#include "report.h"
#include "mesh/file_hash.h"
#include "eval_json.h"
#include "errors.h"
#include "evaluation/probe_sampling.h"
#include "evaluation/query_timing.h"
#include "bake_chart_points.h"
#include "report_charts.h"
#include "report_html.h"
#include "machine_info.h"
#include "figure_text.h"
#include "summary_text.h"
#include "stability_json.h"
#include "stability_section.h"
#include <nlohmann/json.hpp>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <sstream>
#include "evaluation/compression_sweep.h"

namespace hb {
namespace fs = std::filesystem;

namespace {

ProgressCallback sub_range(const ProgressCallback& progress, double begin, double end) {
  if (!progress) return {};
  return [progress, begin, end](double f) { return progress(begin + (end - begin) * f); };
}

void report_progress(const ProgressCallback& progress, double f) {
  if (progress && !progress(f)) throw Cancelled("report: cancelled");
}

// A written file appears whole or not at all: written under a temporary name, renamed.
void move_into_place(const fs::path& tmp, const fs::path& path) {
  std::error_code ec;
  fs::rename(tmp, path, ec);
  if (ec) {
    fs::remove(tmp, ec);
    throw IoError(path.string() + ": cannot rename the written file into place");
  }
}

void write_text(const fs::path& path, const std::string& text) {
  const fs::path tmp = path.string() + ".tmp";
  std::ofstream out(tmp, std::ios::binary);
  out << text;
  out.close();
  if (!out) {
    std::error_code ec;
    fs::remove(tmp, ec);
    throw IoError(path.string() + ": cannot write");
  }
  move_into_place(tmp, path);
}

nlohmann::json row_json(const SweepRow& r) {
  return {{"method", r.method},
          {"m", r.m},
          {"n", r.n},
          {"codec", r.codec},
          {"refine", r.refine},
          {"label", r.label},
          {"query_ns", r.query_ns},
          {"memory_bytes", r.memory_bytes},
          // A loaded box was not baked here: null, not 0.
          {"bake_seconds", r.method == "haptic_box" && !r.from_cache && !(r.bake_seconds > 0.0)
                               ? nlohmann::json(nullptr) : nlohmann::json(r.bake_seconds)},
          {"from_cache", r.from_cache},
          {"force_error_median", r.force_error_median},
          {"force_error_p95", r.force_error_p95},
          // null: not measured (a raw sampling a bake tried judges what a hand feels only)
          {"contact_agreement", r.contact_agreement < 0.0 ? nlohmann::json(nullptr) : nlohmann::json(r.contact_agreement)},
          {"perceptible_share", r.perceptible_share},
          {"tried_by_the_bake", r.tried_by_the_bake},
          {"angle_error_median_deg", r.angle_error_median_deg},
          {"angle_error_p99_deg", r.angle_error_p99_deg},
          {"within_budget", r.within_budget},
          {"pareto", r.pareto}};
}

} // namespace

ReportData compute_report(const TriangleMesh& mesh, const std::vector<std::uint32_t>& pieces,
                          const BoxScene& scene, double bake_seconds,
                          const std::vector<SweepReference>& references, const ReportOptions& options) {
  if (references.empty() || !references.front().query) throw InvalidInput("report: needs the exact reference");
  if (scene.parts().boxes.empty()) throw InvalidInput("report: the box scene is empty");
  const auto t0 = std::chrono::steady_clock::now();
  ReportData d;
  d.options = options;
  d.vertices = mesh.vertex_count();
  d.triangles = mesh.triangle_count();
  d.pieces = scene.parts().boxes.size();
  d.diagonal = mesh.bounds().diagonal();
  d.params = scene.parts().boxes.front().params();
  d.memory_bytes = scene.bytes().memory;  // as the sweep's rows count it
  d.bake_seconds = bake_seconds;
  d.codec = codec_name(scene.parts().boxes.front().codec());
  d.refine = scene.refines();
  d.route = answerer(scene);
  d.stroke_route = strokes_by_full_mesh(scene) ? Answerer::embree : d.route;
  d.stroke_cells_ns = scene.parts().budget.stroke_cells_ns;
  d.stroke_embree_ns = scene.parts().budget.stroke_embree_ns;
  d.densities = density_range(scene);
  d.generated_at = utc_now_iso();
  d.machine = machine_description();
  const ContactQuery& exact = *references.front().query;

  // 1. Accuracy on eval's probes.
  const std::vector<Segment> probes = sample_probes(mesh, options.samples, options.probes);
  d.workspace = make_workspace(d.diagonal, options.workspace);
  const ForceLaw law = d.workspace.law();
  Communicator& comm = communicator_or_serial(options.communicator);
  d.ranks = comm.size();
  d.stats = compare_queries(scene, exact, probes, law, d.diagonal, &d.records, &comm, nullptr, options.judge);
  // eval's second figure, the same count of light touches at any angle.
  d.light_touch = compare_light_touches(scene, exact, mesh, options.samples, options.probes.seed, law, d.diagonal,
                                        &comm, options.judge);
  d.worst = worst_probes(d.records, d.diagonal);
  report_progress(options.progress, 0.05);

  // 2. References, sweep configurations, the box's own row.
  SweepOptions so;
  so.configs = options.sweep_configs;
  so.samples = options.samples;
  so.timing_rounds = options.timing_rounds;
  so.probes = options.probes;
  so.law = law;
  so.judge = options.judge;
  so.cache_dir = options.cache_dir;
  so.progress = sub_range(options.progress, 0.05, 0.85);
  if (!pieces.empty()) {
    so.recipe.pieces.kind = PiecesRecipe::Kind::given;
    so.recipe.pieces.given = pieces;
  }
  so.communicator = &comm;
  d.rows = run_sweep(mesh, scene.parts().source, references, so);
  // Timing and the compression curve are rank 0's: only its ReportData is written.
  if (comm.is_root()) d.box_ns = median_query_ns(scene, probes, law, options.timing_rounds);
  SweepRow own;
  own.method = "haptic_box";
  own.m = d.params.m;
  own.n = d.params.n;
  if (scene.parts().budget.present) {
    // A bake to a budget (the default bake from a mesh) says so, as the sweep's row of it.
    own.label = bake_label(scene);
  } else if (d.pieces > 1) {
    // A scene is not the first box's (m, n): its chart point says what it is.
    own.label = "scene: " + std::to_string(d.pieces) + " boxes, " + densities_text(d);
  }
  own.codec = d.codec;
  own.refine = d.refine;
  own.query_ns = d.box_ns;
  own.memory_bytes = d.memory_bytes;
  own.bake_seconds = bake_seconds;
  own.set_accuracy(d.stats, so.budget);
  d.rows.push_back(own);
  mark_pareto_front(d.rows);
  // The raw samplings the bake tried, as its budget report holds them (their query times at
  // bake time, their shares of its tuning probes): beside the sweep's samplings, off the Pareto
  // front (other probes, another run's clock), before the box's own row, which stays last.
  std::vector<SweepRow> tried;
  for (const SweepRow& r : bake_chart_rows(scene))
    if (r.tried_by_the_bake) tried.push_back(r);
  d.rows.insert(d.rows.end() - 1, tried.begin(), tried.end());
  report_progress(options.progress, 0.9);

  const ReportTolerances& tol = options.tolerances;
  d.pass_perceptible = d.stats.perceptible_share <= tol.perceptible;
  d.pass_median = d.stats.force_error_median <= tol.force_error_median;
  d.pass_p95 = d.stats.force_error_p95 <= tol.force_error_p95;
  d.pass_agreement = d.stats.contact_agreement >= tol.contact_agreement;

  // Compression curve of one codec over its error bounds.
  if (comm.is_root() && !options.compression_codec.empty() && options.compression_codec != "none") {
    CompressionSweepOptions co;
    co.codecs = {parse_codec(options.compression_codec)};
    co.probes = probes;
    co.exact = &exact;
    co.law = law;
    co.judge = options.judge;
    for (const CompressionSweepPoint& p : compression_sweep(scene, co))
      if (p.codec != CodecId::none) d.compression_curve.emplace_back(p.ratio, p.force_error_vs_raw_median);
  }

  // 3. Error field at the vertices.
  if (options.error_field_probes_per_vertex > 0) {
    ErrorFieldOptions fo;
    fo.probes_per_point = options.error_field_probes_per_vertex;
    fo.cone_degrees = options.probes.cone_degrees;
    fo.length_fraction = options.probes.length_fraction;
    fo.max_depth_fraction = options.probes.max_depth_fraction;
    fo.seed = options.probes.seed;
    fo.law = law;
    fo.thresholds = options.judge.thresholds;
    fo.max_force_n = options.judge.max_force_n;
    fo.progress = sub_range(options.progress, 0.9, 1.0);
    fo.communicator = &comm;
    d.error_field = compute_error_field(scene, exact, surface_points_at_vertices(mesh), d.diagonal, fo);
    std::vector<double> e;
    for (float v : d.error_field.force_error)
      if (!std::isnan(v)) e.push_back(v);
    d.error_field_median = quantile(e, 0.5);
    d.error_field_p95 = quantile(e, 0.95);
  }
  report_progress(options.progress, 1.0);
  d.compute_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return d;
}

std::string report_json(const ReportData& d) {
  const ComparisonStats& s = d.stats;
  const ReportOptions& o = d.options;
  nlohmann::json j;
  j["product"] = {{"name", "hapticbox"}, {"version", d.product_version}};
  j["generated"] = {{"at_utc", d.generated_at}, {"machine", d.machine}, {"command_line", d.command_line}};
  j["inputs"] = {{"mesh", d.mesh_path},
                 {"mesh_hash", hash_text(d.mesh_hash)},
                 {"box", d.box_path},
                 {"box_hash", d.box_hash ? hash_text(d.box_hash) : ""}};
  j["model"] = {{"vertices", d.vertices}, {"triangles", d.triangles}, {"pieces", d.pieces}, {"diagonal", d.diagonal}};
  j["box"] = {{"m", d.params.m},
              {"n", d.params.n},
              {"m_range", {d.densities.m_min, d.densities.m_max}},
              {"n_range", {d.densities.n_min, d.densities.n_max}},
              {"codec", d.codec},
              {"memory_bytes", d.memory_bytes},
              {"refine", d.refine},
              {"route", answerer_name(d.route)},
              {"stroke_route", answerer_name(d.stroke_route)},
              {"bake_seconds", d.bake_seconds > 0.0 ? nlohmann::json(d.bake_seconds) : nlohmann::json(nullptr)},
              {"loaded_from_file", !(d.bake_seconds > 0.0)}};
  j["parameters"] = {{"samples", o.samples},
                     {"seed", o.probes.seed},
                     {"cone_degrees", o.probes.cone_degrees},
                     {"length_fraction", o.probes.length_fraction},
                     {"max_depth_fraction", o.probes.max_depth_fraction},
                     {"stiffness_n_per_m", d.workspace.stiffness_n_per_m},
                     {"metres_per_unit", d.workspace.metres_per_unit},
                     {"workspace", {{"fit", d.workspace.fit_name()},
                                    {"diagonal_mm", d.workspace.diagonal_m() * 1000.0},
                                    {"max_force_n", d.workspace.max_force_n},
                                    {"text", d.workspace.describe()}}},
                     {"timing_rounds", o.timing_rounds},
                     {"error_field_probes_per_vertex", o.error_field_probes_per_vertex},
                     {"compression_codec", o.compression_codec},
                     {"sweep_configs", nlohmann::json::array()}};
  for (const SweepConfig& c : o.sweep_configs)
    j["parameters"]["sweep_configs"].push_back({{"m", c.m}, {"n", c.n}, {"codec", c.codec}, {"refine", c.refine}});
  // The keys of `hapticbox eval --json`, with the same values for the same input and seed.
  j["eval"] = eval_json(s, d.box_path, d.mesh_path, o.probes.seed, answerer_name(d.route));
  j["eval"]["ranks"] = d.ranks;  // as `eval --json` states it
  j["eval"]["workspace"] = workspace_json(d.workspace, o.judge);
  j["eval"]["light_touch"] = light_touch_json(d.light_touch);
  j["ranks"] = d.ranks;
  nlohmann::json timing = {{"box_ns", d.box_ns}};
  for (const SweepRow& r : d.rows)
    if (r.method != "haptic_box") timing[r.method + "_ns"] = r.query_ns;
  if (timing.contains("exact_embree_ns") && d.box_ns > 0) {
    const double exact_ns = timing["exact_embree_ns"].get<double>();
    timing["speedup_vs_exact"] = exact_ns / d.box_ns;
    const SpeedComparison speed = compare_speed(d.box_ns, exact_ns);
    timing["verdict"] = speed == SpeedComparison::faster  ? "faster than exact"
                        : speed == SpeedComparison::as_fast ? "as fast as exact"
                                                            : "slower than exact";
    timing["verdict_text"] = "the box is " + speed_verdict(d.box_ns, exact_ns) + " (same probes, one at a time, one core)";
  }
  j["timing"] = timing;
  j["tolerances"] = {{"perceptible", o.tolerances.perceptible},
                     {"pass_perceptible", d.pass_perceptible},
                     {"force_error_median", o.tolerances.force_error_median},
                     {"force_error_p95", o.tolerances.force_error_p95},
                     {"contact_agreement", o.tolerances.contact_agreement},
                     {"pass_force_error_median", d.pass_median},
                     {"pass_force_error_p95", d.pass_p95},
                     {"pass_contact_agreement", d.pass_agreement},
                     {"pass", d.pass()}};
  j["sweep"] = nlohmann::json::array();
  for (const SweepRow& r : d.rows) j["sweep"].push_back(row_json(r));
  std::size_t felt = 0;
  double largest = 0.0;
  for (float r : d.error_field.perceptible_ratio)
    if (r > 1.f) ++felt, largest = std::max(largest, double(r));
  j["error_field"] = {{"points", d.error_field.size()},
                      {"metric_shown", "perceptible ratio (difference over its perceptual threshold; colours from 1)"},
                      {"perceptible_vertices", felt},
                      {"perceptible_ratio_max", largest},
                      {"probes", d.error_field.probes},
                      {"seconds", d.error_field.seconds},
                      {"force_error_median", d.error_field_median},
                      {"force_error_p95", d.error_field_p95},
                      {"image", d.error_field_image.empty() ? "" : "embedded in report.html"},
                      {"note", d.error_field_image.empty() ? d.error_field_note : std::string()}};
  j["compression_curve"] = nlohmann::json::array();
  for (const auto& [cr, err] : d.compression_curve) j["compression_curve"].push_back({cr, err});
  j["worst_probes"] = nlohmann::json::array();
  for (const WorstProbe& w : d.worst)
    j["worst_probes"].push_back({{"kind", to_string(w.kind)},
                                 {"probe", w.index},
                                 {"start", {w.segment.start.x(), w.segment.start.y(), w.segment.start.z()}},
                                 {"tip", {w.segment.end.x(), w.segment.end.y(), w.segment.end.z()}},
                                 {"relative_force_error", w.relative_error},
                                 {"exact_force_n", w.exact_force_n},
                                 {"approx_force_n", w.approx_force_n},
                                 {"force_difference_n", w.force_difference_n},
                                 {"exact_depth_over_diagonal", w.exact_depth_fraction},
                                 {"approx_depth_over_diagonal", w.approx_depth_fraction},
                                 {"incidence_deg", w.incidence_deg},
                                 {"cause", w.cause}});
  j["summary_text"] = report_summary_text(d, "");
  j["compute_seconds"] = d.compute_seconds;
  if (d.stability) j["stability"] = stability_json(*d.stability);
  return j.dump(2);
}

void write_report(const ReportData& d, const std::string& dir_name) {
  const fs::path dir(dir_name);
  std::error_code ec;
  fs::create_directories(dir / "charts", ec);
  if (ec) throw IoError(dir_name + ": cannot create the report directory (" + ec.message() + ")");

  // Charts, as SVG (vector: sharp when printed; embedded in report.html).
  ChartFiles charts;
  charts.speed = (dir / "charts" / "speed_accuracy.svg").string();
  charts.histogram = (dir / "charts" / "force_error_histogram.svg").string();
  plot_speed_accuracy(d.rows, charts.speed);
  charts.difference = (dir / "charts" / "force_difference_histogram.svg").string();
  plot_force_difference_histogram(d.stats.force_differences_n, d.stats.thresholds, d.stats.exact_force_median_n,
                                  charts.difference);
  plot_force_error_histogram(d.stats.force_errors, charts.histogram);
  if (!d.compression_curve.empty()) {
    charts.compression = (dir / "charts" / "compression_curve.svg").string();
    plot_compression_curve(d.compression_curve, charts.compression);
  }
  charts.stability_dir = (dir / "charts").string();

  write_text(dir / "summary.json", report_json(d) + "\n");

  // samples.csv: one row per probe, both answers.
  {
    const fs::path csv_tmp = dir / "samples.csv.tmp";
    std::ofstream csv(csv_tmp);
    csv << "probe,start_x,start_y,start_z,end_x,end_y,end_z,"
           "exact_contact,exact_depth,exact_fx,exact_fy,exact_fz,exact_nx,exact_ny,exact_nz,"
           "approx_contact,approx_depth,approx_fx,approx_fy,approx_fz,approx_nx,approx_ny,approx_nz,"
           "relative_force_error,angle_error_deg\n";
    csv << std::setprecision(9);
    for (std::size_t i = 0; i < d.records.size(); ++i) {
      const ProbeRecord& r = d.records[i];
      auto v3 = [&csv](const Vec3& v) { csv << ',' << v.x() << ',' << v.y() << ',' << v.z(); };
      csv << i;
      v3(r.segment.start);
      v3(r.segment.end);
      csv << ',' << int(r.exact.contact) << ',' << r.exact.depth;
      v3(r.exact.force);
      v3(r.exact.normal);
      csv << ',' << int(r.approx.contact) << ',' << r.approx.depth;
      v3(r.approx.force);
      v3(r.approx.normal);
      if (r.exact.contact && r.approx.contact)
        csv << ',' << relative_force_error(r.exact, r.approx) << ',' << angle_error_degrees(r.exact, r.approx);
      else
        csv << ",nan,nan";  // no data (a probe without contact in both answers): NaN, never 0
      csv << '\n';
    }
    csv.close();
    if (!csv) {
      std::error_code ec;
      fs::remove(csv_tmp, ec);
      throw IoError((dir / "samples.csv").string() + ": cannot write");
    }
    move_into_place(csv_tmp, dir / "samples.csv");
  }

  // report.html and the plain-text summary.
  write_text(dir / "summary.txt", report_summary_text(d, dir_name) + "\n");
  write_text(dir / "report.html", report_html(d, charts));
}

} // namespace hb
