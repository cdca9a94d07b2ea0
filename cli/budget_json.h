#pragma once
// A budgeted bake's report as JSON: what `bake --json`, `info --json` and `report` print of it.
#include "perception/budget_report.h"
#include <nlohmann/json.hpp>

namespace hb::cli {

/// A budgeted bake's report as JSON (null when the scene was not baked to a budget):
/// the budget, met, the fresh-probe figures and seed, the tuning figures, the per-piece choices.
nlohmann::json budget_json(const BudgetReport& report);

} // namespace hb::cli
