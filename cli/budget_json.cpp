#include "budget_json.h"
#include "perception/budget_report.h"

namespace hb::cli {

nlohmann::json budget_json(const BudgetReport& r) {
  if (!r.present) return nullptr;
  nlohmann::json pieces = nlohmann::json::array();
  for (const PieceChoice& p : r.pieces)
    pieces.push_back({{"cell", p.cell}, {"n", p.n}, {"refine", p.refine}, {"tuning_probes", p.probes}});
  nlohmann::json j = {{"budget", budget_spec(r.budget)},
          {"met", r.met},
          {"fresh_probes", r.probes},
          {"fresh_seed", r.seed},
          {"contact_agreement", r.agreement},
          {"force_error_median", r.force_median},
          {"force_error_p95", r.force_p95},
          {"angle_error_p99_deg", r.direction_p99_deg},
          {"perceptible_share", r.perceptible},
          {"tuning_probes", r.tuning_probes},
          {"tuning_seed", r.tuning_seed},
          {"tuning_contact_agreement", r.tuning_agreement},
          {"tuning_force_error_median", r.tuning_force_median},
          {"tuning_force_error_p95", r.tuning_force_p95},
          {"tuning_angle_error_p99_deg", r.tuning_direction_p99_deg},
          {"sampling_bakes", r.candidates_tried},
          {"pieces", pieces},
          {"surface", r.surface_triangles == 0 ? nlohmann::json("full mesh")
                                               : nlohmann::json{{"full_triangles", r.full_triangles},
                                                                {"triangles", r.surface_triangles},
                                                                {"deviation_bound", r.surface_bound},
                                                                {"deviation_mean", r.surface_deviation_mean},
                                                                {"deviation_p99", r.surface_deviation_p99},
                                                                {"deviation_max", r.surface_deviation_max},
                                                                {"normal_median_deg", r.surface_normal_median_deg},
                                                                {"normal_p99_deg", r.surface_normal_p99_deg},
                                                                {"normal_map_side", r.surface_map_side}}}};
  // What answers, and why: the raw samplings tried, in the perceptual currency.
  j["answer"] = answerer_name(r.answer == Answerer::none ? Answerer::cells : r.answer);
  nlohmann::json raw = nlohmann::json::array();
  for (const BudgetReport::RawTried& t : r.raw_tried)
    raw.push_back({{"m", t.m}, {"n", t.n}, {"bytes", t.bytes}, {"probes_felt", t.probes_felt},
                   {"slide_ticks_felt", t.ticks_felt < 0 ? nlohmann::json(nullptr) : nlohmann::json(t.ticks_felt)},
                   {"light_touches_felt", t.light_felt < 0 ? nlohmann::json(nullptr) : nlohmann::json(t.light_felt)},
                   {"outcome", t.outcome},
                   // at bake time, one core, random order (null: a file that holds no times)
                   {"box_ns", t.box_ns > 0 ? nlohmann::json(t.box_ns) : nlohmann::json(nullptr)},
                   {"exact_ns", t.exact_ns > 0 ? nlohmann::json(t.exact_ns) : nlohmann::json(nullptr)}});
  j["raw_tried"] = raw;
  // Query times at bake time (absent from older files).
  if (r.answer_ns > 0) j["answer_ns"] = r.answer_ns, j["exact_ns"] = r.exact_ns;
  if (r.cells_ns > 0) j["cells_ns"] = r.cells_ns, j["embree_ns"] = r.embree_ns;
  // Along strokes (recipe/stroke_route.h): what answers a probe's successive queries, and the
  // two times when timed.
  if (r.stroke_answer != Answerer::none) j["stroke_answer"] = answerer_name(r.stroke_answer);
  if (r.stroke_cells_ns > 0) j["stroke_cells_ns"] = r.stroke_cells_ns, j["stroke_embree_ns"] = r.stroke_embree_ns;
  // Wall times are this run's (bake --json) or an older file's; a file written now holds none.
  if (r.seconds > 0) j["seconds"] = r.seconds;
  if (r.surface_triangles > 0 && r.simplify_seconds > 0) j["surface"]["seconds"] = r.simplify_seconds;
  if (r.surface_rejected > 0) j["surface_rejected_triangles"] = r.surface_rejected;
  if (!r.surface_rejected_why.empty()) j["surface_rejected_why"] = r.surface_rejected_why;
  for (const BudgetReport::SurfaceMissed& m : r.surfaces_missed)
    j["surfaces_missed"].push_back({{"triangles", m.triangles}, {"bound", m.bound}, {"why", m.why}});
  if (!r.stage_seconds.empty()) {
    nlohmann::json stages = nlohmann::json::array();  // an array: the step order is the point
    for (const auto& st : r.stage_seconds) stages.push_back({{"stage", st.first}, {"seconds", st.second}});
    j["stage_seconds"] = stages;
  }
  return j;
}

} // namespace hb::cli
