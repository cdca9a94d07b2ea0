// The budgeted bake (bake_recipe.h, BudgetRecipe): the cheapest scene found that meets an
// error budget against exact Embree.
//  0. The surface the boxes are baked and refined against: the mesh, or above
//     BudgetRecipe::simplify_above triangles (the default) the mesh simplified within the
//     budget's deviation (hb::decimate, simplification_bound), its deviation from the full
//     surface measured, shaded by a normal map of the full mesh's normals (fit_normal_map,
//     SurfaceTriangles::set_normal_map). Steps 1-4 cut, cast, store ids and build grids on
//     that surface; the probes and the exact answers they are judged by stay on the FULL
//     mesh. A simplified scene that misses the budget on the fresh probes (step 5) is
//     dropped and the whole bake done again on the full mesh (bake_to_budget).
//  1. Pieces as the recipe says (automatic by default), once. Tuning probes (the default
//     distribution, BudgetRecipe::tuning_seed) and their exact answers, once.
//  2. Every piece is baked at every sampling (seams in that sampling's cells), with one
//     shared refinement surface and the recipe's codec; each bake is also tried without its
//     triangle ids. These are a piece's variants, costed in bytes.
//     2a. First the coarsest sampling alone: a scene the surface cells answer gives exact's
//     answers whatever its pieces' samplings, so unless the coarsest blend already meets
//     the budget (where a scene without any surface may cost less), that scene, every piece
//     refined at the coarsest sampling, is taken and steps 2-3 end there. One piece (no
//     cells) takes its refined coarse box when that meets the budget and the blend does not.
//     2b. Exact first: that exact scene is timed against Embree before anything finer is
//     baked. On the full mesh, Embree faster ends the search (step 5b routes to Embree); on
//     a simplified surface, Embree over the full mesh faster drops the surface at once (no
//     tighter bound is tried: bake_to_budget bakes the full mesh).
//  3. A piece owns the tuning probes the scene grid routes to it (the first box named by the
//     first surface cell the probe crosses, the handle outside). On its probes each variant
//     is asked alone and its failures counted (contact disagreements; force errors over the
//     median and p95 bounds, direction errors over the p99 bound). The budget becomes
//     allowances of such failures over all probes (80% of them, a margin for unseen probes).
//     The failures are counted in the scene with every piece at one variant, probe by probe,
//     and charged to the owning piece. The choice starts at the cheapest uniform variant
//     within the allowances and takes each piece, largest first, down to its cheapest
//     variant that keeps the sums within them: the bytes go where the error is (triangle ids
//     only where the blend misses, fine sampling only where coarse fails). When no uniform
//     variant is within them, moves that remove the most excess per byte are made instead.
//     A piece left unrefined must also answer every probe it owns on the surface
//     (BudgetRecipe::surface_tolerance): a blend off it is a ghost surface on a trajectory,
//     however rare among random probes; such a piece is refined at its sampling.
//  4. The chosen boxes form the scene (piece ids, a scene grid from the chosen lists). The
//     whole scene is checked on the tuning probes; while it misses the budget, each piece
//     owning a failing probe moves up one variant (at most as many rounds as variants), and
//     an unrefined piece owning a probe answered off the surface is refined.
//  5. A scene the surface cells answer (SceneRoute::cells) drops its boxes' triangle ids
//     (BudgetRecipe::keep_triangle_ids): that route never reads them. 5b: the cells and
//     Embree over the surface are timed (step 2b's tree and, for the scene it timed, its
//     timing reused); a scene routed to Embree keeps only its boxes' frames, no tables nor
//     ids (BoxScene::without_tables): Embree reads the surface alone.
//  6. The scene is measured on fresh probes (BudgetRecipe::check_seed) and the figures are
//     recorded in BudgetReport (the box file, `info`, `--json`, the report).
//  7. A scene the cells answer is timed along strokes against Embree over the full mesh, which
//     answers its strokes where faster (stroke_route.h; after the checks, which judge the
//     cells: the strokes' answers are then exact's own).
//  The steps 0-6 are BudgetSearch (budget_search.h), one method a step; the surface of step 0
//  is budget_surface.h's, the probes and their verdicts budget_probes.h's.
#include "errors.h"
#include "evaluation/comparison.h"
#include "evaluation/probe_sampling.h"
#include "recipe/bake_recipe.h"
#include "recipe/budget_probes.h"
#include "recipe/budget_search.h"
#include "recipe/raw_box_trial.h"
#include "recipe/stroke_route.h"
#include "stopwatch.h"
#include <algorithm>
#include <chrono>
#include <cmath>
#include <optional>
#include <sstream>

namespace hb {
namespace {

// How often a simplified surface that missed the budget is simplified again within a quarter
// of its bound before the full mesh is baked (bake_to_budget).
constexpr int kSimplifyRetries = 2;
} // namespace

double simplification_bound(const ErrorBudget& budget) {
  if (!budget.relative) {
    // A sixteenth of the depth whose force at the workspace's stiffness is the force threshold:
    // k d <= F0 / 16 with the model's diagonal shown at the device's workspace diagonal (2.1e-5
    // of the diagonal, 1.7 um at 80 mm). F0 / 4 missed along T2's slides on the armadillo at
    // 832K triangles (0.36% of contact ticks felt: the slides' contact events, not the
    // deviation's force, decide); F0 / 16 meets it.
    const WorkspaceOptions w;
    return kBudgetFelt.floor_n / (16.0 * w.stiffness_n_per_m * w.diagonal_m);
  }
  const double depth = double(ProbeOptions{}.max_depth_fraction);
  return 0.25 * depth * std::max(0.0, std::min(0.1 * (1.0 - budget.agreement), 0.02 * budget.force_p95));
}

namespace {
BudgetReport::RawTried raw_tried_record(const RawCandidate& c) {
  BudgetReport::RawTried t;
  t.m = c.m, t.n = c.n, t.bytes = c.bytes, t.probes_felt = c.probes_felt, t.ticks_felt = c.ticks_felt;
  t.light_felt = c.light_felt;
  t.box_ns = c.box_ns, t.exact_ns = c.exact_ns;
  t.box_stroke_ns = c.box_stroke_ns, t.exact_stroke_ns = c.exact_stroke_ns;
  t.outcome = c.outcome == "kept" || c.outcome == "serves" ? c.outcome
              : c.outcome == "slower than exact on strokes" ? "slower-strokes"
              : c.outcome == "felt on probes"      ? "felt-probes"
              : c.outcome == "felt on slides"      ? "felt-slides"
              : c.outcome == "felt on light touches" ? "felt-light"
              : c.outcome == "over the memory cap" ? "over-cap"
                                                   : "slower";
  return t;
}

// Step R, before any other: the paper's raw haptic box over the whole model (raw_box_trial.h)
// when no hand could tell it from exact on the tuning probes, along T2's slides and on the
// fresh probes, it fits the memory cap and answers faster than exact. Otherwise nothing, and
// `rep` holds what was tried (raw_tried, its stages' seconds).
std::optional<BakeResult> bake_raw(const TriangleMesh& mesh, const BakeRecipe& recipe, const SourceInfo& source,
                                   BudgetReference& ref, BudgetReport& rep) {
  const BudgetRecipe& br = recipe.budget;
  const auto t0 = std::chrono::steady_clock::now();
  const auto stage_done = [&](const std::string& name, double seconds) {
    rep.add_stage(name, seconds);
    if (br.on_stage) br.on_stage(name, seconds);
  };
  const float diagonal = mesh.bounds().diagonal();
  const ForceLaw law = make_workspace(diagonal).law();
  const TuningProbes& tuning = reference_of(mesh, br, law, ref, stage_done);
  const ExactQuery& exact = *ref.exact;
  auto tstage = std::chrono::steady_clock::now();
  SourceInfo src = source;
  if (src.triangles == 0) src.triangles = mesh.triangle_count();
  if (!(src.diagonal > 0.f)) src.diagonal = diagonal;
  RawTrialOptions o;
  o.allowed_share = kBudgetMargin * br.budget.perceptible;
  o.memory_cap_bytes = br.budget.raw_memory_bytes;
  o.thresholds = kBudgetFelt;
  o.max_force_n = kBudgetFeltMaxForce;
  o.codec_bound = raw_codec_bound(law, kBudgetFelt, double(diagonal));
  o.on_stage = stage_done;
  RawTrial trial = try_raw_boxes(mesh, exact, tuning.probes, tuning.exact, law, recipe.options, src, o);
  for (const RawCandidate& c : trial.tried) rep.raw_tried.push_back(raw_tried_record(c));
  if (!trial.scene) return std::nullopt;
  // The fresh probes, as every budgeted bake's.
  tstage = std::chrono::steady_clock::now();
  ProbeOptions fresh;
  fresh.seed = br.check_seed;
  const std::vector<Segment> check = sample_probes(mesh, br.probes, fresh);
  const ComparisonStats checked = compare_queries(*trial.scene, exact, check, law, diagonal);
  stage_done("fresh_check", seconds_since(tstage));
  if (!meets_budget(checked, br.budget)) {
    for (BudgetReport::RawTried& t : rep.raw_tried)
      if (t.outcome == "kept") t.outcome = "felt-probes", t.probes_felt = checked.perceptible_share;  // the fresh ones
    return std::nullopt;
  }
  BudgetReport r = rep;
  record_fresh_check(r, br, checked, check.size(), tuning.probes.size());
  r.tuning_agreement = r.agreement;  // the tuning probes judged only what a hand feels
  r.candidates_tried = std::uint32_t(trial.tried.size());
  const RawCandidate& kept =
      *std::find_if(trial.tried.begin(), trial.tried.end(), [](const RawCandidate& c) { return c.outcome == "kept"; });
  r.pieces.push_back({0.f, kept.n, false, std::uint32_t(tuning.probes.size())});
  r.answer = Answerer::raw_box;
  r.answer_ns = kept.box_ns;
  r.exact_ns = kept.exact_ns;
  r.seconds = seconds_since(t0);
  BakeResult result;
  result.scene = with_budget(*trial.scene, std::move(r));
  result.stats = trial.stats;
  for (const HapticBox& box : result.scene.parts().boxes) result.stats.table_bytes += box.raw_table_bytes();
  return result;
}
} // namespace

BakeResult bake_to_budget(const TriangleMesh& mesh, const BakeRecipe& recipe, const SourceInfo& source) {
  BudgetReference ref;  // the same for the raw trial and every attempt: built once
  if (recipe.budget.simplify && mesh.triangle_count() > recipe.budget.simplify_once_above)
    ref.finest_fraction = std::pow(0.25, kSimplifyRetries);
  if (recipe.options.communicator && recipe.options.communicator->size() > 1)
    throw InvalidInput("bake: a budgeted bake runs in one process (give the sampling options for a bake across ranks)");
  if (mesh.triangle_count() == 0) throw InvalidInput("bake: mesh has no triangles");
  // The raw box first, for a model of its own pieces (a piece file or given ids name
  // pieces the raw box, one box over the whole model, would not keep).
  BudgetReport raw_rep;
  const bool own_pieces = recipe.pieces.kind == PiecesRecipe::Kind::automatic || recipe.pieces.kind == PiecesRecipe::Kind::none;
  if (recipe.budget.budget.raw && own_pieces)
    if (std::optional<BakeResult> raw = bake_raw(mesh, recipe, source, ref, raw_rep)) return std::move(*raw);
  BakeResult result = BudgetSearch(mesh, recipe, source, ref).run();
  double seconds = 0.0;          // the attempts' time, counted into the bake's
  BudgetReport stages = raw_rep;  // and their stages (stage_seconds), the raw trial's first
  std::uint64_t rejected = 0;    // the last surface that missed
  std::string why;               // and what it missed
  std::vector<BudgetReport::SurfaceMissed> missed;  // every one dropped
  // A simplified surface that missed the budget on the fresh probes or along T2's
  // trajectories (a curved surface whose faces sag between the kept vertices more than the
  // quadric bound says) is simplified again within a quarter of the bound, twice at most (a
  // tighter bound is still within the one asked for); then the full mesh (the chess piece:
  // its lathe surface fails T2 at every bound tried, docs/speed.md).
  BakeRecipe tighter = recipe;
  const double diagonal = double(mesh.bounds().diagonal());
  for (int retry = 0;; ++retry) {
    const BudgetReport& tried = result.scene.parts().budget;
    if (tried.surface_triangles == 0 || result.surface_miss.empty()) break;
    seconds += tried.seconds;
    for (const auto& [name, secs] : tried.stage_seconds) stages.add_stage(name, secs);
    rejected = tried.surface_triangles;
    why = result.surface_miss;
    missed.push_back({tried.surface_triangles, tried.surface_bound, why});
    const bool last = retry == kSimplifyRetries || !(diagonal > 0.0) || result.surface_slower_than_exact;
    if (recipe.budget.on_note) {
      std::ostringstream note;
      note.precision(3);
      note << "the surface simplified to " << tried.surface_triangles << " triangles (within " << tried.surface_bound
           << ") missed the budget (" << why << "): "
           << (last ? "baking the full mesh" : "simplifying again within a quarter of the bound");
      recipe.budget.on_note(note.str());
    }
    if (last) {
      tighter.budget.simplify = false;  // the full mesh, as without simplify
      result = BudgetSearch(mesh, tighter, source, ref).run();
      break;
    }
    tighter.budget.simplify_deviation = 0.25 * tried.surface_bound / diagonal;
    result = BudgetSearch(mesh, tighter, source, ref).run();
  }
  BudgetReport rep = result.scene.parts().budget;
  if (rejected > 0) {
    rep.surface_rejected = rejected;
    rep.surface_rejected_why = why;
    rep.surfaces_missed = std::move(missed);
    rep.seconds += seconds;
  }
  // Step 7: along strokes, the cells or Embree over the full mesh (stroke_route.h).
  if (recipe.budget.fastest_exact) {
    const auto tstage = std::chrono::steady_clock::now();
    choose_stroke_route(result.scene, mesh, make_workspace(float(diagonal)).law(), recipe.budget.check_seed, rep);
    const double s = seconds_since(tstage);
    rep.add_stage("stroke_timing", s);
    rep.seconds += s;
    if (recipe.budget.on_stage) recipe.budget.on_stage("stroke_timing", s);
  }
  // What the raw trial tried, and its time, first in the record.
  rep.raw_tried = raw_rep.raw_tried;
  for (const auto& [name, secs] : raw_rep.stage_seconds) rep.seconds += secs;
  for (const auto& [name, secs] : rep.stage_seconds) stages.add_stage(name, secs);
  rep.stage_seconds = std::move(stages.stage_seconds);
  result.scene = with_budget(result.scene, std::move(rep));
  return result;
}

} // namespace hb
