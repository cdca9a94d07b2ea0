#pragma once
// What a budgeted bake judges its candidates by: the full mesh's exact reference, the tuning
// probes with exact's answers (built once per bake, the same for the raw trial and every
// surface attempt), and the probe-level verdicts (felt, failing the budget, off the surface)
// the search counts. Internal to recipe/ (budgeted_bake.cpp, budget_search.cpp).
#include "contact/contact.h"
#include "perception/perceptible.h"
#include "contact/workspace.h"
#include "exact/exact_query.h"
#include "geometry/segment.h"
#include "recipe/bake_recipe.h"
#include "stopwatch.h"
#include <chrono>
#include <cstdint>
#include <memory>
#include <optional>
#include <vector>

namespace hb {

struct ComparisonStats;

/// Probes sampled on the full mesh (the default distribution) and exact's answers to them.
struct TuningProbes {
  std::vector<Segment> probes;
  std::vector<Contact> exact;
};

/// `count` probes of seed `seed` on `mesh` and `exact`'s answers under `law` (in parallel).
TuningProbes tune_probes(const TriangleMesh& mesh, const ExactQuery& exact, std::size_t count, std::uint64_t seed,
                         const ForceLaw& law);

/// The full mesh's exact reference and the tuning probes with its answers: built on first
/// use, the same for the raw trial and every attempt (they depend on the mesh and the seed only).
struct BudgetReference {
  std::unique_ptr<ExactQuery> exact;
  std::optional<TuningProbes> tuning;
  /// The full mesh simplified within the tightest bound an attempt may ask (bake_to_budget
  /// sets `finest_fraction`, the last retry's bound over the first's): the first simplified
  /// attempt makes it, and every attempt's surface is then simplified from it (within its
  /// bound less this one's), so a huge mesh is decimated once however often the bound is
  /// tightened (budget_surface.cpp).
  struct Simplified {
    TriangleMesh mesh;
    double bound = 0.0;  ///< model units
  };
  std::optional<Simplified> finest;
  double finest_fraction = 0.0;  ///< 0: every attempt decimates the full mesh
};

/// The reference's tuning probes, building what is missing; `stage_done(name, seconds)` names
/// the stages as they finish ("exact_build", "tuning_probes").
template <class StageDone>
const TuningProbes& reference_of(const TriangleMesh& mesh, const BudgetRecipe& br, const ForceLaw& law,
                                 BudgetReference& ref, StageDone&& stage_done) {
  auto t = std::chrono::steady_clock::now();
  if (!ref.exact) {
    ref.exact = std::make_unique<ExactQuery>(mesh, BvhBuild::quick);  // queried ~50,000 times: the build dominates
    stage_done("exact_build", seconds_since(t));
  }
  if (!ref.tuning) {
    t = std::chrono::steady_clock::now();
    ref.tuning = tune_probes(mesh, *ref.exact, br.probes, br.tuning_seed, law);
    stage_done("tuning_probes", seconds_since(t));
  }
  return *ref.tuning;
}

/// What a hand tells apart, and the device's force limit the forces are judged clamped to.
inline const PerceptualThresholds kBudgetFelt{};
constexpr double kBudgetFeltMaxForce = WorkspaceOptions::kDefaultMaxForce;

/// The budget as allowances with a margin for the probes the choice does not see (the fresh
/// check, the scene's own routing).
constexpr double kBudgetMargin = 0.8;

/// Whether a hand would feel the difference between exact's and the approximate answer.
bool felt_difference(const Contact& exact, const Contact& approx);

/// A probe fails when a hand would feel the difference or, with the relative criteria, when
/// the contact flags differ or the force misses the budget's p95 or dir99.
bool probe_fails_budget(const Contact& exact, const Contact& approx, const ErrorBudget& b);

/// A probe answered from off the surface: a contact exact does not have, or a surface point
/// farther than `tolerance` (model units, along the probe) from exact's.
bool answered_off_surface(const Contact& exact, const Contact& approx, float tolerance);

/// The fresh probes' figures (and the budget they were judged by) into the report.
void record_fresh_check(BudgetReport& r, const BudgetRecipe& br, const ComparisonStats& checked, std::size_t probes,
                        std::size_t tuning_probes);

} // namespace hb
