#pragma once
// The JSON of `hapticbox eval --json`, shared by the command and the report's summary.json so
// that both carry the same keys and values for the same input and seed.
#include "contact/workspace.h"
#include "evaluation/comparison.h"
#include "evaluation/probe_sampling.h"
#include <nlohmann/json.hpp>
#include <cstdint>
#include <string>

namespace hb {

/// The workspace every force of an output was computed at, and the judgement's thresholds.
inline nlohmann::json workspace_json(const Workspace& w, const PerceptualJudge& judge) {
  return {{"fit", w.fit_name()},
          {"diagonal_mm", w.diagonal_m() * 1000.0},
          {"metres_per_unit", w.metres_per_unit},
          {"stiffness_n_per_m", w.stiffness_n_per_m},
          {"max_force_n", w.max_force_n},
          {"perceptual", thresholds_spec(judge.thresholds)},
          {"text", w.describe()}};
}

/// eval's second figure (light touches at any angle, hb::light_touch_probe_options).
inline nlohmann::json light_touch_json(const ComparisonStats& light) {
  const ProbeOptions o = light_touch_probe_options(0);
  return {{"samples", light.samples},
          {"perceptible", light.perceptible},
          {"perceptible_share", light.perceptible_share},
          {"exact_contacts", light.exact_contacts},
          {"cone_degrees", o.cone_degrees},
          {"max_depth_fraction", o.max_depth_fraction}};
}

inline nlohmann::json eval_json(const ComparisonStats& s, const std::string& box, const std::string& mesh,
                                std::uint64_t seed, const std::string& route) {
  nlohmann::json j = {{"box", box},
          {"route", route},
          {"mesh", mesh},
          {"seed", seed},
          {"samples", s.samples},
          {"exact_contacts", s.exact_contacts},
          {"contact_agreement", s.contact_agreement},
          {"false_contacts", s.false_contacts},
          {"missed_contacts", s.missed_contacts},
          {"force_error_median", s.force_error_median},
          {"force_error_p95", s.force_error_p95},
          {"force_error_max", s.force_error_max},
          {"angle_error_median_deg", s.angle_error_median_deg},
          {"angle_error_p99_deg", s.angle_error_p99_deg},
          {"depth_rms_over_diag", s.depth_rms_over_diag}};
  j["perceptible"] = {{"probes", s.perceptible},
                      {"share", s.perceptible_share},
                      {"by_magnitude", s.perceptible_magnitude},
                      {"by_direction", s.perceptible_direction},
                      {"by_contact", s.perceptible_contact},
                      {"thresholds", thresholds_spec(s.thresholds)},
                      {"max_force_n", s.max_force_n}};
  j["force_difference_n"] = {{"median", s.force_difference_median_n},
                             {"p95", s.force_difference_p95_n},
                             {"max", s.force_difference_max_n}};
  j["exact_force_median_n"] = s.exact_force_median_n;
  return j;
}

} // namespace hb
