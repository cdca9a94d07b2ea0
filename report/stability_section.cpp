// Stability section.
// 1. The calibration gate and every metric as a table row (box, exact, box - exact,
//    threshold, verdict), failures that exact shares marked as the law's.
// 2. The first force trace (a slide at 1 mm depth) plotted, box against exact, embedded.
#include "stability_section.h"
#include "errors.h"
#include <plplot/plstream.h>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <memory>
#include <sstream>

namespace hb {
namespace {

std::string esc(const std::string& s) {
  std::string o;
  for (char c : s) {
    if (c == '<') o += "&lt;";
    else if (c == '>') o += "&gt;";
    else if (c == '&') o += "&amp;";
    else o += c;
  }
  return o;
}

std::string num(double v) {
  if (std::isnan(v)) return "-";
  char b[32];
  if (v != 0 && (std::fabs(v) < 1e-3 || std::fabs(v) >= 1e5)) std::snprintf(b, sizeof b, "%.3g", v);
  else std::snprintf(b, sizeof b, "%.4f", v);
  return b;
}

std::string data_uri(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw IoError(path + ": cannot read");
  std::ostringstream ss;
  ss << in.rdbuf();
  const std::string bytes = ss.str();
  static const char* t = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string out = "data:image/png;base64,";
  for (std::size_t i = 0; i < bytes.size(); i += 3) {
    unsigned v = (unsigned char)bytes[i] << 16;
    if (i + 1 < bytes.size()) v |= (unsigned char)bytes[i + 1] << 8;
    if (i + 2 < bytes.size()) v |= (unsigned char)bytes[i + 2];
    out += t[v >> 18 & 63];
    out += t[v >> 12 & 63];
    out += i + 1 < bytes.size() ? t[v >> 6 & 63] : '=';
    out += i + 2 < bytes.size() ? t[v & 63] : '=';
  }
  return out;
}

std::string threshold_text(const StabilityMetric& m) {
  switch (m.rule) {
    case StabilityRule::at_most: return "&le; " + num(m.threshold);
    case StabilityRule::at_least: return "&ge; " + num(m.threshold);
    case StabilityRule::within: return num(m.threshold) + " &plusmn; " + num(m.tolerance);
    case StabilityRule::difference_at_most: return "box &minus; exact &le; " + num(m.threshold);
    case StabilityRule::info: return "-";
  }
  return "";
}

void rows(std::ostringstream& h, const std::vector<StabilityMetric>& ms) {
  h << "<table>\n<tr><th>test</th><th>scene</th><th>metric</th><th>box</th><th>exact</th><th>difference</th>"
       "<th>threshold</th><th>verdict</th></tr>\n";
  for (const auto& m : ms) {
    const char* cls = m.rule == StabilityRule::info ? "info" : m.pass ? "pass" : "fail";
    h << "<tr><td>" << esc(m.test) << "</td><td>" << esc(m.scene) << "</td><td>" << esc(m.metric)
      << (m.unit.empty() ? "" : " [" + esc(m.unit) + "]") << "</td><td>" << num(m.box) << "</td><td>" << num(m.exact)
      << "</td><td>" << (std::isnan(m.exact) ? "-" : num(m.difference())) << "</td><td>" << threshold_text(m)
      << "</td><td class=" << cls << ">" << esc(m.verdict) << "</td></tr>\n";
  }
  h << "</table>\n";
}

} // namespace

void plot_force_trace(const ForceTrace& trace, const std::string& png_path) {
  {
    auto pls = std::make_unique<plstream>();
    pls->sdev("pngcairo");
    pls->sfnam(png_path.c_str());
    pls->spage(0, 0, 900, 420, 0, 0);
    const PLINT r[] = {255, 0, 44, 255}, g[] = {255, 0, 160, 127}, b[] = {255, 0, 44, 14};
    pls->scmap0(r, g, b, 4);
    pls->init();
    pls->col0(1);
    double tmax = 1e-3, fmax = 0.1;
    for (double t : trace.t_s) tmax = std::max(tmax, t);
    for (double f : trace.box_n) fmax = std::max(fmax, f);
    for (double f : trace.exact_n) fmax = std::max(fmax, f);
    pls->schr(0, 0.85);
    pls->env(0.0, tmax * 1e3, 0.0, fmax * 1.15, 0, 0);
    pls->lab("time, ms (1 kHz ticks)", "|F|, N", (trace.scene + ": " + trace.label).c_str());
    std::vector<PLFLT> x(trace.t_s.size());
    for (std::size_t i = 0; i < x.size(); ++i) x[i] = trace.t_s[i] * 1e3;
    pls->col0(2);
    pls->line(PLINT(x.size()), x.data(), trace.exact_n.data());
    pls->col0(3);
    pls->line(PLINT(x.size()), x.data(), trace.box_n.data());
    pls->col0(1);
    pls->mtex("t", 0.6, 1.0, 1.0, "exact (green), box (orange)");
  }
  std::error_code ec;
  if (!std::filesystem::exists(png_path, ec) || std::filesystem::file_size(png_path, ec) == 0)
    throw IoError(png_path + ": PLplot could not write the chart (is plplot-driver-cairo installed?)");
}

std::string stability_html_section(const StabilityReport& r, const std::string& charts_dir) {
  std::ostringstream h;
  h << "<h2>Stability along trajectories</h2>\n<p>Deterministic, hardware-free trajectories (device profile "
    << esc(r.device) << ", 1 kHz zero-order hold, depth law " << esc(r.depth_law) << ", servo filter "
    << esc(r.filter) << "): the box and the exact answer on the same trajectories. " << r.passed << " figures pass, "
    << r.failed << " fail, " << r.failed_law
    << " of those fail for the exact answer too (a limit of the force law, not of the box). "
       "Calibration gate: "
    << (r.calibration_pass ? "pass" : "<b>FAIL</b> (the harness is wrong)") << ". Method: docs/stability.md.</p>\n";
  rows(h, r.calibration);
  rows(h, r.metrics);
  if (!r.traces.empty()) {
    const std::string png = (std::filesystem::path(charts_dir) / "stability_force_trace.png").string();
    plot_force_trace(r.traces.front(), png);
    h << "<img alt=\"force along a trajectory\" src=\"" << data_uri(png) << "\">\n";
  }
  return h.str();
}

} // namespace hb
