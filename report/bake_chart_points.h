#pragma once
// The speed chart of a budgeted bake on its own (the first chart a user meets, in
// the window right after a bake and in a report, shows what a hand feels against query time
// with the default bake, exact and the raw configurations the bake tried). Every figure comes
// from the scene's budget report (hb::BudgetReport), measured at bake time: nothing is baked
// or timed again.
#include "scene/box_scene.h"
#include "recipe/sweep.h"
#include <string>
#include <vector>

namespace hb {

/// One point: a row as the sweep's (method, label, query_ns, perceptible_share, ...) and what
/// it is in a sentence (a chart's tooltip, the report's table).
struct BakeChartPoint {
  SweepRow row;
  std::string about;
};

/// The points of `scene`'s budget report, each only when its query time was recorded (files
/// from older versions record none): exact Embree ("exact_embree", timed beside the bake's
/// answer, 0 % perceptibly different); the bake ("haptic_box", labelled as the sweep's row,
/// "default bake: N boxes", or "bake to <budget>: N boxes" for another budget; its share of
/// the fresh probes perceptibly different); each raw sampling tried ("haptic_box", labelled
/// "raw m16 n8 (tried by the bake)", SweepRow::tried_by_the_bake; its share of the tuning
/// probes; contact agreement -1: not measured). Empty for a scene not baked to a budget.
std::vector<BakeChartPoint> bake_chart_points(const BoxScene& scene);

/// The rows of bake_chart_points(scene).
std::vector<SweepRow> bake_chart_rows(const BoxScene& scene);

/// The label bake_chart_points gives the bake itself ("default bake: 19 boxes").
std::string bake_label(const BoxScene& scene);

/// The speed charts' perceptible axis (the report's and the window's), in %: up to ten times
/// the default budget's share, where shares near the budget are seen apart. A share beyond
/// is drawn at felt_axis_edge_percent() (the top edge), its words saying its value.
double felt_axis_cap_percent();
double felt_axis_edge_percent();
/// What a point's words add when its share (a fraction) is beyond the cap: ": 4.21 %, off the
/// scale"; empty within it.
std::string off_scale_words(double share);

} // namespace hb
