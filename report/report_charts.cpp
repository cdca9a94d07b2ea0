// Each chart is one PLplot stream on a cairo file driver (svgcairo for .svg, vector and sharp
// when printed; pngcairo otherwise; no display), with a white background and a small fixed
// palette; the stream ends (and the file is flushed) when the plstream goes out of scope.
#include "report_charts.h"
#include "errors.h"
#include "figure_text.h"
#include "evaluation/comparison.h"
#include <plplot/plstream.h>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <memory>

namespace hb {
namespace {

enum Colour { kWhite = 0, kBlack = 1, kBlue = 2, kRed = 3, kGreen = 4, kOrange = 5, kGrey = 6 };

std::unique_ptr<plstream> open_png(const std::string& path, int width = 900, int height = 560) {
  auto pls = std::make_unique<plstream>();
  const bool svg = path.size() > 4 && path.compare(path.size() - 4, 4, ".svg") == 0;
  pls->sdev(svg ? "svgcairo" : "pngcairo");
  pls->sfnam(path.c_str());
  pls->spage(0, 0, width, height, 0, 0);
  const PLINT r[] = {255, 0, 31, 214, 44, 255, 150};
  const PLINT g[] = {255, 0, 119, 39, 160, 127, 150};
  const PLINT b[] = {255, 0, 180, 40, 44, 14, 150};
  pls->scmap0(r, g, b, 7);
  pls->init();
  pls->col0(kBlack);
  return pls;
}

void check_written(const std::string& path) {
  std::error_code ec;
  if (!std::filesystem::exists(path, ec) || std::filesystem::file_size(path, ec) == 0)
    throw IoError(path + ": PLplot could not write the chart (is plplot-driver-cairo installed?)");
}

} // namespace

void plot_speed_accuracy(const std::vector<SweepRow>& rows, const std::string& png_path) {
  {
    auto pls = open_png(png_path);
    double xmin = 1e300, xmax = 0, ymax = 0;
    for (const SweepRow& r : rows) {
      const double x = std::max(r.query_ns, 1.0);
      xmin = std::min(xmin, x);
      xmax = std::max(xmax, x);
      ymax = std::max(ymax, 100.0 * r.force_error_median);
    }
    if (rows.empty()) xmin = 1, xmax = 10;
    const double lx0 = std::floor(std::log10(xmin) - 0.05), lx1 = std::ceil(std::log10(xmax) + 0.05);
    ymax = ymax > 0 ? ymax * 1.15 : 1.0;
    pls->schr(0, 0.85);
    pls->env(lx0, lx1, -0.04 * ymax, ymax, 0, 12);  // 12: log x with grid
    pls->lab("query time, ns (one core, log scale)", "median force error, %",
             "Speed against accuracy (same probes for every method)");
    // Pareto front as a staircase line through its points, fastest first.
    std::vector<const SweepRow*> front;
    for (const SweepRow& r : rows)
      if (r.pareto) front.push_back(&r);
    std::sort(front.begin(), front.end(), [](const SweepRow* a, const SweepRow* b) { return a->query_ns < b->query_ns; });
    if (front.size() > 1) {
      std::vector<PLFLT> fx, fy;
      for (const SweepRow* r : front) {
        fx.push_back(std::log10(std::max(r->query_ns, 1.0)));
        fy.push_back(100.0 * r->force_error_median);
      }
      pls->col0(kGrey);
      pls->lsty(2);
      pls->line(PLINT(fx.size()), fx.data(), fy.data());
      pls->lsty(1);
    }
    // Labels: to the right of their point, or to the left in the right quarter of the axis (so
    // none runs off the edge); a label that would overlap an earlier one moves down a line.
    pls->schr(0, 0.65);
    const double line = 0.045 * ymax, span = lx1 - lx0;
    std::vector<std::pair<double, double>> placed;  // label anchors already used
    bool have_front = false, have_dominated = false, have_exact = false, have_vtk = false;
    for (const SweepRow& r : rows) {
      PLFLT x = std::log10(std::max(r.query_ns, 1.0)), y = 100.0 * r.force_error_median;
      const bool box = r.method == "haptic_box";
      const bool vtk = r.method.find("vtk") != std::string::npos;
      (box ? (r.pareto ? have_front : have_dominated) : (vtk ? have_vtk : have_exact)) = true;
      pls->col0(box ? (r.pareto ? kBlue : kGrey) : (vtk ? kOrange : kRed));
      pls->ssym(0, box ? 1.2 : 1.6);
      pls->poin(1, &x, &y, box ? 17 : 16);
      char label[96];
      if (box && !r.label.empty())
        std::snprintf(label, sizeof label, "%s%s%s", r.label.c_str(),
                      r.codec != "none" && !r.codec.empty() ? (" " + r.codec).c_str() : "", r.refine ? " ref" : "");
      else if (box)
        std::snprintf(label, sizeof label, "m%d n%d%s%s", r.m, r.n,
                      r.codec != "none" && !r.codec.empty() ? (" " + r.codec).c_str() : "", r.refine ? " ref" : "");
      else std::snprintf(label, sizeof label, "%s", vtk ? "VTK locator" : "exact Embree");
      const bool left = x > lx0 + 0.75 * span;
      double ly = y + 0.02 * ymax;
      for (int tries = 0; tries < 8; ++tries) {
        bool clash = false;
        for (const auto& [px, py] : placed)
          if (std::fabs(px - x) < 0.12 * span && std::fabs(py - ly) < line) clash = true;
        if (!clash) break;
        ly -= line;
      }
      placed.emplace_back(x, ly);
      pls->ptex(x + (left ? -0.015 : 0.015) * span, ly, 1.0, 0.0, left ? 1.0 : 0.0, label);
    }
    // A legend for the series present only.
    struct Entry { bool present; int colour; const char* text; };
    const Entry entries[] = {{have_front, kBlue, "haptic box (Pareto front)"},
                             {have_dominated, kGrey, "haptic box (dominated)"},
                             {have_exact, kRed, "exact Embree"},
                             {have_vtk, kOrange, "VTK vtkStaticCellLocator"}};
    double pos = 0.0;
    pls->schr(0, 0.7);
    for (const Entry& e : entries) {
      if (!e.present) continue;
      pls->col0(e.colour);
      pls->mtex("t", 1.1, pos, 0.0, (std::string("\u25CF ") + e.text).c_str());
      pos += 0.02 + 0.0115 * double(std::string(e.text).size());
    }
    pls->col0(kBlack);
  }
  check_written(png_path);
}

void plot_force_error_histogram(const std::vector<double>& errors, const std::string& png_path, int bins) {
  {
    auto pls = open_png(png_path);
    std::vector<PLFLT> pct(errors.size());
    for (std::size_t i = 0; i < errors.size(); ++i) pct[i] = 100.0 * errors[i];
    const double hi = errors.empty() ? 1.0 : std::max(1e-6, 100.0 * quantile(errors, 0.99));
    bins = std::max(bins, 2);
    std::vector<PLFLT> y(static_cast<std::size_t>(bins), 0.0);
    const double w = hi / bins;
    for (PLFLT v : pct) y[std::size_t(std::clamp(int(v / w), 0, bins - 1))] += 1.0;  // overflow in the last bin
    double ymax = 1.0;
    for (PLFLT c : y) ymax = std::max(ymax, c);
    pls->schr(0, 0.85);
    pls->env(0.0, hi, 0.0, ymax * 1.1, 0, 0);
    pls->lab("relative force error |F1 - F0| / |F0|, % (last bin: >= p99)", "probes",
             "Force error over the probes both answers call a contact");
    pls->col0(kBlue);
    for (int b = 0; b < bins; ++b) {
      const PLFLT bx[4] = {b * w, b * w, (b + 1) * w, (b + 1) * w};
      const PLFLT by[4] = {0.0, y[std::size_t(b)], y[std::size_t(b)], 0.0};
      pls->fill(4, bx, by);
    }
    pls->col0(kBlack);
    for (int b = 0; b < bins; ++b) {
      const PLFLT bx[5] = {b * w, b * w, (b + 1) * w, (b + 1) * w, b * w};
      const PLFLT by[5] = {0.0, y[std::size_t(b)], y[std::size_t(b)], 0.0, 0.0};
      pls->line(5, bx, by);
    }
    if (!errors.empty()) {
      const double med = 100.0 * quantile(errors, 0.5), p95 = 100.0 * quantile(errors, 0.95);
      for (auto [v, c] : {std::pair<double, int>{med, kRed}, {p95, kOrange}}) {
        const PLFLT lx[2] = {v, v}, ly[2] = {0.0, ymax * 1.05};
        pls->col0(c);
        pls->line(2, lx, ly);
      }
      const std::string text = "median " + sig(med) + " % (red), p95 " + sig(p95) + " % (orange), " +
                               count_text(double(errors.size())) + " probes";
      pls->col0(kBlack);
      pls->mtex("t", 1.1, 1.0, 1.0, text.c_str());
    }
  }
  check_written(png_path);
}

void plot_compression_curve(const std::vector<std::pair<double, double>>& curve, const std::string& png_path) {
  {
    auto pls = open_png(png_path);
    std::vector<PLFLT> x, y;
    for (const auto& [cr, err] : curve) {
      x.push_back(cr);
      y.push_back(100.0 * err);
    }
    double xmax = 1.0, ymax = 1e-3;
    for (std::size_t i = 0; i < x.size(); ++i) xmax = std::max(xmax, x[i]), ymax = std::max(ymax, y[i]);
    pls->schr(0, 0.85);
    pls->env(0.0, xmax * 1.1, 0.0, ymax * 1.15, 0, 2);
    pls->lab("compression rate (x : 1)", "median force error against the raw tables, %",
             "Compression curve (one point per error bound)");
    pls->col0(kBlue);
    if (x.size() > 1) pls->line(PLINT(x.size()), x.data(), y.data());
    if (!x.empty()) pls->poin(PLINT(x.size()), x.data(), y.data(), 17);
  }
  check_written(png_path);
}

} // namespace hb
