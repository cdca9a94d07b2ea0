#pragma once
// Whether a scene's accuracy meets an error budget (hb::ErrorBudget, perception/budget_report.h).
#include "perception/budget_report.h"
#include <string>

namespace hb {

struct ComparisonStats;

/// Whether `stats` meets `budget` (every figure within it).
bool meets_budget(const ComparisonStats& stats, const ErrorBudget& budget);
/// The figures of `stats` that miss `budget`, as "p95 12.3% > 7%" phrases joined by "; "
/// (empty when it meets it).
std::string budget_misses(const ComparisonStats& stats, const ErrorBudget& budget);

} // namespace hb
