#pragma once
// The JSON of `hapticbox stability --json`, shared by the command and the report's
// summary.json (the same keys and values for the same input and options).
#include "stability/stability_suite.h"
#include <nlohmann/json.hpp>
#include <cmath>

namespace hb {

inline const char* to_string(StabilityRule r) {
  switch (r) {
    case StabilityRule::at_most: return "at_most";
    case StabilityRule::at_least: return "at_least";
    case StabilityRule::within: return "within";
    case StabilityRule::difference_at_most: return "difference_at_most";
    case StabilityRule::info: return "info";
  }
  return "unknown";
}

inline nlohmann::json stability_metric_json(const StabilityMetric& m) {
  const auto num = [](double v) { return std::isfinite(v) ? nlohmann::json(v) : nlohmann::json(nullptr); };
  return {{"test", m.test},       {"scene", m.scene},          {"metric", m.metric},
          {"unit", m.unit},       {"box", num(m.box)},         {"exact", num(m.exact)},
          {"difference", num(m.difference())}, {"rule", to_string(m.rule)}, {"threshold", num(m.threshold)},
          {"tolerance", num(m.tolerance)}, {"pass", m.pass},   {"exact_pass", m.exact_pass},
          {"verdict", m.verdict}};
}

inline nlohmann::json stability_json(const StabilityReport& r) {
  nlohmann::json j;
  j["device"] = r.device;
  j["filter"] = r.filter;
  j["depth_law"] = r.depth_law;
  j["calibration_pass"] = r.calibration_pass;
  j["calibration"] = nlohmann::json::array();
  for (const auto& m : r.calibration) j["calibration"].push_back(stability_metric_json(m));
  j["metrics"] = nlohmann::json::array();
  for (const auto& m : r.metrics) j["metrics"].push_back(stability_metric_json(m));
  j["passed"] = r.passed;
  j["failed"] = r.failed;
  j["failed_law"] = r.failed_law;
  j["seconds"] = r.seconds;
  return j;
}

} // namespace hb
