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
//     refined at the coarsest sampling, is taken and steps 2-3 end there.
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
//     (BudgetRecipe::keep_triangle_ids): that route never reads them.
//  6. The scene is measured on fresh probes (BudgetRecipe::check_seed) and the figures are
//     recorded in BudgetReport (the box file, `info`, `--json`, the report).
#include "contact/perceptible.h"
#include "contact/workspace.h"
#include "errors.h"
#include "stopwatch.h"
#include "evaluation/comparison.h"
#include "evaluation/probe_sampling.h"
#include "evaluation/query_timing.h"
#include "evaluation/stability_suite.h"
#include "evaluation/surface_deviation.h"
#include "exact/exact_query.h"
#include "mesh/decimation.h"
#include "recipe/bake_recipe.h"
#include "recipe/raw_box_trial.h"
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <map>
#include <memory>
#include <optional>
#include <sstream>

namespace hb {
namespace {

// The box the scene grid routes the probe to first (UINT32_MAX: not routed).
std::uint32_t routed_box(const SceneGrid& grid, const Segment& s) {
  std::uint32_t box = UINT32_MAX;
  if (grid.code_at(s.start) != SceneGrid::kOutside) return box;
  grid.walk_surface(s.start, s.end, [&](std::uint16_t code, float) {
    box = *grid.boxes_begin(code);
    return false;
  });
  return box;
}

struct Tuning {
  std::vector<Segment> probes;
  std::vector<Contact> exact;
};

Tuning tune_probes(const TriangleMesh& mesh, const ExactQuery& exact, std::size_t count, std::uint64_t seed,
                   const ForceLaw& law) {
  Tuning t;
  ProbeOptions po;
  po.seed = seed;
  t.probes = sample_probes(mesh, count, po);
  t.exact.resize(t.probes.size());
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, t.probes.size(), 256), [&](const auto& r) {
    for (std::size_t i = r.begin(); i != r.end(); ++i) t.exact[i] = exact.query(t.probes[i], law);
  });
  return t;
}

// What a hand tells apart, and the device's force limit the forces are judged clamped to.
const PerceptualThresholds kFelt{};
constexpr double kFeltMaxForce = WorkspaceOptions::kDefaultMaxForce;

bool felt(const Contact& exact, const Contact& approx) {
  return perceive(exact, approx, kFelt, kFeltMaxForce).perceptible();
}

// A probe fails when a hand would feel the difference or, with the relative criteria, when
// the contact flags differ or the force misses the budget's p95 or dir99.
bool probe_fails(const Contact& exact, const Contact& approx, const ErrorBudget& b) {
  if (felt(exact, approx)) return true;
  if (!b.relative) return false;
  if (exact.contact != approx.contact) return true;
  if (!exact.contact) return false;
  return relative_force_error(exact, approx) > b.force_p95 || angle_error_degrees(exact, approx) > b.direction_p99_deg;
}

// The budget as allowances with a margin for the probes the choice does not see (the fresh
// check, the scene's own routing).
constexpr double kMargin = 0.8;

// The stability suite's T2 metric of the perceptual budget along trajectories.
constexpr const char* kFeltTicks = "share of contact ticks perceptibly different";

// How often a simplified surface that missed the budget is simplified again within a quarter
// of its bound before the full mesh is baked (bake_to_budget).
constexpr int kSimplifyRetries = 2;

// A probe answered from off the surface: a contact exact does not have, or a surface point
// farther than `tolerance` (model units, along the probe) from exact's.
bool off_surface(const Contact& exact, const Contact& approx, float tolerance) {
  if (!approx.contact || tolerance <= 0.f) return false;
  return !exact.contact || std::fabs(exact.depth - approx.depth) > tolerance;
}

} // namespace

double simplification_bound(const ErrorBudget& budget) {
  if (!budget.relative) {
    // A sixteenth of the depth whose force at the workspace's stiffness is the force threshold:
    // k d <= F0 / 16 with the model's diagonal shown at the device's workspace diagonal (2.1e-5
    // of the diagonal, 1.7 um at 80 mm). F0 / 4 missed along T2's slides on the armadillo at
    // 832K triangles (0.36% of contact ticks felt: the slides' contact events, not the
    // deviation's force, decide), F0 / 16 met it (2026-12-06).
    const WorkspaceOptions w;
    return kFelt.floor_n / (16.0 * w.stiffness_n_per_m * w.diagonal_m);
  }
  const double depth = double(ProbeOptions{}.max_depth_fraction);
  return 0.25 * depth * std::max(0.0, std::min(0.1 * (1.0 - budget.agreement), 0.02 * budget.force_p95));
}

namespace {
// The full mesh's exact reference and the tuning probes with its answers: built on first
// use, the same for the raw trial and every attempt (they depend on the mesh and the seed only).
struct Reference {
  std::unique_ptr<ExactQuery> exact;
  std::optional<Tuning> tuning;
};

// The reference, built where missing; the stages named as they finish.
template <class StageDone>
const Tuning& reference_of(const TriangleMesh& mesh, const BudgetRecipe& br, const ForceLaw& law, Reference& ref,
                           StageDone&& stage_done) {
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

BakeResult bake_to_budget_on_one_surface(const TriangleMesh& mesh, const BakeRecipe& recipe, const SourceInfo& source,
                                         Reference& ref);

// The fresh probes' figures (and the budget they were judged by) into the report.
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

BudgetReport::RawTried raw_tried_record(const RawCandidate& c) {
  BudgetReport::RawTried t;
  t.m = c.m, t.n = c.n, t.bytes = c.bytes, t.probes_felt = c.probes_felt, t.ticks_felt = c.ticks_felt;
  t.outcome = c.outcome == "kept" || c.outcome == "serves" ? c.outcome
              : c.outcome == "felt on probes"      ? "felt-probes"
              : c.outcome == "felt on slides"      ? "felt-slides"
              : c.outcome == "over the memory cap" ? "over-cap"
                                                   : "slower";
  return t;
}

// Step R, before any other: the paper's raw haptic box over the whole model (raw_box_trial.h)
// when no hand could tell it from exact on the tuning probes, along T2's slides and on the
// fresh probes, it fits the memory cap and answers faster than exact. Otherwise nothing, and
// `rep` holds what was tried (raw_tried, its stages' seconds).
std::optional<BakeResult> bake_raw(const TriangleMesh& mesh, const BakeRecipe& recipe, const SourceInfo& source,
                                   Reference& ref, BudgetReport& rep) {
  const BudgetRecipe& br = recipe.budget;
  const auto t0 = std::chrono::steady_clock::now();
  const auto stage_done = [&](const std::string& name, double seconds) {
    rep.add_stage(name, seconds);
    if (br.on_stage) br.on_stage(name, seconds);
  };
  const float diagonal = mesh.bounds().diagonal();
  const ForceLaw law = make_workspace(diagonal).law();
  const Tuning& tuning = reference_of(mesh, br, law, ref, stage_done);
  const ExactQuery& exact = *ref.exact;
  auto tstage = std::chrono::steady_clock::now();
  SourceInfo src = source;
  if (src.triangles == 0) src.triangles = mesh.triangle_count();
  if (!(src.diagonal > 0.f)) src.diagonal = diagonal;
  RawTrialOptions o;
  o.allowed_share = kMargin * br.budget.perceptible;
  o.memory_cap_bytes = br.budget.raw_memory_bytes;
  o.thresholds = kFelt;
  o.max_force_n = kFeltMaxForce;
  o.codec_bound = raw_codec_bound(law, kFelt, double(diagonal));
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
  r.answer = "raw";
  r.answer_ns = kept.box_ns;
  r.exact_ns = kept.exact_ns;
  r.seconds = seconds_since(t0);
  BakeResult result;
  result.scene = std::move(*trial.scene);
  result.scene.set_budget_report(std::move(r));
  result.stats = trial.stats;
  for (const HapticBox& box : result.scene.boxes()) result.stats.table_bytes += box.raw_table_bytes();
  return result;
}
} // namespace

BakeResult bake_to_budget(const TriangleMesh& mesh, const BakeRecipe& recipe, const SourceInfo& source) {
  Reference ref;  // the same for the raw trial and every attempt: built once
  if (recipe.options.communicator && recipe.options.communicator->size() > 1)
    throw InvalidInput("bake: a budgeted bake runs in one process (give the sampling options for a bake across ranks)");
  if (mesh.triangle_count() == 0) throw InvalidInput("bake: mesh has no triangles");
  // The raw box first, for a model of its own pieces (a piece file or given ids name
  // pieces the raw box, one box over the whole model, would not keep).
  BudgetReport raw_rep;
  const bool own_pieces = recipe.pieces.kind == PiecesRecipe::Kind::automatic || recipe.pieces.kind == PiecesRecipe::Kind::none;
  if (recipe.budget.budget.raw && own_pieces)
    if (std::optional<BakeResult> raw = bake_raw(mesh, recipe, source, ref, raw_rep)) return std::move(*raw);
  BakeResult result = bake_to_budget_on_one_surface(mesh, recipe, source, ref);
  double seconds = 0.0;          // the attempts' time, counted into the bake's
  std::uint64_t rejected = 0;    // the last surface that missed
  std::string why;               // and what it missed
  // A simplified surface that missed the budget on the fresh probes or along T2's
  // trajectories (a curved surface whose faces sag between the kept vertices more than the
  // quadric bound says) is simplified again within a quarter of the bound, twice at most (a
  // tighter bound is still within the one asked for); then the full mesh (the chess piece:
  // its lathe surface fails T2 at every bound tried, docs/speed.md).
  BakeRecipe tighter = recipe;
  const double diagonal = double(mesh.bounds().diagonal());
  for (int retry = 0;; ++retry) {
    const BudgetReport& tried = result.scene.budget_report();
    if (tried.surface_triangles == 0 || result.surface_miss.empty()) break;
    seconds += tried.seconds;
    rejected = tried.surface_triangles;
    why = result.surface_miss;
    if (retry == kSimplifyRetries || !(diagonal > 0.0) || result.surface_slower_than_exact) {
      tighter.budget.simplify = false;  // the full mesh, as without simplify
      result = bake_to_budget_on_one_surface(mesh, tighter, source, ref);
      break;
    }
    tighter.budget.simplify_deviation = 0.25 * tried.surface_bound / diagonal;
    result = bake_to_budget_on_one_surface(mesh, tighter, source, ref);
  }
  BudgetReport rep = result.scene.budget_report();
  if (rejected > 0) {
    rep.surface_rejected = rejected;
    rep.surface_rejected_why = why;
    rep.seconds += seconds;
  }
  // What the raw trial tried, and its time, first in the record.
  rep.raw_tried = raw_rep.raw_tried;
  for (const auto& [name, secs] : raw_rep.stage_seconds) rep.seconds += secs;
  auto stages = raw_rep.stage_seconds;
  for (const auto& st : rep.stage_seconds) {
    bool merged = false;
    for (auto& mine : stages)
      if (mine.first == st.first) mine.second += st.second, merged = true;
    if (!merged) stages.push_back(st);
  }
  rep.stage_seconds = std::move(stages);
  result.scene.set_budget_report(std::move(rep));
  return result;
}

namespace {
BakeResult bake_to_budget_on_one_surface(const TriangleMesh& mesh, const BakeRecipe& recipe, const SourceInfo& source,
                                         Reference& ref) {
  const BudgetRecipe& br = recipe.budget;
  if (br.samplings.empty()) throw InvalidInput("bake: the budget has no samplings to try");
  for (const Sampling& s : br.samplings)
    if (!(s.cell > 0.f && s.cell <= 1.f) || s.n < 2 || s.n > 256)
      throw InvalidInput("bake: budget sampling cell " + std::to_string(s.cell) + " n " + std::to_string(s.n) +
                         " out of range (cell in (0, 1], n in [2, 256])");
  if (recipe.options.communicator && recipe.options.communicator->size() > 1)
    throw InvalidInput("bake: a budgeted bake runs in one process (give the sampling options for a bake across ranks)");
  if (mesh.triangle_count() == 0) throw InvalidInput("bake: mesh has no triangles");
  const auto t0 = std::chrono::steady_clock::now();
  const ProgressCallback& progress = recipe.options.progress;
  const auto report_progress = [&](double f) {
    if (progress && !progress(std::min(1.0, std::max(0.0, f)))) throw Cancelled("bake cancelled");
  };

  BakeResult result;
  const float diagonal = mesh.bounds().diagonal();
  BudgetReport rep;
  const auto stage_done = [&](const char* name, double seconds) {
    rep.add_stage(name, seconds);
    if (br.on_stage) br.on_stage(name, seconds);
  };
  // Step 0: the surface to bake against (`base`), the full mesh or a simplified one.
  TriangleMesh simplified;
  TriangleMesh shaded;  // `simplified` with corner normals of its own fitted to the full mesh's shading
  bool use_simplified = false;
  // Piece files and given ids name the full mesh's triangles: those bakes keep it.
  const bool own_pieces = recipe.pieces.kind == PiecesRecipe::Kind::automatic || recipe.pieces.kind == PiecesRecipe::Kind::none;
  if (br.simplify && own_pieces && mesh.triangle_count() > br.simplify_above) {
    if (!(br.simplify_deviation >= 0.0 && br.simplify_deviation < 0.1))
      throw InvalidInput("bake: simplify deviation " + std::to_string(br.simplify_deviation) +
                         " out of range [0, 0.1) of the diagonal");
    const auto ts = std::chrono::steady_clock::now();
    DecimationOptions d;
    d.max_deviation = double(diagonal) * (br.simplify_deviation > 0 ? br.simplify_deviation : simplification_bound(br.budget));
    d.shading_check = br.simplify_shading_check;
    const bool fit_check = d.shading_check == DecimationOptions::ShadingCheck::fit;
    d.max_shading_deviation_deg = br.simplify_shading_deg > 0 ? br.simplify_shading_deg
                                  : br.shading_map_side >= 0   ? 180.0  // the map carries the shading
                                                               : (fit_check ? 0.3 : 0.2) * br.budget.direction_p99_deg;
    auto tstage = std::chrono::steady_clock::now();
    DecimationResult dr = decimate(mesh, d);
    stage_done("decimate", seconds_since(tstage));
    if (double(dr.mesh.triangle_count()) < 0.9 * double(mesh.triangle_count())) {
      simplified = std::move(dr.mesh);
      use_simplified = true;
      // The exact answers shade with the full mesh's normals. With a normal map (the
      // default) the refinement shades through it (built once the exact BVH is, below) and
      // the rays' samples keep the simplified mesh's own normals (they serve only the boxes'
      // route and the blend view); without one, the refinement records and the rays' samples
      // take corner normals fitted to them (the decomposition, the lists and the grid keep
      // the shared-vertex surface; same triangles in the same order).
      if (br.shading_map_side < 0) {
        tstage = std::chrono::steady_clock::now();
        shaded = fit_shading(mesh, simplified, 0.002 * double(diagonal));
        stage_done("fit_shading", seconds_since(tstage));
      }
      tstage = std::chrono::steady_clock::now();
      const SurfaceDeviation dev =
          measure_deviation(mesh, br.shading_map_side < 0 ? shaded : simplified, 100000, 0.002 * double(diagonal));
      stage_done("deviation", seconds_since(tstage));
      rep.full_triangles = mesh.triangle_count();
      rep.surface_triangles = simplified.triangle_count();
      rep.surface_bound = d.max_deviation;
      rep.surface_deviation_mean = dev.mean;
      rep.surface_deviation_p99 = dev.p99;
      rep.surface_deviation_max = dev.max;
      // The fitted corner normals' angles; a map's shading is judged by the fresh check.
      rep.surface_normal_median_deg = br.shading_map_side < 0 ? dev.normal_median_deg : 0.0;
      rep.surface_normal_p99_deg = br.shading_map_side < 0 ? dev.normal_p99_deg : 0.0;
    }
    rep.simplify_seconds = seconds_since(ts);
  }
  const TriangleMesh& base = use_simplified ? simplified : mesh;
  // What the rays hit and the refinement's records shade with (a map, when fitted, overrides).
  const TriangleMesh& cast = use_simplified && br.shading_map_side < 0 ? shaded : use_simplified ? simplified : mesh;
  // Forces at the one workspace scale every command judges at (the model fitted to the
  // device's workspace, k 1500 N/m): the perceptual criterion is in newtons a hand feels.
  const ForceLaw law = make_workspace(diagonal).law();
  // The exact answers' BVH of the full mesh first: a decomposition of the full mesh casts its
  // lines against it instead of building its own (one 13M-triangle BVH build fewer).
  const Tuning& tuning = reference_of(mesh, br, law, ref, stage_done);
  const ExactQuery& exact = *ref.exact;
  const auto td = std::chrono::steady_clock::now();
  std::vector<std::uint32_t> ids = resolve_piece_ids(base, recipe.pieces, use_simplified ? nullptr : &exact.scene());
  if (recipe.pieces.kind == PiecesRecipe::Kind::automatic) result.decompose_seconds = seconds_since(td);
  stage_done("decompose", seconds_since(td));
  SourceInfo src = source;
  if (src.triangles == 0) src.triangles = mesh.triangle_count();
  if (!(src.diagonal > 0.f)) src.diagonal = diagonal;
  auto tstage = std::chrono::steady_clock::now();
  std::shared_ptr<const SurfaceTriangles> surface;
  {
    auto records = std::make_shared<SurfaceTriangles>(cast);
    if (use_simplified && br.shading_map_side >= 0) {
      // The full mesh's shading on a lattice over each simplified triangle.
      int side = br.shading_map_side;
      if (side == 0) {
        const double ratio = std::sqrt(double(mesh.triangle_count()) / double(base.triangle_count()));
        side = 1;
        while (side < 16 && double(side) < ratio - 1e-9) side *= 2;
      }
      const auto tm = std::chrono::steady_clock::now();
      records->set_normal_map(side, fit_normal_map(mesh, base, side, 0.002 * double(diagonal), &exact.scene()));
      rep.surface_map_side = std::uint32_t(side);
      stage_done("normal_map", seconds_since(tm));
    }
    surface = std::move(records);
  }
  stage_done("surface", seconds_since(tstage));
  // The piece ids the scene records are per triangle of the full mesh; a simplified
  // surface's pieces are not (the scene then records none).
  const std::vector<std::uint32_t> scene_ids = use_simplified ? std::vector<std::uint32_t>{} : ids;

  const std::size_t samplings = br.samplings.size();
  const auto options_for = [&](std::size_t c) {
    BakeOptions o = recipe.options;
    o.params.n = br.samplings[c].n;
    o.density.cell = br.samplings[c].cell;
    o.refine = true;
    o.surface = surface;
    o.scene_grid = false;
    o.communicator = nullptr;
    o.progress = nullptr;
    return o;
  };
  // Per sampling: the seamed lists of every piece (cheap) and the boxes baked so far.
  std::vector<std::vector<std::vector<std::uint32_t>>> lists(samplings);
  std::vector<std::map<std::size_t, HapticBox>> baked(samplings);
  const auto lists_at = [&](std::size_t c) -> const std::vector<std::vector<std::uint32_t>>& {
    if (lists[c].empty()) {
      const auto tl = std::chrono::steady_clock::now();
      lists[c] = seamed_piece_lists(base, ids, recipe.seams, options_for(c));
      stage_done("lists", seconds_since(tl));
    }
    return lists[c];
  };
  const std::size_t pieces = lists_at(0).size();
  std::uint64_t rays = 0, hits = 0;
  double ray_seconds = 0.0;
  std::uint32_t tried = 0;
  const auto bake_pieces = [&](std::size_t c, const std::vector<std::size_t>& which) {
    std::vector<std::vector<std::uint32_t>> pending;
    std::vector<std::size_t> pending_ids;
    for (std::size_t p : which)
      if (!baked[c].count(p)) {
        pending.push_back(lists_at(c)[p]);
        pending_ids.push_back(p);
      }
    if (pending.empty()) return;
    ++tried;
    BakeStats stats;
    auto tb = std::chrono::steady_clock::now();
    BoxScene part = bake_scene_from_lists(cast, pending, options_for(c), src, &stats);
    stage_done("tables", seconds_since(tb));
    if (recipe.codec.codec != CodecId::none) {
      tb = std::chrono::steady_clock::now();
      part = part.compressed(recipe.codec);
      stage_done("compress", seconds_since(tb));
    }
    rays += stats.rays;
    hits += stats.hits;
    ray_seconds += stats.seconds;
    for (std::size_t k = 0; k < pending_ids.size(); ++k) baked[c].emplace(pending_ids[k], part.boxes()[k]);
  };

  // Scene grids by the sampling each piece's lists come from: a grid depends on the lists
  // only, so a variant and its refined twin, the ownership grid and the final scene share
  // one (each build is seconds at 832K triangles; it was built 6+ times per bake).
  std::map<std::vector<std::size_t>, std::shared_ptr<const SceneGrid>> grids;
  const auto grid_for = [&](const std::vector<std::size_t>& sampling_of_piece) {
    auto& g = grids[sampling_of_piece];
    if (!g) {
      const auto tg = std::chrono::steady_clock::now();
      std::vector<std::vector<std::uint32_t>> chosen_lists;
      for (std::size_t p = 0; p < pieces; ++p) chosen_lists.push_back(lists_at(sampling_of_piece[p])[p]);
      g = std::make_shared<const SceneGrid>(
          build_scene_grid(base, chosen_lists, recipe.options.grid, use_simplified ? nullptr : &exact.scene()));
      stage_done("grids", seconds_since(tg));
    }
    return g;
  };
  // Ownership of the tuning probes: the grid of the first sampling's lists.
  std::vector<std::vector<std::size_t>> owned(pieces);
  tstage = std::chrono::steady_clock::now();
  if (pieces > 1) {
    const SceneGrid& grid = *grid_for(std::vector<std::size_t>(pieces, 0));
    for (std::size_t i = 0; i < tuning.probes.size(); ++i) {
      const std::uint32_t b = grid.empty() ? UINT32_MAX : routed_box(grid, tuning.probes[i]);
      if (b < pieces) owned[b].push_back(i);
    }
  } else {
    for (std::size_t i = 0; i < tuning.probes.size(); ++i) owned[0].push_back(i);
  }
  stage_done("ownership", seconds_since(tstage));

  // Variants, cheapest first: (sampling c, unrefined) then (c, refined).
  const std::size_t variants = 2 * samplings;
  std::vector<std::size_t> all(pieces);
  for (std::size_t p = 0; p < pieces; ++p) all[p] = p;

  // Per piece and variant: its bytes and, on the probes it owns, the counts the budget
  // limits: contact disagreements, and among probes in contact on both sides those whose
  // force error exceeds the median bound, the p95 bound, and whose direction error exceeds
  // the p99 bound.
  struct Counts {
    double bytes = 0;
    double disagree = 0, both = 0, over_median = 0, over_p95 = 0, over_dir = 0;
    double felt = 0;         // perceptibly different (the budget's perceptual criterion)
    double off_surface = 0;  // answered off the surface (not a budget figure: see step 3)
  };
  const float surface_tolerance = float(br.surface_tolerance) * diagonal;
  std::vector<std::vector<Counts>> counts(pieces, std::vector<Counts>(variants));
  std::vector<std::size_t> choice(pieces, 0);
  // The scene of the chosen boxes, checked whole; pieces owning failing probes move up.
  const auto compose = [&]() {
    std::vector<HapticBox> boxes;
    std::vector<std::size_t> sampling_of_piece;
    for (std::size_t p = 0; p < pieces; ++p) {
      const HapticBox& box = baked[choice[p] / 2].at(p);
      boxes.push_back(choice[p] % 2 ? box : box.without_refinement());
      sampling_of_piece.push_back(choice[p] / 2);
    }
    std::shared_ptr<const SceneGrid> grid;
    if (recipe.options.scene_grid && pieces > 1) grid = grid_for(sampling_of_piece);
    return BoxScene(std::move(boxes), src, pieces > 1 ? scene_ids : std::vector<std::uint32_t>{}, grid);
  };
  // A variant's failures in the scene (every piece at that variant), probe by probe, charged
  // to the piece owning the probe: the scene answers a probe with more than the routed box
  // alone (other boxes, fallbacks), so a box asked alone is no proxy for it. Returns the
  // scene's answering route.
  const auto score = [&](std::size_t v, BoxScene* keep = nullptr) {
    choice.assign(pieces, v);
    BoxScene uniform = compose();
    std::vector<Contact> answers(tuning.probes.size());
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, tuning.probes.size(), 256), [&](const auto& r) {
      for (std::size_t i = r.begin(); i != r.end(); ++i) answers[i] = uniform.query(tuning.probes[i], law);
    });
    for (std::size_t p = 0; p < pieces; ++p) {
      const HapticBox& box = uniform.boxes()[p];
      Counts& n = counts[p][v];
      n = Counts{};
      n.bytes = double(box.table_bytes() + box.triangle_id_bytes());
      for (std::size_t i : owned[p]) {
        const Contact& a = answers[i];
        const Contact& e = tuning.exact[i];
        n.off_surface += off_surface(e, a, surface_tolerance) ? 1 : 0;
        n.felt += felt(e, a) ? 1 : 0;
        if (a.contact != e.contact) {
          ++n.disagree;
          continue;
        }
        if (!e.contact) continue;
        ++n.both;
        const double f = relative_force_error(e, a);
        n.over_median += f > br.budget.force_median ? 1 : 0;
        n.over_p95 += f > br.budget.force_p95 ? 1 : 0;
        n.over_dir += angle_error_degrees(e, a) > br.budget.direction_p99_deg ? 1 : 0;
      }
    }
    const SceneRoute route = uniform.answering_route();
    if (keep) *keep = std::move(uniform);
    return route;
  };
  // The budget as allowances over all owned probes, with a margin for the probes the choice
  // does not see (the fresh check, the scene's own routing); failures add up over pieces.
  const auto totals = [&]() {
    Counts t;
    for (std::size_t p = 0; p < pieces; ++p) {
      const Counts& n = counts[p][choice[p]];
      t.disagree += n.disagree, t.both += n.both, t.over_median += n.over_median;
      t.over_p95 += n.over_p95, t.over_dir += n.over_dir, t.off_surface += n.off_surface;
      t.felt += n.felt;
    }
    return t;
  };
  double owned_probes = 0;
  for (const auto& o : owned) owned_probes += double(o.size());
  // Excess over the allowances, each relative to its allowance (0: within the budget).
  const auto excess = [&](const Counts& t) {
    const double allow_disagree = kMargin * (1.0 - br.budget.agreement) * owned_probes;
    const double allow_median = 0.5 * t.both * (br.budget.force_median > 0 ? 1.0 : 0.0);
    const double allow_p95 = kMargin * 0.05 * t.both, allow_dir = kMargin * 0.01 * t.both;
    const auto over = [](double count, double allow) { return count > allow ? (count - allow) / std::max(allow, 1.0) : 0.0; };
    const double felt_excess = over(t.felt, kMargin * br.budget.perceptible * owned_probes);
    if (!br.budget.relative) return felt_excess;
    return felt_excess + over(t.disagree, allow_disagree) + over(t.over_median, kMargin * allow_median) + over(t.over_p95, allow_p95) +
           over(t.over_dir, allow_dir);
  };

  bake_pieces(0, all);
  report_progress(0.7 / double(samplings));
  double scoring_seconds = 0.0;
  const auto timed_score = [&](std::size_t v, BoxScene* keep = nullptr) {
    const auto ts = std::chrono::steady_clock::now();
    const SceneRoute route = score(v, keep);
    scoring_seconds += seconds_since(ts);
    return route;
  };
  // Step 2a. A scene the surface cells answer (several pieces, a grid, one refined box) gives
  // exact's answer to every probe, whatever each piece's sampling and refinement: its boxes'
  // tables answer only the boxes' route (--route boxes, the window's blend view). Its
  // cheapest form is every piece at the coarsest sampling, refined (the surface is shared).
  // Only a scene with no refined piece, which needs no surface at all, could cost less; when
  // the coarsest blend misses the budget or answers off the surface (every piece of the six
  // models of issue 17 under the default budget), the finer samplings are not baked and that
  // exact scene is taken (BudgetRecipe::full_search bakes and searches them all).
  bool exact_scene = false;
  std::size_t scored = 0;   // variants [0, scored) are counted
  BoxScene refined_coarse;  // variant 1's scene: the exact scene when taken (composed once, its surface cells built once)
  if (!br.full_search && pieces > 1 && recipe.options.scene_grid) {
    timed_score(0);
    const Counts blend = totals();
    exact_scene = timed_score(1, &refined_coarse) == SceneRoute::cells && (excess(blend) > 0.0 || blend.off_surface > 0);
    scored = 2;
    if (exact_scene) choice.assign(pieces, 1);
    else refined_coarse = BoxScene{};
  } else if (!br.full_search && pieces == 1) {
    // One piece: no cells, so its refined box is exact only where its triangle ids reach.
    // When the coarsest blend misses and its refined twin meets the budget on every probe's
    // surface, nothing finer is cheaper that could also serve (the raw trial judged the
    // finer blends): that box is taken.
    timed_score(0);
    const Counts blend = totals();
    timed_score(1, &refined_coarse);
    const Counts refined = totals();
    exact_scene = (excess(blend) > 0.0 || blend.off_surface > 0) && excess(refined) <= 0.0 && refined.off_surface == 0;
    scored = 2;
    if (exact_scene) choice.assign(pieces, 1);
    else refined_coarse = BoxScene{};
  }
  // Step 2b. Exact first: the exact scene (the cells, or one refined box) timed against
  // Embree before any finer sampling is baked. On the full mesh, when Embree answers faster,
  // the search ends here and step 5b routes the scene to Embree (its tables would answer
  // nothing); on a simplified surface, when Embree over the full mesh is faster, the surface
  // is dropped (bake_to_budget bakes the full mesh): it would serve neither time nor
  // accuracy.
  std::optional<PairedTiming> early;
  const std::vector<Segment> timed(tuning.probes.begin(),
                                   tuning.probes.begin() + std::min<std::size_t>(tuning.probes.size(), 5000));
  if (br.fastest_exact && !br.full_search && (exact_scene || pieces == 1)) {
    tstage = std::chrono::steady_clock::now();
    if (!exact_scene) {
      choice.assign(pieces, 1);
      refined_coarse = compose();
    }
    if (use_simplified) {
      early = paired_query_ns(refined_coarse, exact, timed, law);
    } else {
      BoxScene by_embree = refined_coarse;
      by_embree.set_route(SceneRoute::embree);
      early = paired_query_ns(refined_coarse, by_embree, timed, law);
    }
    stage_done("exact_first", seconds_since(tstage));
    if (early->a_ns > early->b_ns && use_simplified) {
      std::ostringstream why;
      why.precision(3);
      why << "the simplified surface's exact scene (" << early->a_ns << " ns a query) is slower than Embree over the full mesh ("
          << early->b_ns << " ns)";
      rep.seconds = seconds_since(t0);
      refined_coarse.set_budget_report(rep);
      result.scene = std::move(refined_coarse);
      result.surface_miss = why.str();
      result.surface_slower_than_exact = true;
      return result;
    }
    if (early->a_ns > early->b_ns) {
      exact_scene = true;
      choice.assign(pieces, 1);
    } else if (!exact_scene) {
      refined_coarse = BoxScene{};
      choice.assign(pieces, 0);
      early.reset();
    }
  }
  if (!exact_scene) {
    for (std::size_t c = 1; c < samplings; ++c) {
      bake_pieces(c, all);
      report_progress(0.7 * double(c + 1) / double(samplings));
    }
    for (std::size_t v = scored; v < variants; ++v) {
      timed_score(v);
      report_progress(0.7 + 0.1 * double(v + 1) / double(variants));
    }
  }
  stage_done("variant_scoring", scoring_seconds);  // includes its scenes' grids
  tstage = std::chrono::steady_clock::now();
  if (!exact_scene) {
    // Start from the cheapest uniform variant that is within the allowances (or, when none
    // is, the one with the least excess), then take each piece, largest first, down to the
    // cheapest of its variants that keeps the scene within them.
    const auto piece_bytes = [&](std::size_t p, std::size_t v) { return counts[p][v].bytes; };
    {
      std::size_t start = variants;
      double start_bytes = 0, least = 0;
      std::size_t least_v = variants - 1;
      for (std::size_t v = 0; v < variants; ++v) {
        choice.assign(pieces, v);
        const double e = excess(totals());
        double bytes = 0;
        for (std::size_t p = 0; p < pieces; ++p) bytes += piece_bytes(p, v);
        if (e <= 0.0 && (start == variants || bytes < start_bytes)) start = v, start_bytes = bytes;
        if (v == 0 || e < least) least = e, least_v = v;
      }
      choice.assign(pieces, start < variants ? start : least_v);
    }
    std::vector<std::size_t> by_size(pieces);
    for (std::size_t p = 0; p < pieces; ++p) by_size[p] = p;
    std::sort(by_size.begin(), by_size.end(),
              [&](std::size_t x, std::size_t y) { return piece_bytes(x, choice[x]) > piece_bytes(y, choice[y]); });
    if (excess(totals()) <= 0.0) {
      for (std::size_t p : by_size) {
        // A piece that owns no probe is not measured: it keeps its refinement (its blends
        // could answer other pieces' probes, uncharged).
        if (owned[p].empty()) {
          choice[p] = std::min(choice[p], std::size_t(1));
          continue;
        }
        std::vector<std::size_t> cheaper;
        for (std::size_t v = 0; v < variants; ++v)
          if (piece_bytes(p, v) < piece_bytes(p, choice[p])) cheaper.push_back(v);
        std::sort(cheaper.begin(), cheaper.end(), [&](std::size_t x, std::size_t y) { return piece_bytes(p, x) < piece_bytes(p, y); });
        const std::size_t keep = choice[p];
        for (std::size_t v : cheaper) {
          choice[p] = v;
          if (excess(totals()) <= 0.0) break;
          choice[p] = keep;
        }
      }
    }
    // Still beyond the allowances (no uniform variant met them): the move that removes the
    // most excess per byte added, until within them or no move helps.
    for (std::size_t step = 0; step < pieces * variants; ++step) {
      const Counts t = totals();
      const double now = excess(t);
      if (now <= 0.0) break;
      double best_gain = 0.0;
      std::size_t best_p = pieces, best_v = 0;
      for (std::size_t p = 0; p < pieces; ++p)
        for (std::size_t v = choice[p] + 1; v < variants; ++v) {
          Counts u = t;
          const Counts &from = counts[p][choice[p]], &to = counts[p][v];
          u.disagree += to.disagree - from.disagree, u.both += to.both - from.both;
          u.over_median += to.over_median - from.over_median, u.over_p95 += to.over_p95 - from.over_p95;
          u.over_dir += to.over_dir - from.over_dir;
          u.felt += to.felt - from.felt;
          const double gain = (now - excess(u)) / std::max(1.0, to.bytes - from.bytes);
          if (gain > best_gain) best_gain = gain, best_p = p, best_v = v;
        }
      if (best_p == pieces) break;  // no move helps: the finest variants are the best there is
      choice[best_p] = best_v;
    }
    // An unrefined piece whose blends answer its probes from off the surface is refined at
    // its sampling (its refined variant is the next one).
    for (std::size_t p = 0; p < pieces; ++p)
      if (choice[p] % 2 == 0 && counts[p][choice[p]].off_surface > 0) choice[p] += 1;
  }
  stage_done("selection", seconds_since(tstage));
  report_progress(0.8);

  tstage = std::chrono::steady_clock::now();
  BoxScene scene = exact_scene ? std::move(refined_coarse) : compose();
  std::vector<std::uint32_t> owner(tuning.probes.size(), UINT32_MAX);
  for (std::size_t p = 0; p < pieces; ++p)
    for (std::size_t i : owned[p]) owner[i] = std::uint32_t(p);
  ComparisonStats tuned;
  for (std::size_t round = 0;; ++round) {
    std::vector<ProbeRecord> records(tuning.probes.size());
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, tuning.probes.size(), 256), [&](const auto& r) {
      for (std::size_t i = r.begin(); i != r.end(); ++i)
        records[i] = {tuning.probes[i], tuning.exact[i], scene.query(tuning.probes[i], law)};
    });
    tuned = summarize(records, diagonal);
    // Unrefined pieces whose blends answer a probe off the surface in the whole scene (its
    // routing and neighbours answer probes that other pieces own, which the per-variant
    // counts do not see) are refined: the box that gave the answer (its own blend is it).
    std::vector<bool> ghost(pieces, false);
    bool ghosts = false;
    for (std::size_t i = 0; i < records.size(); ++i) {
      const Contact& a = records[i].approx;
      if (!off_surface(records[i].exact, a, surface_tolerance)) continue;
      for (std::size_t p = 0; p < pieces; ++p) {
        if (choice[p] % 2 != 0) continue;
        Contact c;
        float along = 0.f;
        if (scene.boxes()[p].query_into(records[i].segment, law, c, along) && c.depth == a.depth && c.point == a.point)
          ghost[p] = ghosts = true;
      }
    }
    if ((meets_budget(tuned, br.budget) && !ghosts) || round >= variants) break;
    std::vector<bool> upgrade(pieces, false);
    for (std::size_t i = 0; i < records.size(); ++i)
      if (owner[i] != UINT32_MAX && probe_fails(records[i].exact, records[i].approx, br.budget)) upgrade[owner[i]] = true;
    bool moved = false;
    for (std::size_t p = 0; p < pieces; ++p)
      if (ghost[p] && !upgrade[p]) {
        choice[p] += 1;  // refined at its sampling
        bake_pieces(choice[p] / 2, {p});
        moved = true;
      } else if (upgrade[p] && choice[p] + (choice[p] % 2 ? 2 : 1) < variants) {
        // Up to the next refined variant (a refined piece never drops its refinement).
        choice[p] += choice[p] % 2 ? 2 : 1;
        bake_pieces(choice[p] / 2, {p});
        moved = true;
      }
    if (!moved) break;
    scene = compose();
  }
  stage_done("tuning_check", seconds_since(tstage));  // includes its re-bakes and grids
  report_progress(0.9);
  // The cells route reads the surface and the grid, never the boxes' triangle ids: a scene
  // it answers keeps no ids (the same answers; the fresh check below is this scene's).
  if (!br.keep_triangle_ids && scene.answering_route() == SceneRoute::cells) scene = scene.without_triangle_ids();

  // Step 5b. Never slower than exact: a scene the cells (or one refined box) answer on the
  // full mesh's surface is timed against Embree over that surface (the same contacts), one
  // core, random order, on
  // the tuning probes, and takes the faster route (Embree wins on small and medium meshes,
  // the cells at 800K triangles and up; docs/speed.md). A simplified surface keeps the cells
  // (only they shade through its normal map); it is timed against exact on the full mesh.
  tstage = std::chrono::steady_clock::now();
  const bool exact_route = scene.answering_route() == SceneRoute::cells || scene.has_triangle_ids();
  if (br.fastest_exact && exact_route && scene.surface() && scene.surface()->normal_map_side() == 0) {
    BoxScene by_embree = scene;
    by_embree.set_route(SceneRoute::embree);
    // The scene timed at step 2b is this one: its timing stands.
    const PairedTiming t = early ? *early : paired_query_ns(scene, by_embree, timed, law);
    rep.cells_ns = t.a_ns, rep.embree_ns = t.b_ns;
    rep.exact_ns = t.b_ns;
    rep.answer_ns = std::min(t.a_ns, t.b_ns);
    if (t.a_ns > t.b_ns) scene = std::move(by_embree);
  } else {
    const PairedTiming t = paired_query_ns(scene, exact, timed, law);
    rep.answer_ns = t.a_ns, rep.exact_ns = t.b_ns;
  }
  const SceneRoute answering = scene.answering_route();
  rep.answer = answering == SceneRoute::embree ? "embree"
               : answering == SceneRoute::cells ? "cells"
               : scene.refines()               ? "boxes"
                                               : "raw";
  stage_done("route_timing", seconds_since(tstage));

  tstage = std::chrono::steady_clock::now();
  // Fresh probes: what the scene achieves on probes the choice never saw.
  ProbeOptions fresh;
  fresh.seed = br.check_seed;
  const std::vector<Segment> check = sample_probes(mesh, br.probes, fresh);
  const ComparisonStats checked = compare_queries(scene, exact, check, law, diagonal);
  stage_done("fresh_check", seconds_since(tstage));
  record_fresh_check(rep, br, checked, check.size(), tuning.probes.size());
  rep.tuning_agreement = tuned.contact_agreement;
  rep.tuning_force_median = tuned.force_error_median;
  rep.tuning_force_p95 = tuned.force_error_p95;
  rep.tuning_direction_p99_deg = tuned.angle_error_p99_deg;
  rep.candidates_tried = tried;
  for (std::size_t p = 0; p < pieces; ++p)
    rep.pieces.push_back({br.samplings[choice[p] / 2].cell, br.samplings[choice[p] / 2].n, choice[p] % 2 == 1,
                          std::uint32_t(owned[p].size())});
  if (use_simplified && rep.met) {
    // Along trajectories too: a simplified surface can meet the budget on random probes and
    // still drop or jolt a hand sliding over it (the chess piece's lathe surface: 1-1.3% of
    // exact's contact ticks lost, ghost ticks; docs/speed.md). T2 slides over the model at
    // 1 mm depth, box against exact; a metric only the box fails rejects the surface.
    tstage = std::chrono::steady_clock::now();
    StabilityOptions so;
    so.tests = {"T2"};
    so.generated = false;
    so.exact = &exact;
    std::ostringstream miss;
    miss.precision(3);
    std::size_t failures = 0;  // metrics the box fails and exact passes
    for (const StabilityMetric& m : run_stability_suite(scene, mesh, so).metrics) {
      if (!br.budget.relative) {
        // The perceptual budget: the share of slide ticks a hand would feel, nothing else.
        if (m.metric.rfind(kFeltTicks, 0) != 0 || m.box <= br.budget.perceptible) continue;
      } else if (m.pass || !m.exact_pass) {
        continue;
      }
      if (++failures <= 3)
        miss << (failures > 1 ? "; " : "T2's trajectories: ") << m.metric << " " << m.box << " (exact " << m.exact << ")";
    }
    if (failures > 3) miss << "; " << failures - 3 << " more";
    result.surface_miss = miss.str();
    stage_done("trajectory_check", seconds_since(tstage));
  } else if (use_simplified) {
    result.surface_miss = "fresh probes: " + budget_misses(checked, br.budget);
  }
  rep.seconds = seconds_since(t0);
  scene.set_budget_report(rep);
  result.scene = std::move(scene);
  result.stats.seconds = ray_seconds;
  result.stats.rays = rays;
  result.stats.hits = hits;
  result.stats.rays_per_second = ray_seconds > 0 ? double(rays) / ray_seconds : 0.0;
  result.stats.ranks = {{0, rays, ray_seconds, 0}};
  for (const HapticBox& box : result.scene.boxes())
    result.stats.table_bytes += box.raw_table_bytes() + box.triangle_id_bytes();
  report_progress(1.0);
  return result;
}

} // namespace

} // namespace hb
