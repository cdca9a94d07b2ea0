// A report in four steps:
//  1. the report's box against the exact reference on eval's probes (same count and seed as
//     `hapticbox eval`, so the figures are the same);
//  2. the references and the extra sweep configurations on the same probes (hb::run_sweep),
//     plus the box's own row, and the Pareto front;
//  3. the per-vertex error field;
//  4. writing: charts through PLplot (PNG files), then report.html with the PNGs embedded as
//     base64 data URIs (one self-contained file), summary.json and samples.csv.
#include "report.h"
#include "eval_json.h"
#include "errors.h"
#include "evaluation/probe_sampling.h"
#include "evaluation/query_timing.h"
#include "report_charts.h"
#include "stability_json.h"
#include "stability_section.h"
#include <nlohmann/json.hpp>
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

std::string hex64(std::uint64_t v) {
  char buf[17];
  std::snprintf(buf, sizeof buf, "%016llx", static_cast<unsigned long long>(v));
  return buf;
}

std::string base64(const std::string& bytes) {
  static const char* table = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string out;
  out.reserve((bytes.size() + 2) / 3 * 4);
  std::size_t i = 0;
  for (; i + 2 < bytes.size(); i += 3) {
    const unsigned v = (unsigned char)bytes[i] << 16 | (unsigned char)bytes[i + 1] << 8 | (unsigned char)bytes[i + 2];
    out += table[v >> 18 & 63];
    out += table[v >> 12 & 63];
    out += table[v >> 6 & 63];
    out += table[v & 63];
  }
  if (i + 1 == bytes.size()) {
    const unsigned v = (unsigned char)bytes[i] << 16;
    out += table[v >> 18 & 63];
    out += table[v >> 12 & 63];
    out += "==";
  } else if (i + 2 == bytes.size()) {
    const unsigned v = (unsigned char)bytes[i] << 16 | (unsigned char)bytes[i + 1] << 8;
    out += table[v >> 18 & 63];
    out += table[v >> 12 & 63];
    out += table[v >> 6 & 63];
    out += '=';
  }
  return out;
}

std::string read_bytes(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw IoError(path + ": cannot read");
  std::ostringstream ss;
  ss << in.rdbuf();
  return ss.str();
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

std::string html_escape(const std::string& s) {
  std::string out;
  for (char c : s) {
    switch (c) {
      case '&': out += "&amp;"; break;
      case '<': out += "&lt;"; break;
      case '>': out += "&gt;"; break;
      case '"': out += "&quot;"; break;
      default: out += c;
    }
  }
  return out;
}

std::string fmt(double v, int precision = 2) {
  std::ostringstream ss;
  ss << std::fixed << std::setprecision(precision) << v;
  return ss.str();
}

std::string bytes_text(std::size_t b) {
  if (b >= (1u << 30)) return fmt(double(b) / double(1u << 30)) + " GiB";
  if (b >= (1u << 20)) return fmt(double(b) / double(1u << 20)) + " MiB";
  if (b >= (1u << 10)) return fmt(double(b) / double(1u << 10)) + " KiB";
  return std::to_string(b) + " B";
}

const SweepRow* find_row(const std::vector<SweepRow>& rows, const std::string& method) {
  for (const SweepRow& r : rows)
    if (r.method == method) return &r;
  return nullptr;
}

nlohmann::json row_json(const SweepRow& r) {
  return {{"method", r.method},
          {"m", r.m},
          {"n", r.n},
          {"codec", r.codec},
          {"refine", r.refine},
          {"query_ns", r.query_ns},
          {"memory_bytes", r.memory_bytes},
          // A loaded box was not baked here: null, not 0.
          {"bake_seconds", r.method == "haptic_box" && !r.from_cache && !(r.bake_seconds > 0.0)
                               ? nlohmann::json(nullptr) : nlohmann::json(r.bake_seconds)},
          {"from_cache", r.from_cache},
          {"force_error_median", r.force_error_median},
          {"force_error_p95", r.force_error_p95},
          {"contact_agreement", r.contact_agreement},
          {"angle_error_median_deg", r.angle_error_median_deg},
          {"pareto", r.pareto}};
}

} // namespace

ReportData compute_report(const TriangleMesh& mesh, const std::vector<std::uint32_t>& pieces,
                          const BoxScene& scene, double bake_seconds,
                          const std::vector<SweepReference>& references, const ReportOptions& options) {
  if (references.empty() || !references.front().query) throw InvalidInput("report: needs the exact reference");
  if (scene.boxes().empty()) throw InvalidInput("report: the box scene is empty");
  const auto t0 = std::chrono::steady_clock::now();
  ReportData d;
  d.options = options;
  d.vertices = mesh.vertex_count();
  d.triangles = mesh.triangle_count();
  d.pieces = scene.boxes().size();
  d.diagonal = mesh.bounds().diagonal();
  d.params = scene.boxes().front().params();
  d.memory_bytes = scene.table_bytes();
  d.bake_seconds = bake_seconds;
  d.codec = codec_name(scene.boxes().front().codec());
  d.refine = scene.refines();
  const ContactQuery& exact = *references.front().query;

  // 1. Accuracy on eval's probes.
  const std::vector<Segment> probes = sample_probes(mesh, options.samples, options.probes);
  Communicator& comm = communicator_or_serial(options.communicator);
  d.ranks = comm.size();
  d.stats = compare_queries(scene, exact, probes, options.law, d.diagonal, &d.records, &comm);
  report_progress(options.progress, 0.05);

  // 2. References, sweep configurations, the box's own row.
  SweepOptions so;
  so.configs = options.sweep_configs;
  so.samples = options.samples;
  so.timing_rounds = options.timing_rounds;
  so.probes = options.probes;
  so.law = options.law;
  so.cache_dir = options.cache_dir;
  so.progress = sub_range(options.progress, 0.05, 0.85);
  if (!pieces.empty()) {
    so.recipe.pieces.kind = PiecesRecipe::Kind::given;
    so.recipe.pieces.given = pieces;
  }
  so.communicator = &comm;
  d.rows = run_sweep(mesh, scene.source(), references, so);
  // Timing and the compression curve are rank 0's: only its ReportData is written.
  if (comm.is_root()) d.box_ns = median_query_ns(scene, probes, options.law, options.timing_rounds);
  SweepRow own;
  own.method = "haptic_box";
  own.m = d.params.m;
  own.n = d.params.n;
  own.codec = d.codec;
  own.refine = d.refine;
  own.query_ns = d.box_ns;
  own.memory_bytes = d.memory_bytes;
  own.bake_seconds = bake_seconds;
  own.force_error_median = d.stats.force_error_median;
  own.force_error_p95 = d.stats.force_error_p95;
  own.contact_agreement = d.stats.contact_agreement;
  own.angle_error_median_deg = d.stats.angle_error_median_deg;
  d.rows.push_back(own);
  mark_pareto_front(d.rows);
  report_progress(options.progress, 0.9);

  const ReportTolerances& tol = options.tolerances;
  d.pass_median = d.stats.force_error_median <= tol.force_error_median;
  d.pass_p95 = d.stats.force_error_p95 <= tol.force_error_p95;
  d.pass_agreement = d.stats.contact_agreement >= tol.contact_agreement;

  // Compression curve of one codec over its error bounds.
  if (comm.is_root() && !options.compression_codec.empty() && options.compression_codec != "none") {
    CompressionSweepOptions co;
    co.codecs = {parse_codec(options.compression_codec)};
    co.probes = probes;
    co.exact = &exact;
    co.law = options.law;
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
    fo.law = options.law;
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
  j["inputs"] = {{"mesh", d.mesh_path},
                 {"mesh_hash", hex64(d.mesh_hash)},
                 {"box", d.box_path},
                 {"box_hash", d.box_hash ? hex64(d.box_hash) : ""}};
  j["model"] = {{"vertices", d.vertices}, {"triangles", d.triangles}, {"pieces", d.pieces}, {"diagonal", d.diagonal}};
  j["box"] = {{"m", d.params.m},
              {"n", d.params.n},
              {"codec", d.codec},
              {"memory_bytes", d.memory_bytes},
              {"refine", d.refine},
              {"bake_seconds", d.bake_seconds > 0.0 ? nlohmann::json(d.bake_seconds) : nlohmann::json(nullptr)},
              {"loaded_from_file", !(d.bake_seconds > 0.0)}};
  j["parameters"] = {{"samples", o.samples},
                     {"seed", o.probes.seed},
                     {"cone_degrees", o.probes.cone_degrees},
                     {"length_fraction", o.probes.length_fraction},
                     {"max_depth_fraction", o.probes.max_depth_fraction},
                     {"stiffness_n_per_m", o.law.stiffness_n_per_m},
                     {"metres_per_unit", o.law.metres_per_unit},
                     {"timing_rounds", o.timing_rounds},
                     {"error_field_probes_per_vertex", o.error_field_probes_per_vertex},
                     {"compression_codec", o.compression_codec},
                     {"sweep_configs", nlohmann::json::array()}};
  for (const SweepConfig& c : o.sweep_configs)
    j["parameters"]["sweep_configs"].push_back({{"m", c.m}, {"n", c.n}, {"codec", c.codec}, {"refine", c.refine}});
  // The keys of `hapticbox eval --json`, with the same values for the same input and seed.
  j["eval"] = eval_json(s, d.box_path, d.mesh_path, o.probes.seed);
  j["eval"]["ranks"] = d.ranks;  // as `eval --json` states it
  j["ranks"] = d.ranks;
  nlohmann::json timing = {{"box_ns", d.box_ns}};
  for (const SweepRow& r : d.rows)
    if (r.method != "haptic_box") timing[r.method + "_ns"] = r.query_ns;
  if (timing.contains("exact_embree_ns") && d.box_ns > 0) {
    const double exact_ns = timing["exact_embree_ns"].get<double>();
    timing["speedup_vs_exact"] = exact_ns / d.box_ns;
    timing["verdict"] = exact_ns >= d.box_ns ? "faster than exact" : "slower than exact";
  }
  j["timing"] = timing;
  j["tolerances"] = {{"force_error_median", o.tolerances.force_error_median},
                     {"force_error_p95", o.tolerances.force_error_p95},
                     {"contact_agreement", o.tolerances.contact_agreement},
                     {"pass_force_error_median", d.pass_median},
                     {"pass_force_error_p95", d.pass_p95},
                     {"pass_contact_agreement", d.pass_agreement},
                     {"pass", d.pass()}};
  j["sweep"] = nlohmann::json::array();
  for (const SweepRow& r : d.rows) j["sweep"].push_back(row_json(r));
  j["error_field"] = {{"points", d.error_field.size()},
                      {"probes", d.error_field.probes},
                      {"seconds", d.error_field.seconds},
                      {"force_error_median", d.error_field_median},
                      {"force_error_p95", d.error_field_p95},
                      {"image", d.error_field_image.empty() ? "" : "embedded in report.html"},
                      {"note", d.error_field_image.empty() ? d.error_field_note : std::string()}};
  j["compression_curve"] = nlohmann::json::array();
  for (const auto& [cr, err] : d.compression_curve) j["compression_curve"].push_back({cr, err});
  j["compute_seconds"] = d.compute_seconds;
  if (d.stability) j["stability"] = stability_json(*d.stability);
  return j.dump(2);
}

void write_report(const ReportData& d, const std::string& dir_name) {
  const fs::path dir(dir_name);
  std::error_code ec;
  fs::create_directories(dir / "charts", ec);
  if (ec) throw IoError(dir_name + ": cannot create the report directory (" + ec.message() + ")");

  // Charts.
  const std::string speed_png = (dir / "charts" / "speed_accuracy.png").string();
  const std::string hist_png = (dir / "charts" / "force_error_histogram.png").string();
  const std::string comp_png = (dir / "charts" / "compression_curve.png").string();
  plot_speed_accuracy(d.rows, speed_png);
  plot_force_error_histogram(d.stats.force_errors, hist_png);
  if (!d.compression_curve.empty()) plot_compression_curve(d.compression_curve, comp_png);

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

  // report.html.
  const ComparisonStats& s = d.stats;
  const ReportTolerances& tol = d.options.tolerances;
  auto img = [](const std::string& png, const std::string& alt) {
    return "<img alt=\"" + html_escape(alt) + "\" src=\"data:image/png;base64," + base64(read_bytes(png)) + "\">";
  };
  auto verdict = [](bool ok) { return ok ? "<td class=pass>pass</td>" : "<td class=fail>fail</td>"; };
  const SweepRow* exact = find_row(d.rows, "exact_embree");
  const SweepRow* vtk = find_row(d.rows, "vtk_static_cell_locator");
  std::ostringstream h;
  h << "<!DOCTYPE html>\n<html lang=en><head><meta charset=utf-8><title>HapticBox report: "
    << html_escape(fs::path(d.mesh_path).filename().string()) << "</title>\n<style>"
    << "body{font-family:sans-serif;max-width:1000px;margin:2em auto;color:#222}"
    << "table{border-collapse:collapse;margin:1em 0}td,th{border:1px solid #bbb;padding:3px 8px;text-align:right}"
    << "th{background:#eee}td.l{text-align:left}.pass{color:#070;font-weight:bold}.fail{color:#b00;font-weight:bold}"
    << "img{max-width:100%;border:1px solid #ddd}.note{color:#666}</style></head><body>\n";
  h << "<h1>HapticBox error report</h1>\n<p>" << html_escape(d.mesh_path)
    << (d.box_path.empty() ? "" : " with box file " + html_escape(d.box_path)) << ". hapticbox "
    << html_escape(d.product_version) << "; " << s.samples << " probes, seed " << d.options.probes.seed
    << "; every method answered the same probe segments. Overall: "
    << (d.pass() ? "<span class=pass>within tolerances</span>" : "<span class=fail>outside tolerances</span>")
    << ".</p>\n";
  h << "<h2>Summary</h2>\n<table>\n";
  auto tr = [&h](const std::string& k, const std::string& v) { h << "<tr><th>" << k << "</th><td class=l>" << v << "</td></tr>\n"; };
  tr("model", html_escape(fs::path(d.mesh_path).filename().string()));
  tr("triangles", std::to_string(d.triangles));
  tr("pieces (boxes)", std::to_string(d.pieces));
  tr("densities", "m = " + std::to_string(d.params.m) + ", n = " + std::to_string(d.params.n));
  tr("codec", html_escape(d.codec));
  tr("memory (tables)", bytes_text(d.memory_bytes));
  tr("bake time", d.bake_seconds > 0 ? fmt(d.bake_seconds) + " s" : "loaded from a box file");
  tr("query time, haptic box", fmt(d.box_ns, 1) + " ns");
  if (exact) tr("query time, exact Embree", fmt(exact->query_ns, 1) + " ns");
  if (exact && d.box_ns > 0 && exact->query_ns > 0)
    tr("speed against exact (same probes, one at a time)",
       exact->query_ns >= d.box_ns ? "<span class=pass>faster than exact, " + fmt(exact->query_ns / d.box_ns) + "x</span>"
                                   : "<span class=fail>slower than exact, " + fmt(d.box_ns / exact->query_ns) + "x</span>");
  if (vtk) tr("query time, VTK vtkStaticCellLocator", fmt(vtk->query_ns, 1) + " ns");
  h << "</table>\n<h2>Accuracy against the exact answer</h2>\n<table>\n"
    << "<tr><th>figure</th><th>value</th><th>tolerance</th><th>verdict</th></tr>\n"
    << "<tr><td class=l>median relative force error</td><td>" << fmt(100 * s.force_error_median) << " %</td><td>&le; "
    << fmt(100 * tol.force_error_median) << " %</td>" << verdict(d.pass_median) << "</tr>\n"
    << "<tr><td class=l>95th percentile force error</td><td>" << fmt(100 * s.force_error_p95) << " %</td><td>&le; "
    << fmt(100 * tol.force_error_p95) << " %</td>" << verdict(d.pass_p95) << "</tr>\n"
    << "<tr><td class=l>contact agreement</td><td>" << fmt(100 * s.contact_agreement) << " %</td><td>&ge; "
    << fmt(100 * tol.contact_agreement) << " %</td>" << verdict(d.pass_agreement) << "</tr>\n"
    << "<tr><td class=l>max force error</td><td>" << fmt(100 * s.force_error_max) << " %</td><td></td><td></td></tr>\n"
    << "<tr><td class=l>direction error median / p99</td><td>" << fmt(s.angle_error_median_deg) << " / "
    << fmt(s.angle_error_p99_deg) << " deg</td><td></td><td></td></tr>\n"
    << "<tr><td class=l>false / missed contacts</td><td>" << s.false_contacts << " / " << s.missed_contacts
    << "</td><td></td><td></td></tr>\n"
    << "<tr><td class=l>depth RMS / diagonal</td><td>" << fmt(s.depth_rms_over_diag, 5) << "</td><td></td><td></td></tr>\n"
    << "</table>\n";
  h << "<h2>Speed against accuracy</h2>\n" << img(speed_png, "speed against accuracy chart") << "\n<table>\n"
    << "<tr><th>method</th><th>m</th><th>n</th><th>codec</th><th>query ns</th><th>memory</th><th>bake / build s</th>"
       "<th>median error</th><th>p95 error</th><th>agreement</th><th>Pareto</th></tr>\n";
  for (const SweepRow& r : d.rows) {
    const bool box = r.method == "haptic_box";
    h << "<tr><td class=l>" << html_escape(r.method) << "</td><td>" << (box ? std::to_string(r.m) : "")
      << "</td><td>" << (box ? std::to_string(r.n) : "") << "</td><td>" << html_escape(r.codec) << "</td><td>"
      << fmt(r.query_ns, 1) << "</td><td>" << bytes_text(r.memory_bytes) << "</td><td>"
      << (r.from_cache ? "cached" : fmt(r.bake_seconds, 3)) << "</td><td>" << fmt(100 * r.force_error_median)
      << " %</td><td>" << fmt(100 * r.force_error_p95) << " %</td><td>" << fmt(100 * r.contact_agreement)
      << " %</td><td>" << (r.pareto ? "yes" : "") << "</td></tr>\n";
  }
  h << "</table>\n<p class=note>Pareto front: no other row is both faster and more accurate (median force "
       "error). Memory of the references counts the mesh arrays and the locator's index, not Embree's BVH.</p>\n";
  h << "<h2>Force error distribution</h2>\n" << img(hist_png, "force error histogram") << "\n";
  if (!d.compression_curve.empty())
    h << "<h2>Compression (" << html_escape(d.options.compression_codec) << ")</h2>\n"
      << img(comp_png, "compression curve") << "\n";
  h << "<h2>Error field</h2>\n<p>" << d.error_field.size() << " vertices, "
    << d.options.error_field_probes_per_vertex << " probe(s) each, computed in " << fmt(d.error_field.seconds, 3)
    << " s; relative force error over the vertices: median " << fmt(100 * d.error_field_median) << " %, p95 "
    << fmt(100 * d.error_field_p95) << " %.</p>\n";
  if (!d.error_field_image.empty() && fs::exists(d.error_field_image))
    h << img(d.error_field_image, "error field") << "\n";
  else
    h << "<p class=note>No rendered image: " << html_escape(d.error_field_note.empty() ? "not requested" : d.error_field_note)
      << "</p>\n";
  if (d.stability) h << stability_html_section(*d.stability, (dir / "charts").string());
  h << "<h2>Reproducing</h2>\n<p>summary.json holds every figure above and every parameter; samples.csv one "
       "row per probe with both answers. Mesh hash "
    << hex64(d.mesh_hash) << (d.box_hash ? ", box hash " + hex64(d.box_hash) : "") << ".</p>\n</body></html>\n";
  write_text(dir / "report.html", h.str());
}

} // namespace hb
