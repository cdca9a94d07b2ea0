// report.html in five parts: the stamp (what, when, where, how asked for), the verdicts
// (accuracy and speed side by side, in words), the figures (significant digits), the worst
// probes (where, how wrong, why), the charts (SVG) and the error field.
#include "report_html.h"
#include "bake_chart_points.h"
#include "mesh/file_hash.h"
#include "errors.h"
#include "figure_text.h"
#include "perceptible_text.h"
#include "stability_section.h"
#include "summary_text.h"
#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>

namespace hb {
namespace fs = std::filesystem;

namespace {

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

// An image embedded in the page; SVG stays vector (sharp when printed or zoomed).
std::string image(const std::string& path, const std::string& alt) {
  const bool svg = fs::path(path).extension() == ".svg";
  return "<img class=chart alt=\"" + html_escape(alt) + "\" src=\"data:image/" + (svg ? "svg+xml" : "png") + ";base64," +
         base64(read_bytes(path)) + "\">";
}

const SweepRow* find_row(const std::vector<SweepRow>& rows, const std::string& method) {
  for (const SweepRow& r : rows)
    if (r.method == method) return &r;
  return nullptr;
}

std::string ns_text(double ns) { return ns > 0 ? duration_text(ns * 1e-9) : "n/a"; }

// The speed of the box against exact Embree, as the verdicts and the accuracy table say it.
struct SpeedAgainstExact {
  double exact_ns = 0.0;
  bool faster = false;
  std::string text;
};

SpeedAgainstExact speed_against_exact(const ReportData& d) {
  const SweepRow* exact = find_row(d.rows, "exact_embree");
  SpeedAgainstExact v;
  v.exact_ns = exact ? exact->query_ns : 0.0;
  const SpeedComparison speed = compare_speed(d.box_ns, v.exact_ns);
  v.faster = speed == SpeedComparison::faster || speed == SpeedComparison::as_fast;
  v.text = speed_verdict(d.box_ns, v.exact_ns);
  return v;
}

void write_page_head(std::ostringstream& h, const ReportData& d) {
  h << "<!DOCTYPE html>\n<html lang=en><head><meta charset=utf-8><title>HapticBox report: "
    << html_escape(fs::path(d.mesh_path).filename().string()) << "</title>\n<style>"
    << "body{font-family:sans-serif;max-width:1000px;margin:2em auto;color:#222;line-height:1.4}"
    << "table{border-collapse:collapse;margin:1em 0}td,th{border:1px solid #bbb;padding:3px 8px;text-align:right;white-space:nowrap}td.l{white-space:normal}"
    << "th{background:#eee}td.l,th.l{text-align:left}.pass{color:#070;font-weight:bold}.fail{color:#b00;font-weight:bold}"
    << ".slow{color:#a60;font-weight:bold}img.chart{max-width:100%;border:1px solid #ddd}.note{color:#555}"
    << "table.worst td{white-space:normal}table.worst td.l:last-child{min-width:16em}"
    << ".stamp{color:#555;font-size:90%}.verdicts td{font-size:110%}code{background:#f4f4f4;padding:0 3px}"
    << "@media print{body{max-width:none;margin:1cm}}</style></head><body>\n";
  h << "<h1>HapticBox error report: " << html_escape(fs::path(d.mesh_path).filename().string()) << "</h1>\n";
}

// 1. The stamp: what, when, where, how asked for.
void write_stamp(std::ostringstream& h, const ReportData& d) {
  h << "<p class=stamp>Generated " << html_escape(d.generated_at) << " on " << html_escape(d.machine)
    << " by hapticbox " << html_escape(d.product_version);
  if (!d.command_line.empty()) h << ":<br><code>" << html_escape(d.command_line) << "</code>";
  h << "<br>Mesh " << html_escape(d.mesh_path) << " (hash " << hash_text(d.mesh_hash) << ")";
  if (!d.box_path.empty()) h << "; box file " << html_escape(d.box_path) << (d.box_hash ? " (hash " + hash_text(d.box_hash) + ")" : "");
  h << ".</p>\n";
}

// 2. The verdicts, side by side, and what was measured.
void write_verdicts(std::ostringstream& h, const ReportData& d, const SpeedAgainstExact& speed) {
  const ComparisonStats& s = d.stats;
  h << "<table class=verdicts><tr><th class=l>accuracy against the exact answer</th><td class=l>"
    << (d.pass() ? "<span class=pass>no one could feel the difference</span>"
                 : "<span class=fail>a hand would feel the difference</span>")
    << ": " << html_escape(perceptible_headline(s)) << " (budget " << percent(d.options.tolerances.perceptible)
    << "; threshold " << html_escape(thresholds_text(s.thresholds)) << "); secondary: median force error "
    << percent(s.force_error_median) << ", p95 " << percent(s.force_error_p95) << ", contact agreement "
    << agreement_percent(s.contact_agreement) << "</td></tr>\n"
    << "<tr><th class=l>light touches at any angle</th><td class=l>" << html_escape(perceptible_headline(d.light_touch))
    << " (" << html_escape(light_touch_words()) << ": what the probes above, near the normal and pressed harder, do "
       "not show)</td></tr>\n"
    << "<tr><th class=l>speed against exact Embree</th><td class=l><span class=" << (speed.faster ? "pass" : "slow")
    << ">the box is " << html_escape(speed.text) << "</span> (" << ns_text(d.box_ns) << " against " << ns_text(speed.exact_ns)
    << " a query; same probes, one at a time, one core)</td></tr></table>\n";
  h << "<p>What was measured: " << count_text(double(s.samples)) << " random probe segments (seed "
    << d.options.probes.seed << "; tips on the surface, within " << sig(d.options.probes.cone_degrees)
    << " deg of the inward normal), each answered by the haptic box and by the exact reference on the same "
       "segment with the same contact rule and force law ("
    << html_escape(d.workspace.describe()) << ").</p>\n";
}

void write_summary(std::ostringstream& h, const ReportData& d) {
  const SweepRow* exact = find_row(d.rows, "exact_embree");
  const SweepRow* vtk = find_row(d.rows, "vtk_static_cell_locator");
  h << "<h2>Summary</h2>\n<table>\n";
  auto tr = [&h](const std::string& k, const std::string& v) { h << "<tr><th class=l>" << k << "</th><td class=l>" << v << "</td></tr>\n"; };
  tr("model", html_escape(fs::path(d.mesh_path).filename().string()));
  tr("triangles", count_text(double(d.triangles)));
  tr("pieces (boxes)", std::to_string(d.pieces));
  tr(d.pieces > 1 ? "densities (over the boxes)" : "densities", densities_text(d));
  tr("codec", html_escape(d.codec) + (d.refine ? ", exact refinement" : ""));
  tr("route", html_escape(std::string(answerer_words(d.route)) +
                          (d.stroke_route != d.route ? "; along strokes (a probe's successive queries): exact Embree over "
                                                       "the full mesh, measured faster there at bake time"
                                                     : std::string())));
  tr("memory (what its queries read: tables, triangle ids, surface, normal map, grid, cells)", bytes_text(d.memory_bytes));
  tr("bake time", d.bake_seconds > 0 ? duration_text(d.bake_seconds) : "loaded from a box file");
  tr("query time, haptic box", ns_text(d.box_ns));
  if (exact) tr("query time, exact Embree", ns_text(exact->query_ns));
  if (vtk) tr("query time, VTK vtkStaticCellLocator", ns_text(vtk->query_ns));
  h << "</table>\n";
}

// The figures against their tolerances.
void write_accuracy(std::ostringstream& h, const ReportData& d, const SpeedAgainstExact& speed) {
  const ComparisonStats& s = d.stats;
  const ReportTolerances& tol = d.options.tolerances;
  auto verdict = [](bool ok) { return ok ? "<td class=pass>pass</td>" : "<td class=fail>fail</td>"; };
  h << "<h2>Accuracy and speed against the exact answer</h2>\n<table>\n"
    << "<tr><th class=l>figure</th><th>value</th><th>tolerance</th><th>verdict</th></tr>\n"
    << "<tr><td class=l>median relative force error</td><td>" << percent(s.force_error_median) << "</td><td>&le; "
    << percent(tol.force_error_median) << "</td>" << verdict(d.pass_median) << "</tr>\n"
    << "<tr><td class=l>95th percentile force error</td><td>" << percent(s.force_error_p95) << "</td><td>&le; "
    << percent(tol.force_error_p95) << "</td>" << verdict(d.pass_p95) << "</tr>\n"
    << "<tr><td class=l>contact agreement</td><td>" << agreement_percent(s.contact_agreement) << "</td><td>&ge; "
    << percent(tol.contact_agreement) << "</td>" << verdict(d.pass_agreement) << "</tr>\n"
    << "<tr><td class=l>speed: box against exact Embree</td><td>" << ns_text(d.box_ns) << " / " << ns_text(speed.exact_ns)
    << "</td><td>none stated</td><td class=" << (speed.faster ? "pass" : "slow") << ">" << html_escape(speed.text) << "</td></tr>\n"
    << (d.stroke_route == Answerer::embree && d.stroke_route != d.route
            ? "<tr><td class=l>along strokes: the bake's route against the cells</td><td>" + ns_text(d.stroke_embree_ns) + " / " +
                  ns_text(d.stroke_cells_ns) +
                  "</td><td colspan=2 class=l>a probe's successive queries (the servo loop, the window) are answered by "
                  "exact Embree over the full mesh, measured faster there at bake time</td></tr>\n"
            : std::string())
    << "<tr><td class=l>largest force error</td><td>" << percent(s.force_error_max)
    << "</td><td colspan=2 class=l>where the exact force is tiny; see the worst probes below</td></tr>\n"
    << "<tr><td class=l>direction error median / p99</td><td>" << sig(s.angle_error_median_deg) << " / "
    << sig(s.angle_error_p99_deg) << " deg</td><td></td><td></td></tr>\n"
    << "<tr><td class=l>false / missed contacts</td><td>" << s.false_contacts << " / " << s.missed_contacts << " of "
    << s.samples << "</td><td></td><td></td></tr>\n"
    << "<tr><td class=l>depth RMS / diagonal</td><td>" << sig(s.depth_rms_over_diag) << "</td><td></td><td></td></tr>\n"
    << "</table>\n";
}

// 3. The worst probes: where, how wrong, why.
void write_worst_probes(std::ostringstream& h, const ReportData& d) {
  h << "<h2 id=worst>Worst probes</h2>\n";
  if (d.worst.empty()) {
    h << "<p class=note>No probe disagrees and no force error to list.</p>\n";
  } else {
    h << "<p class=note>The largest relative force errors, then the deepest false and missed contacts. Probe "
         "numbers are rows of samples.csv; tips in model units; depths as a percentage of the mesh diagonal; "
         "incidence is the angle between the probe and the surface normal (90 deg: grazing).</p>\n<table class=worst>\n"
      << "<tr><th>probe</th><th class=l>kind</th><th>tip (x, y, z)</th><th>error</th><th>|F exact| / |F box|</th>"
         "<th>depth exact / box</th><th>incidence</th><th class=l>why</th></tr>\n";
    // The cells may wrap (the "why" needs the room), but only between values: a value keeps
    // its unit.
    const auto unit = [](std::string v) {
      for (const char* u : {" %", " N", " deg"})
        for (std::size_t at = v.find(u); at != std::string::npos; at = v.find(u, at)) v.replace(at, 1, "&nbsp;");
      return v;
    };
    for (const WorstProbe& w : d.worst) {
      const Vec3& t = w.segment.end;
      h << "<tr><td>" << w.index << "</td><td class=l>" << to_string(w.kind) << "</td><td>" << sig(t.x()) << ", "
        << sig(t.y()) << ", " << sig(t.z()) << "</td><td>"
        << unit(w.kind == WorstProbe::Kind::force_error ? percent(w.relative_error) : sig(w.force_difference_n) + " N")
        << "</td><td>" << sig(w.exact_force_n) << " / " << unit(sig(w.approx_force_n) + " N") << "</td><td>"
        << unit(percent(w.exact_depth_fraction)) << " / " << unit(percent(w.approx_depth_fraction)) << "</td><td>"
        << unit(sig(w.incidence_deg) + " deg") << "</td><td class=l>" << html_escape(w.cause) << "</td></tr>\n";
    }
    h << "</table>\n";
  }
}

// 4. The charts and the sweep's table.
void write_charts(std::ostringstream& h, const ReportData& d, const ChartFiles& charts) {
  h << "<h2>Speed against accuracy</h2>\n";
  if (!charts.speed.empty()) h << image(charts.speed, "speed against accuracy chart") << "\n";
  h << "<table>\n<tr><th class=l>method</th><th>m</th><th>n</th><th>codec</th><th>query time</th><th>memory</th>"
       "<th>bake / build</th><th>median error</th><th>p95 error</th><th>agreement</th><th>Pareto</th></tr>\n";
  for (const SweepRow& r : d.rows) {
    const bool box = r.method == "haptic_box";
    const bool own = box && &r == &d.rows.back();
    if (r.tried_by_the_bake) {
      // Figures of the bake's own trial: time at bake time, no contact agreement measured.
      h << "<tr><td class=l>" << html_escape(r.label) << "</td><td>" << r.m << "</td><td>" << r.n << "</td><td>"
        << html_escape(r.codec) << "</td><td>" << ns_text(r.query_ns) << "</td><td>" << bytes_text(r.memory_bytes)
        << "</td><td>at bake time</td><td colspan=3>felt on " << percent(r.perceptible_share)
        << " of the bake's tuning probes</td><td></td></tr>\n";
      continue;
    }
    h << "<tr><td class=l>" << html_escape(own ? "haptic_box (this report's box)" : r.method) << "</td><td>"
      << (box ? (own ? range_text(d.densities.m_min, d.densities.m_max) : std::to_string(r.m)) : "")
      << "</td><td>" << (box ? std::to_string(r.n) : "") << "</td><td>" << html_escape(r.codec) << (r.refine ? ", refined" : "")
      << "</td><td>" << ns_text(r.query_ns) << "</td><td>" << bytes_text(r.memory_bytes) << "</td><td>"
      << (r.from_cache ? std::string("cached") : r.bake_seconds > 0 ? duration_text(r.bake_seconds) : std::string("loaded"))
      << "</td><td>" << percent(r.force_error_median) << "</td><td>" << percent(r.force_error_p95) << "</td><td>"
      << agreement_percent(r.contact_agreement) << "</td><td>" << (r.pareto ? "yes" : "") << "</td></tr>\n";
  }
  h << "</table>\n<p class=note>Pareto front: no other row is both faster and more accurate (median force "
       "error). Memory of the references counts the mesh arrays and the locator's index, not Embree's BVH.</p>\n";
  h << "<h2>Force error distribution</h2>\n";
  if (!charts.difference.empty()) h << image(charts.difference, "force difference histogram") << "\n";
  if (!charts.histogram.empty()) h << image(charts.histogram, "force error histogram") << "\n";
  if (!d.compression_curve.empty() && !charts.compression.empty())
    h << "<h2>Compression (" << html_escape(d.options.compression_codec) << ")</h2>\n"
      << image(charts.compression, "compression curve") << "\n";
}

// 5. The error field: how many vertices a hand would feel, and its image.
void write_error_field(std::ostringstream& h, const ReportData& d) {
  std::size_t felt = 0;
  double largest = 0.0;
  for (float r : d.error_field.perceptible_ratio)
    if (r > 1.f) ++felt, largest = std::max(largest, double(r));
  h << "<h2>Error field</h2>\n<p>Metric shown: perceptible difference, per vertex the largest box-vs-exact "
       "force difference over what a hand can feel (its perceptual threshold; 1 = just feelable) among its "
    << d.options.error_field_probes_per_vertex << " probe(s) (" << d.error_field.size() << " vertices, computed in "
    << duration_text(d.error_field.seconds) << "): a hand would feel the difference at " << felt << " of "
    << d.error_field.size() << " vertices ("
    << percent(d.error_field.size() ? double(felt) / double(d.error_field.size()) : 0.0) << ")"
    << (felt ? ", up to " + sig(largest) + " times the threshold" : std::string())
    << ". Colours: below 1 the model's plain colour (no one can feel it), from 1 amber through red to dark "
       "crimson at 4 and above. The relative force error, secondary: median "
    << percent(d.error_field_median) << ", p95 " << percent(d.error_field_p95) << " over the vertices with data.</p>\n";
  if (!d.error_field_image.empty() && fs::exists(d.error_field_image))
    h << image(d.error_field_image, "error field") << "\n";
  else
    h << "<p class=note>No rendered image: " << html_escape(d.error_field_note.empty() ? "not requested" : d.error_field_note)
      << "</p>\n";
}

} // namespace

std::string report_html(const ReportData& d, const ChartFiles& charts) {
  const SpeedAgainstExact speed = speed_against_exact(d);
  std::ostringstream h;
  write_page_head(h, d);
  write_stamp(h, d);
  write_verdicts(h, d, speed);
  write_summary(h, d);
  write_accuracy(h, d, speed);
  write_worst_probes(h, d);
  write_charts(h, d, charts);
  write_error_field(h, d);
  if (d.stability) h << stability_html_section(*d.stability, charts.stability_dir);
  h << "<h2>Reproducing</h2>\n<p>summary.json holds every figure above and every parameter (and this page's "
       "summary as text, also in summary.txt); samples.csv one row per probe with both answers (nan: no data). "
       "Compute time "
    << duration_text(d.compute_seconds) << (d.ranks > 1 ? ", " + std::to_string(d.ranks) + " ranks" : std::string()) << ".</p>\n";
  h << "</body></html>\n";
  return h.str();
}

} // namespace hb
