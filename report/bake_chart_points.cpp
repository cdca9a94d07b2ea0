// The bake's own chart points: exact, the bake, the raw samplings tried, read off the budget
// report (query times at bake time, one core, random order; shares of the fresh probes for
// the bake, of the tuning probes for the raw samplings, as the bake judged them).
#include "bake_chart_points.h"
#include "codec/codec.h"
#include "figure_text.h"
#include "summary_text.h"

namespace hb {
namespace {

const char kRawSuffix[] = " (tried by the bake)";

std::string outcome_words(const std::string& outcome) {
  if (outcome == "kept") return "kept: it answers the bake";
  if (outcome == "serves") return "serves, but a cheaper sampling was kept";
  if (outcome == "felt-probes") return "felt on probes, not kept";
  if (outcome == "felt-slides") return "felt along slides, not kept";
  if (outcome == "felt-light") return "felt on light touches, not kept";
  if (outcome == "over-cap") return "over the memory cap, not kept";
  if (outcome == "slower-strokes") return "faster at random but slower than exact along strokes, not kept";
  return "slower than exact, not kept";
}

} // namespace

std::string bake_label(const BoxScene& scene) {
  const std::size_t boxes = scene.boxes().size();
  const BudgetReport& r = scene.budget_report();
  const std::string budget = budget_spec(r.budget) == budget_spec(ErrorBudget{}) ? "default bake" : "bake to " + budget_spec(r.budget);
  return budget + ": " + std::to_string(boxes) + (boxes == 1 ? " box" : " boxes");
}

std::vector<BakeChartPoint> bake_chart_points(const BoxScene& scene) {
  std::vector<BakeChartPoint> out;
  const BudgetReport& r = scene.budget_report();
  if (!r.present) return out;
  const std::string timed = " a query at bake time (one core, random order)";
  if (r.exact_ns > 0) {
    BakeChartPoint p;
    p.row.method = "exact_embree";
    p.row.query_ns = r.exact_ns;
    p.row.contact_agreement = 1.0;
    p.row.within_budget = true;
    p.about = "exact Embree: " + duration_text(r.exact_ns * 1e-9) + timed + ", beside the bake's answer; the reference";
    out.push_back(p);
  }
  if (r.answer_ns > 0) {
    BakeChartPoint p;
    SweepRow& row = p.row;
    row.method = "haptic_box";
    row.label = bake_label(scene);
    // As the sweep's row of the default bake names it.
    row.refine = scene.surface() != nullptr;
    row.codec = scene.boxes().empty() ? "none" : codec_name(scene.boxes().front().codec());
    row.query_ns = r.answer_ns;
    row.memory_bytes = scene.memory_bytes();
    row.force_error_median = r.force_median;
    row.force_error_p95 = r.force_p95;
    row.contact_agreement = r.agreement;
    row.angle_error_p99_deg = r.direction_p99_deg;
    row.perceptible_share = r.perceptible;
    row.within_budget = r.met;
    const std::string answer = r.answer.empty() ? "cells" : r.answer;  // older files name none: the cells
    p.about = row.label + ", answered by " + route_words(answer) + ": " + duration_text(r.answer_ns * 1e-9) + timed +
              ", perceptibly different on " + percent(r.perceptible) + " of " + count_text(double(r.probes)) +
              " fresh probes (the budget: at most " + percent(r.budget.perceptible) + ", " + (r.met ? "met" : "MISSED") +
              "); " + bytes_text(scene.memory_bytes()) +
              (r.stroke_answer == "embree"
                   ? "; along strokes exact Embree over the full mesh (" + duration_text(r.stroke_embree_ns * 1e-9) +
                         " a query against the cells' " + duration_text(r.stroke_cells_ns * 1e-9) + " at bake time)"
                   : std::string());
    out.push_back(p);
  }
  for (const BudgetReport::RawTried& t : r.raw_tried) {
    if (!(t.box_ns > 0)) continue;
    BakeChartPoint p;
    SweepRow& row = p.row;
    row.method = "haptic_box";
    row.tried_by_the_bake = true;
    row.m = t.m, row.n = t.n;
    row.codec = "none";
    row.label = "raw m" + std::to_string(t.m) + " n" + std::to_string(t.n) + kRawSuffix;
    row.query_ns = t.box_ns;
    row.memory_bytes = std::size_t(t.bytes);
    row.contact_agreement = -1.0;  // the trial judges what a hand feels only
    row.perceptible_share = t.probes_felt;
    row.within_budget = t.outcome == "kept";
    p.about = row.label + ", the paper's raw haptic box over the whole model: " + duration_text(t.box_ns * 1e-9) + timed +
              " against exact's " + duration_text(t.exact_ns * 1e-9) + ", perceptibly different on " + percent(t.probes_felt) +
              " of " + count_text(double(r.tuning_probes)) + " tuning probes" +
              (t.light_felt >= 0 ? ", " + percent(t.light_felt) + " of light touches at any angle" : std::string()) +
              (t.ticks_felt >= 0 ? " and " + percent(t.ticks_felt) + " of slide ticks" : std::string()) + "; " +
              bytes_text(std::uint64_t(t.bytes)) + "; " + outcome_words(t.outcome);
    out.push_back(p);
  }
  return out;
}

std::vector<SweepRow> bake_chart_rows(const BoxScene& scene) {
  std::vector<SweepRow> rows;
  for (const BakeChartPoint& p : bake_chart_points(scene)) rows.push_back(p.row);
  return rows;
}

double felt_axis_cap_percent() { return 10.0 * 100.0 * ErrorBudget{}.perceptible; }

double felt_axis_edge_percent() { return 1.1 * felt_axis_cap_percent(); }

std::string off_scale_words(double share) {
  return 100.0 * share > felt_axis_cap_percent() ? ": " + percent(share) + ", off the scale" : std::string();
}

} // namespace hb
