// The budgeted bake's probes and probe verdicts (see budget_probes.h).
#include "recipe/budget_probes.h"
#include "evaluation/comparison.h"
#include "evaluation/probe_sampling.h"
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <cmath>

namespace hb {

TuningProbes tune_probes(const TriangleMesh& mesh, const ExactQuery& exact, std::size_t count, std::uint64_t seed,
                         const ForceLaw& law) {
  TuningProbes t;
  ProbeOptions po;
  po.seed = seed;
  t.probes = sample_probes(mesh, count, po);
  t.exact.resize(t.probes.size());
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, t.probes.size(), 256), [&](const auto& r) {
    for (std::size_t i = r.begin(); i != r.end(); ++i) t.exact[i] = exact.query(t.probes[i], law);
  });
  return t;
}

bool felt_difference(const Contact& exact, const Contact& approx) {
  return perceive(exact, approx, kBudgetFelt, kBudgetFeltMaxForce).perceptible();
}

bool probe_fails_budget(const Contact& exact, const Contact& approx, const ErrorBudget& b) {
  if (felt_difference(exact, approx)) return true;
  if (!b.relative) return false;
  if (exact.contact != approx.contact) return true;
  if (!exact.contact) return false;
  return relative_force_error(exact, approx) > b.force_p95 || angle_error_degrees(exact, approx) > b.direction_p99_deg;
}

bool answered_off_surface(const Contact& exact, const Contact& approx, float tolerance) {
  if (!approx.contact || tolerance <= 0.f) return false;
  return !exact.contact || std::fabs(exact.depth - approx.depth) > tolerance;
}

void record_fresh_check(BudgetReport& r, const BudgetRecipe& br, const ComparisonStats& checked, std::size_t probes,
                        std::size_t tuning_probes) {
  r.present = true;
  r.budget = br.budget;
  r.met = meets_budget(checked, br.budget);
  r.probes = probes;
  r.seed = br.check_seed;
  r.agreement = checked.contact_agreement;
  r.force_median = checked.force_error_median;
  r.force_p95 = checked.force_error_p95;
  r.direction_p99_deg = checked.angle_error_p99_deg;
  r.perceptible = checked.perceptible_share;
  r.tuning_probes = tuning_probes;
  r.tuning_seed = br.tuning_seed;
}

} // namespace hb
