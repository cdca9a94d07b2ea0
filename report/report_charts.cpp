// Each chart is one PLplot stream on a cairo file driver (svgcairo for .svg, vector and sharp
// when printed; pngcairo otherwise; no display), with a white background and a small fixed
// palette; the stream ends (and the file is flushed) when the plstream goes out of scope.
#include "report_charts.h"
#include "bake_chart_points.h"
#include "series_colours.h"
#include "errors.h"
#include "figure_text.h"
#include "evaluation/comparison.h"
#include "recipe/error_budget.h"
#include <plplot/plstream.h>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <limits>
#include <memory>

namespace hb {
namespace {

enum Colour { kWhite = 0, kBlack = 1, kBlue = 2, kRed = 3, kGreen = 4, kOrange = 5, kGrey = 6, kPurple = 7 };

std::unique_ptr<plstream> open_png(const std::string& path, int width = 900, int height = 560) {
  auto pls = std::make_unique<plstream>();
  const bool svg = path.size() > 4 && path.compare(path.size() - 4, 4, ".svg") == 0;
  pls->sdev(svg ? "svgcairo" : "pngcairo");
  pls->sfnam(path.c_str());
  pls->spage(0, 0, width, height, 0, 0);
  // kBlue, kRed, kOrange, kPurple: the series colours (series_colours.h), as the window draws them.
  const PLINT r[] = {255, 0, kBoxSeries.r, kExactSeries.r, 44, kVtkSeries.r, 150, kRawTrialSeries.r};
  const PLINT g[] = {255, 0, kBoxSeries.g, kExactSeries.g, 160, kVtkSeries.g, 150, kRawTrialSeries.g};
  const PLINT b[] = {255, 0, kBoxSeries.b, kExactSeries.b, 44, kVtkSeries.b, 150, kRawTrialSeries.b};
  pls->scmap0(r, g, b, 8);
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

LabelPlacer::LabelPlacer(double x0, double x1, double y0, double y1) : x0_(x0), x1_(x1), y0_(y0), y1_(y1) {}

LabelPlacer::Placement LabelPlacer::place(double x, double y, std::size_t chars, bool must, bool big) {
  const double span = x1_ - x0_, line = 0.05 * (y1_ - y0_);
  const double width = kCharWidth * span * double(chars), gap = (big ? 0.035 : 0.012) * span;
  // Beside the point first; a label that must be drawn (a reference, the default bake, a raw
  // sampling the bake tried) is then stacked higher: the good configurations crowd the bottom
  // of the top panel (0% felt), where there is no room below. An optional one stays near.
  const double dys[] = {0.2 * line, -0.9 * line, 1.2 * line, -1.6 * line, 2.2 * line, 3.2 * line};
  struct Try { bool left; double dy; };
  std::vector<Try> tries;
  for (std::size_t k = 0; k < (must ? 6u : 4u); ++k)
    for (bool left : {false, true}) tries.push_back({left, dys[k]});
  const auto rect = [&](const Try& t) {
    const double lo = t.left ? x - gap - width : x + gap, base = y + t.dy;
    return Rect{lo, lo + width, base - 0.1 * line, base + 0.8 * line};
  };
  const auto fits = [&](const Rect& r) {
    if (r.x0 < x0_ || r.x1 > x1_ || r.y0 < y0_ || r.y1 > y1_) return false;
    for (const Rect& q : taken_)
      if (r.x0 < q.x1 && q.x0 < r.x1 && r.y0 < q.y1 && q.y0 < r.y1) return false;
    return true;
  };
  const Try* chosen = nullptr;
  for (const Try& t : tries)
    if (fits(rect(t))) {
      chosen = &t;
      break;
    }
  Placement out;
  if (!chosen) {
    if (!must) return out;
    // The place inside the axes across that covers the least of what is there.
    double least = std::numeric_limits<double>::infinity();
    for (const Try& t : tries) {
      const Rect r = rect(t);
      if (r.x0 < x0_ || r.x1 > x1_) continue;
      double covered = 0;
      for (const Rect& q : taken_)
        covered += std::max(0.0, std::min(r.x1, q.x1) - std::max(r.x0, q.x0)) *
                   std::max(0.0, std::min(r.y1, q.y1) - std::max(r.y0, q.y0));
      if (r.y0 < y0_ || r.y1 > y1_) covered += 0.5 * (r.x1 - r.x0) * (r.y1 - r.y0);  // cut by the frame
      if (covered < least) least = covered, chosen = &t;
    }
    if (!chosen) chosen = &tries.front();
  }
  taken_.push_back(rect(*chosen));
  out.shown = true;
  out.left = chosen->left;
  out.x = chosen->left ? x - gap : x + gap;
  out.y = y + chosen->dy;
  out.box = taken_.back();
  return out;
}

void LabelPlacer::mark(double x, double y, bool big) {
  const double span = x1_ - x0_, line = 0.05 * (y1_ - y0_);
  const double half_x = (big ? 0.03 : 0.008) * span, half_y = (big ? 0.5 : 0.25) * line;
  taken_.push_back(Rect{x - half_x, x + half_x, y - half_y, y + half_y});
}

void LabelPlacer::reserve(double x0, double x1, double y0, double y1) { taken_.push_back(Rect{x0, x1, y0, y1}); }

namespace {

std::string row_label(const SweepRow& r) {
  // The default bake and the raw samplings it tried by their names alone ("default bake: 19
  // boxes", "raw m16 n8 (tried by the bake)"); a sampling or a scene with its codec and route.
  const bool named = r.label.rfind("default bake", 0) == 0 || r.label.rfind("bake to ", 0) == 0 || r.tried_by_the_bake;
  if (r.method == "haptic_box") return named ? r.label : configuration_name(r);
  return r.method.find("vtk") != std::string::npos ? "VTK locator" : "exact Embree";
}

} // namespace

void plot_speed_accuracy(const std::vector<SweepRow>& rows, const std::string& png_path) {
  {
    // Two panels on one time axis: the share of probes a hand would tell apart from exact
    // (top, the headline, with the default budget's line) and the contact agreement (bottom),
    // so a fast configuration that loses contacts is seen to.
    auto pls = open_png(png_path, 900, 860);
    double xmin = 1e300, xmax = 0, amin = 100;
    for (const SweepRow& r : rows) {
      const double x = std::max(r.query_ns, 1.0);
      xmin = std::min(xmin, x);
      xmax = std::max(xmax, x);
      if (r.contact_agreement >= 0.0) amin = std::min(amin, 100.0 * r.contact_agreement);  // < 0: not measured
    }
    if (rows.empty()) xmin = 1, xmax = 10;
    const double lx0 = std::floor(std::log10(xmin) - 0.05), lx1 = std::ceil(std::log10(xmax) + 0.05);
    const double budget_felt = 100.0 * ErrorBudget{}.perceptible;  // the default budget's
    // The top panel shows up to felt_axis_cap_percent(); a share above sits on the top edge,
    // its label saying its value (off_scale_words).
    const double cap = felt_axis_cap_percent();
    const double ymax = 1.15 * cap;
    // Room above 100% for the labels of the exact answers there.
    const double a0 = std::max(0.0, std::floor(amin / 10.0) * 10.0 - 5.0), a1 = 100.0 + 0.14 * (100.0 - a0);
    const double budget_agreement = 100.0 * ErrorBudget{}.agreement;  // the default budget's
    std::vector<const SweepRow*> front;
    for (const SweepRow& r : rows)
      if (r.pareto) front.push_back(&r);
    std::sort(front.begin(), front.end(), [](const SweepRow* a, const SweepRow* b) { return a->query_ns < b->query_ns; });
    bool have_front = false, have_dominated = false, have_exact = false, have_vtk = false, have_raw = false;
    pls->adv(0);
    for (int panel = 0; panel < 2; ++panel) {
      const bool top = panel == 0;
      const double y0 = top ? -0.04 * ymax : a0, y1 = top ? ymax : a1;
      pls->schr(0, 0.85);
      pls->col0(kBlack);
      if (top) pls->vpor(0.1, 0.95, 0.53, 0.9);
      else pls->vpor(0.1, 0.95, 0.08, 0.45);
      pls->wind(lx0, lx1, y0, y1);
      pls->box("bcgnstl", 0.0, 0, "bcgnstv", 0.0, 0);
      if (top)
        pls->lab("", "perceptibly different probes, %", "Speed against what a hand feels (same probes for every method)");
      else
        pls->lab("query time, ns (one core, log scale)", "contact agreement, %", "");
      const auto value = [&](const SweepRow& r) {
        return top ? std::min(100.0 * r.perceptible_share, felt_axis_edge_percent()) : 100.0 * r.contact_agreement;
      };
      const auto off_scale = [&](const SweepRow& r) { return top && 100.0 * r.perceptible_share > cap; };
      LabelPlacer labels(lx0, lx1, y0, y1);
      if (top) {
        // The default budget's perceptible share, its words at the right end over the line.
        const PLFLT bx[2] = {lx0, lx1}, by[2] = {budget_felt, budget_felt};
        pls->col0(kGreen);
        pls->lsty(2);
        pls->line(2, bx, by);
        pls->lsty(1);
        pls->schr(0, 0.6);
        char budget[96];
        std::snprintf(budget, sizeof budget, "default budget: at most %g%% perceptibly different", budget_felt);
        const double right = lx1 - 0.01 * (lx1 - lx0), above = budget_felt + 0.03 * (y1 - y0);
        pls->ptex(right, above, 1.0, 0.0, 1.0, budget);
        labels.reserve(right - LabelPlacer::kCharWidth * (lx1 - lx0) * double(std::strlen(budget)), right, budget_felt,
                       above + 0.03 * (y1 - y0));
      } else {
        // The default budget's agreement, its words at the right end under the line.
        const PLFLT bx[2] = {lx0, lx1}, by[2] = {budget_agreement, budget_agreement};
        pls->col0(kGreen);
        pls->lsty(2);
        pls->line(2, bx, by);
        pls->lsty(1);
        pls->schr(0, 0.6);
        char budget[64];
        std::snprintf(budget, sizeof budget, "default budget: %g%% agreement", budget_agreement);
        const double right = lx1 - 0.01 * (lx1 - lx0), below = budget_agreement - 0.05 * (a1 - a0);
        pls->ptex(right, below, 1.0, 0.0, 1.0, budget);
        labels.reserve(right - LabelPlacer::kCharWidth * (lx1 - lx0) * double(std::strlen(budget)), right,
                       below - 0.01 * (a1 - a0), budget_agreement);
      }
      // Pareto front as a line through its points, fastest first.
      if (front.size() > 1) {
        std::vector<PLFLT> fx, fy;
        for (const SweepRow* r : front) {
          fx.push_back(std::log10(std::max(r->query_ns, 1.0)));
          fy.push_back(value(*r));
        }
        pls->col0(kGrey);
        pls->lsty(2);
        pls->line(PLINT(fx.size()), fx.data(), fy.data());
        pls->lsty(1);
      }
      // A raw sampling the bake tried has no contact agreement measured: the top panel only.
      const auto shown = [&](const SweepRow& r) { return top || r.contact_agreement >= 0.0; };
      for (const SweepRow& r : rows)
        if (shown(r)) labels.mark(std::log10(std::max(r.query_ns, 1.0)), value(r), r.method != "haptic_box");
      // The references, the front and the named rows (the default bake, the raw samplings the
      // bake tried) first: they get the free places.
      std::vector<const SweepRow*> order;
      for (const SweepRow& r : rows)
        if (shown(r) && (r.method != "haptic_box" || r.pareto || !r.label.empty())) order.push_back(&r);
      for (const SweepRow& r : rows)
        if (shown(r) && !(r.method != "haptic_box" || r.pareto || !r.label.empty())) order.push_back(&r);
      pls->schr(0, 0.65);
      for (const SweepRow* rp : order) {
        const SweepRow& r = *rp;
        PLFLT x = std::log10(std::max(r.query_ns, 1.0)), y = value(r);
        const bool box = r.method == "haptic_box";
        const bool vtk = r.method.find("vtk") != std::string::npos;
        const bool raw = r.tried_by_the_bake;
        (raw ? have_raw : box ? (r.pareto ? have_front : have_dominated) : (vtk ? have_vtk : have_exact)) = true;
        const int colour = raw ? kPurple : box ? (r.pareto ? kBlue : kGrey) : (vtk ? kOrange : kRed);
        pls->col0(colour);
        pls->ssym(0, box ? 1.2 : 1.6);
        pls->poin(1, &x, &y, off_scale(r) ? 7 : box ? 17 : 16);  // an open triangle: off the scale above
        const std::string text = row_label(r) + (top ? off_scale_words(r.perceptible_share) : std::string());
        const LabelPlacer::Placement at = labels.place(x, y, text.size(), !box || r.pareto || !r.label.empty(), !box);
        if (at.shown) pls->ptex(at.x, at.y, 1.0, 0.0, at.left ? 1.0 : 0.0, text.c_str());
      }
    }
    // A legend for the series present only (over the top panel).
    pls->vpor(0.1, 0.95, 0.53, 0.9);
    pls->wind(lx0, lx1, -0.04 * ymax, ymax);
    struct Entry { bool present; int colour; const char* text; };
    const Entry entries[] = {{have_front, kBlue, "box, Pareto front"},
                             {have_dominated, kGrey, "box, dominated"},
                             {have_exact, kRed, "exact Embree"},
                             {have_vtk, kOrange, "VTK vtkStaticCellLocator"},
                             {have_raw, kPurple, "raw box, tried by the bake"}};
    // One line across the panel: smaller letters when the series present need more room.
    double width = 0.0;
    for (const Entry& e : entries)
      if (e.present) width += 0.03 + 0.0125 * double(std::string(e.text).size());
    const double shrink = std::min(1.0, 0.98 / std::max(width, 1e-9));
    double pos = 0.0;
    pls->schr(0, 0.7 * shrink);
    for (const Entry& e : entries) {
      if (!e.present) continue;
      pls->col0(e.colour);
      pls->mtex("t", 1.1, pos, 0.0, (std::string("\u25CF ") + e.text).c_str());
      pos += shrink * (0.03 + 0.0125 * double(std::string(e.text).size()));
    }
    pls->col0(kBlack);
  }
  check_written(png_path);
}

namespace {

// Counts of `values` in `bins` bins over [0, hi) (the last bin also takes what lies beyond),
// drawn as filled bars with the axes and labels; returns the tallest count.
double draw_histogram(plstream& pls, const std::vector<double>& values, double hi, int bins, const char* xlabel,
                      const char* title) {
  bins = std::max(bins, 2);
  std::vector<PLFLT> y(static_cast<std::size_t>(bins), 0.0);
  const double w = hi / bins;
  for (double v : values) y[std::size_t(std::clamp(int(v / w), 0, bins - 1))] += 1.0;
  double ymax = 1.0;
  for (PLFLT c : y) ymax = std::max(ymax, c);
  pls.schr(0, 0.85);
  pls.env(0.0, hi, 0.0, ymax * 1.1, 0, 0);
  pls.lab(xlabel, "probes", title);
  pls.col0(kBlue);
  for (int b = 0; b < bins; ++b) {
    const PLFLT bx[4] = {b * w, b * w, (b + 1) * w, (b + 1) * w};
    const PLFLT by[4] = {0.0, y[std::size_t(b)], y[std::size_t(b)], 0.0};
    pls.fill(4, bx, by);
  }
  pls.col0(kBlack);
  for (int b = 0; b < bins; ++b) {
    const PLFLT bx[5] = {b * w, b * w, (b + 1) * w, (b + 1) * w, b * w};
    const PLFLT by[5] = {0.0, y[std::size_t(b)], y[std::size_t(b)], 0.0, 0.0};
    pls.line(5, bx, by);
  }
  return ymax;
}

} // namespace

void plot_force_error_histogram(const std::vector<double>& errors, const std::string& png_path, int bins) {
  {
    auto pls = open_png(png_path);
    std::vector<double> pct(errors.size());
    for (std::size_t i = 0; i < errors.size(); ++i) pct[i] = 100.0 * errors[i];
    const double hi = errors.empty() ? 1.0 : std::max(1e-6, 100.0 * quantile(errors, 0.99));
    const double ymax = draw_histogram(*pls, pct, hi, bins, "relative force error |F1 - F0| / |F0|, % (last bin: >= p99)",
                                       "Force error over the probes both answers call a contact");
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

void plot_force_difference_histogram(const std::vector<double>& differences_n, const PerceptualThresholds& t,
                                     double exact_median_n, const std::string& png_path, int bins) {
  {
    auto pls = open_png(png_path);
    // The axis reaches past the threshold, so "nothing a hand feels" reads as bars left of it.
    const double p99 = differences_n.empty() ? 0.0 : quantile(differences_n, 0.99);
    const double hi = std::max({1.5 * t.floor_n, p99, 1e-9});
    const double ymax = draw_histogram(*pls, differences_n, hi, bins, "| |F box| - |F exact| |, N (last bin: >= the axis end)",
                                       "Force difference a hand would feel? (probes with a contact on either side)");
    // The absolute threshold F0 and the JND at exact's median force (w |F|).
    const double jnd = t.weber * exact_median_n;
    for (auto [v, c] : {std::pair<double, int>{t.floor_n, kRed}, {jnd, kOrange}}) {
      if (!(v > 0.0) || v > hi) continue;
      const PLFLT lx[2] = {v, v}, ly[2] = {0.0, ymax * 1.05};
      pls->col0(c);
      pls->lsty(c == kOrange ? 2 : 1);
      pls->line(2, lx, ly);
      pls->lsty(1);
    }
    const std::string text = "felt beyond max(" + sig(100.0 * t.weber) + " % |F|, " + sig(t.floor_n) + " N): " +
                             sig(t.floor_n) + " N (red), " + sig(100.0 * t.weber) + " % of exact's median " +
                             sig(exact_median_n) + " N (orange); " + count_text(double(differences_n.size())) +
                             " probes";
    pls->col0(kBlack);
    pls->schr(0, 0.7);
    pls->mtex("t", 1.1, 1.0, 1.0, text.c_str());
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
