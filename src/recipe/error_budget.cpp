#include "recipe/error_budget.h"
#include "evaluation/comparison.h"
#include "spec_parse.h"

namespace hb {
namespace {
std::string fmt(double v) { return spec_format(v); }
} // namespace

bool meets_budget(const ComparisonStats& s, const ErrorBudget& b) { return budget_misses(s, b).empty(); }

std::string budget_misses(const ComparisonStats& s, const ErrorBudget& b) {
  std::string out;
  const auto add = [&](bool miss, const std::string& what) {
    if (!miss) return;
    if (!out.empty()) out += "; ";
    out += what;
  };
  add(b.relative && s.contact_agreement < b.agreement,
      "agreement " + fmt(s.contact_agreement * 100.0) + "% < " + fmt(b.agreement * 100.0) + "%");
  add(b.relative && s.force_error_median > b.force_median,
      "median " + fmt(s.force_error_median * 100.0) + "% > " + fmt(b.force_median * 100.0) + "%");
  add(b.relative && s.force_error_p95 > b.force_p95,
      "p95 " + fmt(s.force_error_p95 * 100.0) + "% > " + fmt(b.force_p95 * 100.0) + "%");
  add(s.perceptible_share > b.perceptible,
      "felt " + fmt(s.perceptible_share * 100.0) + "% > " + fmt(b.perceptible * 100.0) + "%");
  add(b.relative && s.angle_error_p99_deg > b.direction_p99_deg,
      "dir99 " + fmt(s.angle_error_p99_deg) + " deg > " + fmt(b.direction_p99_deg) + " deg");
  return out;
}

} // namespace hb
