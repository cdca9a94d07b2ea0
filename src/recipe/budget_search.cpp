// The budgeted bake on one surface (see budget_search.h; the steps are budgeted_bake.cpp's).
//  1. prepare_surface: the surface (budget_surface.h), the reference and tuning probes, the
//     pieces, the refinement records; assign_ownership: each tuning probe to the piece the
//     scene grid routes it to.
//  2. bake_pieces: every piece at a sampling, once (the boxes are kept per sampling; the
//     unrefined variant is the refined box without its refinement). grid_for: one grid per
//     choice of samplings. compose: the scene of the current choice.
//  3. score_variants: per variant, the failures in the uniform scene charged to the owning
//     pieces; a scene the surface cells answer at the coarsest sampling ends the search
//     (step 2a; one piece: its refined coarse box when it meets the budget); exact_first
//     times that exact scene against Embree before anything finer is baked (step 2b: Embree
//     faster ends the search, or drops a simplified surface). select_variants (budget_choice.cpp):
//     the cheapest uniform variant within the allowances, then
//     each piece down, or the best moves per byte; unrefined pieces answering off the
//     surface are refined.
//  4. check_whole_scene: rounds of the whole scene on the tuning probes; failing pieces move
//     up, ghost pieces are refined.
//  5. choose_route: no triangle ids for the cells route; the cells or Embree by their time.
//  6. check_fresh, check_trajectories: the fresh probes and, on a simplified surface, T2.
#include "recipe/budget_search.h"
#include "recipe/route_rule.h"
#include "errors.h"
#include "evaluation/probe_sampling.h"
#include "evaluation/query_timing.h"
#include "stability/stability_suite.h"
#include "stopwatch.h"
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <algorithm>
#include <cmath>
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

// The stability suite's T2 metric of the perceptual budget along trajectories.
constexpr const char* kFeltTicks = "share of contact ticks perceptibly different";

} // namespace

BudgetSearch::BudgetSearch(const TriangleMesh& mesh, const BakeRecipe& recipe, const SourceInfo& source,
                           BudgetReference& ref)
    : mesh_(mesh), recipe_(recipe), br_(recipe.budget), source_(source), ref_(ref) {
  if (br_.samplings.empty()) throw InvalidInput("bake: the budget has no samplings to try");
  for (const Sampling& s : br_.samplings)
    if (!(s.cell > 0.f && s.cell <= 1.f) || s.n < 2 || s.n > 256)
      throw InvalidInput("bake: budget sampling cell " + std::to_string(s.cell) + " n " + std::to_string(s.n) +
                         " out of range (cell in (0, 1], n in [2, 256])");
  if (recipe.options.communicator && recipe.options.communicator->size() > 1)
    throw InvalidInput("bake: a budgeted bake runs in one process (give the sampling options for a bake across ranks)");
  if (mesh.triangle_count() == 0) throw InvalidInput("bake: mesh has no triangles");
}

void BudgetSearch::stage_done(const char* name, double seconds) {
  rep_.add_stage(name, seconds);
  if (br_.on_stage) br_.on_stage(name, seconds);
}

BudgetStageDone BudgetSearch::stage_callback() {
  return [this](const char* name, double seconds) { stage_done(name, seconds); };
}

void BudgetSearch::report_progress(double f) const {
  const ProgressCallback& progress = recipe_.options.progress;
  if (progress && !progress(std::min(1.0, std::max(0.0, f)))) throw Cancelled("bake cancelled");
}

BakeResult BudgetSearch::run() {
  t0_ = std::chrono::steady_clock::now();
  diagonal_ = mesh_.bounds().diagonal();
  prepare_surface();
  pieces_ = lists_at(0).size();
  assign_ownership();
  // Variants, cheapest first: (sampling c, unrefined) then (c, refined).
  variants_ = 2 * samplings_;
  all_.resize(pieces_);
  for (std::size_t p = 0; p < pieces_; ++p) all_[p] = p;
  surface_tolerance_ = float(br_.surface_tolerance) * diagonal_;
  counts_.assign(pieces_, std::vector<Counts>(variants_));
  choice_.assign(pieces_, 0);
  for (const auto& o : owned_) owned_probes_ += double(o.size());

  bake_pieces(0, all_);
  report_progress(0.7 / double(samplings_));
  BoxScene refined_coarse;  // variant 1's scene: the exact scene when taken (composed once, its surface cells built once)
  const bool exact_scene = score_variants(refined_coarse);
  if (slower_than_exact_) return drop_surface(std::move(refined_coarse));
  auto tstage = std::chrono::steady_clock::now();
  if (!exact_scene) select_variants();
  stage_done("selection", seconds_since(tstage));
  report_progress(0.8);

  tstage = std::chrono::steady_clock::now();
  BoxScene scene = exact_scene ? std::move(refined_coarse) : compose();
  const std::vector<std::size_t> timed_choice = choice_;
  const ComparisonStats tuned = check_whole_scene(scene);
  if (choice_ != timed_choice) early_.reset();  // not the scene step 2b timed: step 5b times it again
  stage_done("tuning_check", seconds_since(tstage));  // includes its re-bakes and grids
  report_progress(0.9);
  // The cells route reads the surface and the grid, never the boxes' triangle ids: a scene
  // it answers keeps no ids (the same answers; the fresh check below is this scene's).
  if (!br_.keep_triangle_ids && scene.route() == SceneRoute::cells) scene = BoxScene(without_triangle_ids(scene));
  choose_route(scene);
  check_fresh(scene, tuned);
  return finish(std::move(scene));
}

// Step 0 and the first of step 1: the surface to bake against, the reference, the pieces and
// the refinement records.
void BudgetSearch::prepare_surface() {
  surface_mesh_ = simplify_for_budget(mesh_, recipe_, rep_, stage_callback(), ref_);
  base_ = &surface_mesh_.base(mesh_);
  cast_ = &surface_mesh_.cast(mesh_, br_);
  // Forces at the one workspace scale every command judges at (the model fitted to the
  // device's workspace, k 1500 N/m): the perceptual criterion is in newtons a hand feels.
  law_ = make_workspace(diagonal_).law();
  // The exact answers' BVH of the full mesh first: a decomposition of the full mesh casts its
  // lines against it instead of building its own (one 13M-triangle BVH build fewer).
  tuning_ = &reference_of(mesh_, br_, law_, ref_, [this](const char* name, double s) { stage_done(name, s); });
  timed_.assign(tuning_->probes.begin(), tuning_->probes.begin() + std::min<std::size_t>(tuning_->probes.size(), 5000));
  exact_ = ref_.exact.get();
  decompose();
  src_ = source_;
  if (src_.triangles == 0) src_.triangles = mesh_.triangle_count();
  if (!(src_.diagonal > 0.f)) src_.diagonal = diagonal_;
  const auto tstage = std::chrono::steady_clock::now();
  surface_ = refinement_surface(mesh_, surface_mesh_, br_, exact_->scene(), rep_, stage_callback());
  stage_done("surface", seconds_since(tstage));
  // The piece ids the scene records are per triangle of the full mesh; a simplified
  // surface's pieces are not (the scene then records none).
  if (!surface_mesh_.use_simplified) scene_ids_ = ids_;
  samplings_ = br_.samplings.size();
  lists_.resize(samplings_);
  baked_.resize(samplings_);
}

void BudgetSearch::decompose() {
  const auto td = std::chrono::steady_clock::now();
  // Ids a caller resolved (the window's decomposition filter) are the full mesh's: a
  // simplified surface is cut anew.
  PiecesRecipe pieces = recipe_.pieces;
  if (surface_mesh_.use_simplified && pieces.resolved.size() != base_->triangle_count()) pieces.resolved.clear();
  ids_ = resolve_piece_ids(*base_, pieces, surface_mesh_.use_simplified ? nullptr : &exact_->scene());
  if (recipe_.pieces.kind == PiecesRecipe::Kind::automatic) result_.decompose_seconds = seconds_since(td);
  stage_done("decompose", seconds_since(td));
}

// Ownership of the tuning probes: the grid of the first sampling's lists.
void BudgetSearch::assign_ownership() {
  owned_.assign(pieces_, {});
  const auto tstage = std::chrono::steady_clock::now();
  if (pieces_ > 1) {
    const SceneGrid& grid = *grid_for(std::vector<std::size_t>(pieces_, 0));
    for (std::size_t i = 0; i < tuning_->probes.size(); ++i) {
      const std::uint32_t b = grid.empty() ? UINT32_MAX : routed_box(grid, tuning_->probes[i]);
      if (b < pieces_) owned_[b].push_back(i);
    }
  } else {
    for (std::size_t i = 0; i < tuning_->probes.size(); ++i) owned_[0].push_back(i);
  }
  stage_done("ownership", seconds_since(tstage));
}

BakeOptions BudgetSearch::options_for(std::size_t c) const {
  BakeOptions o = search_bake_options(recipe_.options, surface_);
  o.params.n = br_.samplings[c].n;
  o.density.cell = br_.samplings[c].cell;
  return o;
}

const BudgetSearch::Lists& BudgetSearch::lists_at(std::size_t c) {
  if (lists_[c].empty()) {
    const auto tl = std::chrono::steady_clock::now();
    lists_[c] = seamed_piece_lists(*base_, ids_, recipe_.seams, options_for(c));
    stage_done("lists", seconds_since(tl));
  }
  return lists_[c];
}

// The pieces `which` at sampling c that are not baked yet, in one bake (and the codec).
void BudgetSearch::bake_pieces(std::size_t c, const std::vector<std::size_t>& which) {
  Lists pending;
  std::vector<std::size_t> pending_ids;
  for (std::size_t p : which)
    if (!baked_[c].count(p)) {
      pending.push_back(lists_at(c)[p]);
      pending_ids.push_back(p);
    }
  if (pending.empty()) return;
  ++tried_;
  BakeStats stats;
  auto tb = std::chrono::steady_clock::now();
  BoxScene part = bake_scene_from_lists(*cast_, pending, options_for(c), src_, &stats);
  stage_done("tables", seconds_since(tb));
  if (recipe_.codec.codec != CodecId::none) {
    tb = std::chrono::steady_clock::now();
    part = BoxScene(compressed(part, recipe_.codec));
    stage_done("compress", seconds_since(tb));
  }
  rays_ += stats.rays;
  hits_ += stats.hits;
  ray_seconds_ += stats.seconds;
  for (std::size_t k = 0; k < pending_ids.size(); ++k) baked_[c].emplace(pending_ids[k], part.parts().boxes[k]);
}

// Scene grids by the sampling each piece's lists come from: a grid depends on the lists
// only, so a variant and its refined twin, the ownership grid and the final scene share
// one (each build is seconds at 832K triangles).
std::shared_ptr<const SceneGrid> BudgetSearch::grid_for(const std::vector<std::size_t>& sampling_of_piece) {
  auto& g = grids_[sampling_of_piece];
  if (!g) {
    const auto tg = std::chrono::steady_clock::now();
    Lists chosen_lists;
    for (std::size_t p = 0; p < pieces_; ++p) chosen_lists.push_back(lists_at(sampling_of_piece[p])[p]);
    g = std::make_shared<const SceneGrid>(build_scene_grid(*base_, chosen_lists, recipe_.options.grid,
                                                           surface_mesh_.use_simplified ? nullptr : &exact_->scene()));
    stage_done("grids", seconds_since(tg));
  }
  return g;
}

// The scene of the chosen boxes.
BoxScene BudgetSearch::compose() {
  std::vector<HapticBox> boxes;
  std::vector<std::size_t> sampling_of_piece;
  for (std::size_t p = 0; p < pieces_; ++p) {
    const HapticBox& box = baked_[choice_[p] / 2].at(p);
    boxes.push_back(choice_[p] % 2 ? box : box.without_refinement());
    sampling_of_piece.push_back(choice_[p] / 2);
  }
  std::shared_ptr<const SceneGrid> grid;
  if (recipe_.options.scene_grid && pieces_ > 1) grid = grid_for(sampling_of_piece);
  return BoxScene(SceneParts{std::move(boxes), src_, pieces_ > 1 ? scene_ids_ : std::vector<std::uint32_t>{}, grid});
}

// A variant's failures in the scene (every piece at that variant), probe by probe, charged
// to the piece owning the probe: the scene answers a probe with more than the routed box
// alone (other boxes, fallbacks), so a box asked alone is no proxy for it. Returns the
// scene's answering route; `keep` receives the scene.
SceneRoute BudgetSearch::score(std::size_t v, BoxScene* keep) {
  choice_.assign(pieces_, v);
  BoxScene uniform = compose();
  const TuningProbes& tuning = *tuning_;
  std::vector<Contact> answers(tuning.probes.size());
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, tuning.probes.size(), 256), [&](const auto& r) {
    for (std::size_t i = r.begin(); i != r.end(); ++i) answers[i] = uniform.query(tuning.probes[i], law_);
  });
  const ErrorBudget& budget = br_.budget;
  for (std::size_t p = 0; p < pieces_; ++p) {
    const HapticBox& box = uniform.parts().boxes[p];
    Counts& n = counts_[p][v];
    n = Counts{};
    n.bytes = double(box.table_bytes() + box.triangle_id_bytes());
    for (std::size_t i : owned_[p]) {
      const Contact& a = answers[i];
      const Contact& e = tuning.exact[i];
      n.off_surface += answered_off_surface(e, a, surface_tolerance_) ? 1 : 0;
      n.felt += felt_difference(e, a) ? 1 : 0;
      if (a.contact != e.contact) {
        ++n.disagree;
        continue;
      }
      if (!e.contact) continue;
      ++n.both;
      const double f = relative_force_error(e, a);
      n.over_median += f > budget.force_median ? 1 : 0;
      n.over_p95 += f > budget.force_p95 ? 1 : 0;
      n.over_dir += angle_error_degrees(e, a) > budget.direction_p99_deg ? 1 : 0;
    }
  }
  const SceneRoute route = uniform.route();
  if (keep) *keep = std::move(uniform);
  return route;
}

SceneRoute BudgetSearch::timed_score(std::size_t v, BoxScene* keep) {
  const auto ts = std::chrono::steady_clock::now();
  const SceneRoute route = score(v, keep);
  scoring_seconds_ += seconds_since(ts);
  return route;
}

// Step 2a and the counts of step 3. A scene the surface cells answer (several pieces, a grid,
// one refined box) gives exact's answer to every probe, whatever each piece's sampling and
// refinement: its boxes' tables answer only the boxes' route (--route boxes, the window's
// blend view). Its cheapest form is every piece at the coarsest sampling, refined (the
// surface is shared). Only a scene with no refined piece, which needs no surface at all,
// could cost less; when the coarsest blend misses the budget or answers off the surface
// (every piece of the exactly answered models of docs/results.md under the default budget), the finer samplings
// are not baked and that exact scene is taken (BudgetRecipe::full_search bakes and searches
// them all). Returns whether it was taken (then `refined_coarse` holds it and every piece
// is at variant 1).
bool BudgetSearch::score_variants(BoxScene& refined_coarse) {
  bool exact_scene = false;
  std::size_t scored = 0;  // variants [0, scored) are counted
  if (!br_.full_search && pieces_ > 1 && recipe_.options.scene_grid) {
    timed_score(0);
    const Counts blend = totals();
    exact_scene = timed_score(1, &refined_coarse) == SceneRoute::cells && (excess(blend) > 0.0 || blend.off_surface > 0);
    scored = 2;
    if (exact_scene) choice_.assign(pieces_, 1);
    else refined_coarse = BoxScene{};
  } else if (!br_.full_search && pieces_ == 1) {
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
    if (exact_scene) choice_.assign(pieces_, 1);
    else refined_coarse = BoxScene{};
  }
  if (br_.fastest_exact && !br_.full_search && (exact_scene || pieces_ == 1)) {
    exact_scene = exact_first(refined_coarse, exact_scene);
    if (slower_than_exact_) return exact_scene;
    if (!exact_scene && pieces_ == 1) scored = 0;  // its counts were overwritten: all again
  }
  if (!exact_scene) {
    for (std::size_t c = 1; c < samplings_; ++c) {
      bake_pieces(c, all_);
      report_progress(0.7 * double(c + 1) / double(samplings_));
    }
    for (std::size_t v = scored; v < variants_; ++v) {
      timed_score(v);
      report_progress(0.7 + 0.1 * double(v + 1) / double(variants_));
    }
  }
  stage_done("variant_scoring", scoring_seconds_);  // includes its scenes' grids
  return exact_scene;
}

// Step 2b. Exact first: the exact scene (the cells, or one refined box) timed against Embree
// before any finer sampling is baked. On the full mesh, when Embree answers faster, the search
// ends here and step 5b routes the scene to Embree (its tables would answer nothing); on a
// simplified surface, when Embree over the full mesh is faster, the surface is dropped
// (bake_to_budget bakes the full mesh): it would serve neither time nor accuracy. Returns
// whether the exact scene is taken (`refined_coarse` holds it).
bool BudgetSearch::exact_first(BoxScene& refined_coarse, bool exact_scene) {
  const auto tstage = std::chrono::steady_clock::now();
  if (!exact_scene) {
    choice_.assign(pieces_, 1);
    refined_coarse = compose();
  }
  if (surface_mesh_.use_simplified) {
    early_ = paired_query_ns(refined_coarse, *exact_, timed_, law_);
  } else {
    embree_tree_ = with_route(refined_coarse, SceneRoute::embree);  // its tree serves step 5b (the same surface)
    early_ = paired_query_ns(refined_coarse, embree_tree_, timed_, law_);
  }
  stage_done("exact_first", seconds_since(tstage));
  if (!clearly_faster_than_embree(early_->a_ns, early_->b_ns)) {
    slower_than_exact_ = surface_mesh_.use_simplified;
    choice_.assign(pieces_, 1);
    return true;
  }
  early_.reset();
  if (!exact_scene) {
    refined_coarse = BoxScene{};
    choice_.assign(pieces_, 0);
  }
  return exact_scene;
}

// Step 2b's outcome on a simplified surface slower than Embree over the full mesh: a result
// that names why, for bake_to_budget to bake the full mesh.
BakeResult BudgetSearch::drop_surface(BoxScene refined_coarse) {
  std::ostringstream why;
  why.precision(3);
  why << "the simplified surface's exact scene (" << early_->a_ns << " ns a query) is slower than Embree over the full mesh ("
      << early_->b_ns << " ns)";
  result_.surface_miss = why.str();
  result_.surface_slower_than_exact = true;
  rep_.seconds = seconds_since(t0_);
  result_.scene = with_budget(refined_coarse, rep_);
  return std::move(result_);
}

// Step 4: the whole scene on the tuning probes, in rounds (at most as many as variants):
// while it misses the budget or a ghost answers, each piece owning a failing probe moves up
// to its next refined variant and each ghost piece is refined. Returns the last round's
// figures; `scene` is the last composed.
ComparisonStats BudgetSearch::check_whole_scene(BoxScene& scene) {
  const TuningProbes& tuning = *tuning_;
  std::vector<std::uint32_t> owner(tuning.probes.size(), UINT32_MAX);
  for (std::size_t p = 0; p < pieces_; ++p)
    for (std::size_t i : owned_[p]) owner[i] = std::uint32_t(p);
  ComparisonStats tuned;
  for (std::size_t round = 0;; ++round) {
    std::vector<ProbeRecord> records(tuning.probes.size());
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, tuning.probes.size(), 256), [&](const auto& r) {
      for (std::size_t i = r.begin(); i != r.end(); ++i)
        records[i] = {tuning.probes[i], tuning.exact[i], scene.query(tuning.probes[i], law_)};
    });
    tuned = summarize(records, diagonal_);
    const std::vector<bool> ghost = ghost_pieces(scene, records);
    const bool ghosts = std::find(ghost.begin(), ghost.end(), true) != ghost.end();
    if ((meets_budget(tuned, br_.budget) && !ghosts) || round >= variants_) break;
    std::vector<bool> upgrade(pieces_, false);
    for (std::size_t i = 0; i < records.size(); ++i)
      if (owner[i] != UINT32_MAX && probe_fails_budget(records[i].exact, records[i].approx, br_.budget))
        upgrade[owner[i]] = true;
    bool moved = false;
    for (std::size_t p = 0; p < pieces_; ++p)
      if (ghost[p] && !upgrade[p]) {
        choice_[p] += 1;  // refined at its sampling
        bake_pieces(choice_[p] / 2, {p});
        moved = true;
      } else if (upgrade[p] && choice_[p] + (choice_[p] % 2 ? 2 : 1) < variants_) {
        // Up to the next refined variant (a refined piece never drops its refinement).
        choice_[p] += choice_[p] % 2 ? 2 : 1;
        bake_pieces(choice_[p] / 2, {p});
        moved = true;
      }
    if (!moved) break;
    scene = compose();
  }
  return tuned;
}

// Unrefined pieces whose blends answer a probe off the surface in the whole scene (its
// routing and neighbours answer probes that other pieces own, which the per-variant counts do
// not see): the box that gave the answer (its own blend is it).
std::vector<bool> BudgetSearch::ghost_pieces(const BoxScene& scene, const std::vector<ProbeRecord>& records) const {
  std::vector<bool> ghost(pieces_, false);
  for (std::size_t i = 0; i < records.size(); ++i) {
    const Contact& a = records[i].approx;
    if (!answered_off_surface(records[i].exact, a, surface_tolerance_)) continue;
    for (std::size_t p = 0; p < pieces_; ++p) {
      if (choice_[p] % 2 != 0) continue;
      Contact c;
      float along = 0.f;
      if (scene.parts().boxes[p].query_into(records[i].segment, law_, c, along) && c.depth == a.depth && c.point == a.point)
        ghost[p] = true;
    }
  }
  return ghost;
}

// Step 5b. Never slower than exact: a scene the cells (or one refined box) answer on the full
// mesh's surface is timed against Embree over that surface (the same contacts), one core,
// random order, on the tuning probes, and takes the faster route (Embree wins on small and
// medium meshes, the cells at 800K triangles and up; docs/speed.md). A simplified surface
// keeps the cells (only they shade through its normal map); it is timed against exact on the
// full mesh.
void BudgetSearch::choose_route(BoxScene& scene) {
  const auto tstage = std::chrono::steady_clock::now();
  const bool exact_route = scene.route() == SceneRoute::cells || has_triangle_ids(scene.parts());
  const std::shared_ptr<const SurfaceTriangles>& surface = scene.parts().surface;
  if (br_.fastest_exact && exact_route && surface && surface->normal_map_side() == 0) {
    SceneParts parts = scene.parts();
    parts.embree = embree_tree_.parts().embree;  // step 2b's tree: no second build over the same surface
    parts.route = SceneRoute::embree;
    const BoxScene by_embree(std::move(parts));
    // The scene timed at step 2b is this one: its timing stands.
    const PairedTiming t = early_ ? *early_ : paired_query_ns(scene, by_embree, timed_, law_);
    rep_.cells_ns = t.a_ns, rep_.embree_ns = t.b_ns;
    rep_.exact_ns = t.b_ns;
    rep_.answer_ns = std::min(t.a_ns, t.b_ns);
    // Embree reads the surface alone: the boxes keep their frames (the window draws them,
    // `info` lists them), not their tables and ids (most of the file), unless asked to
    // (BudgetRecipe::keep_triangle_ids: `--route boxes` to compare).
    if (!clearly_faster_than_embree(t.a_ns, t.b_ns)) scene = br_.keep_triangle_ids ? by_embree : BoxScene(without_tables(by_embree));
  } else {
    const PairedTiming t = paired_query_ns(scene, *exact_, timed_, law_);
    rep_.answer_ns = t.a_ns, rep_.exact_ns = t.b_ns;
  }
  rep_.answer = answerer(scene);
  stage_done("route_timing", seconds_since(tstage));
}

// Step 6: what the scene achieves on fresh probes the choice never saw, and the choice, into
// the report; on a simplified surface also along trajectories.
void BudgetSearch::check_fresh(const BoxScene& scene, const ComparisonStats& tuned) {
  const auto tstage = std::chrono::steady_clock::now();
  ProbeOptions fresh;
  fresh.seed = br_.check_seed;
  const std::vector<Segment> check = sample_probes(mesh_, br_.probes, fresh);
  const ComparisonStats checked = compare_queries(scene, *exact_, check, law_, diagonal_);
  stage_done("fresh_check", seconds_since(tstage));
  record_fresh_check(rep_, br_, checked, check.size(), tuning_->probes.size());
  rep_.tuning_agreement = tuned.contact_agreement;
  rep_.tuning_force_median = tuned.force_error_median;
  rep_.tuning_force_p95 = tuned.force_error_p95;
  rep_.tuning_direction_p99_deg = tuned.angle_error_p99_deg;
  rep_.candidates_tried = tried_;
  for (std::size_t p = 0; p < pieces_; ++p)
    rep_.pieces.push_back({br_.samplings[choice_[p] / 2].cell, br_.samplings[choice_[p] / 2].n, choice_[p] % 2 == 1,
                           std::uint32_t(owned_[p].size())});
  if (surface_mesh_.use_simplified && rep_.met) check_trajectories(scene);
  else if (surface_mesh_.use_simplified) result_.surface_miss = "fresh probes: " + budget_misses(checked, br_.budget);
}

// Along trajectories too: a simplified surface can meet the budget on random probes and still
// drop or jolt a hand sliding over it (the chess piece's lathe surface: 1-1.3% of exact's
// contact ticks lost, ghost ticks; docs/speed.md). T2 slides over the model at 1 mm depth,
// box against exact; a metric only the box fails rejects the surface.
void BudgetSearch::check_trajectories(const BoxScene& scene) {
  const auto tstage = std::chrono::steady_clock::now();
  StabilityOptions so;
  so.tests = {"T2"};
  so.generated = false;
  so.exact = exact_;
  std::ostringstream miss;
  miss.precision(3);
  std::size_t failures = 0;  // metrics the box fails and exact passes
  for (const StabilityMetric& m : run_stability_suite(scene, mesh_, so).metrics) {
    if (!br_.budget.relative) {
      // The perceptual budget: the share of slide ticks a hand would feel, nothing else.
      if (m.metric.rfind(kFeltTicks, 0) != 0 || m.box <= br_.budget.perceptible) continue;
    } else if (m.pass || !m.exact_pass) {
      continue;
    }
    if (++failures <= 3)
      miss << (failures > 1 ? "; " : "T2's trajectories: ") << m.metric << " " << m.box << " (exact " << m.exact << ")";
  }
  if (failures > 3) miss << "; " << failures - 3 << " more";
  result_.surface_miss = miss.str();
  stage_done("trajectory_check", seconds_since(tstage));
}

BakeResult BudgetSearch::finish(BoxScene scene) {
  rep_.seconds = seconds_since(t0_);
  result_.scene = with_budget(scene, rep_);
  result_.stats.seconds = ray_seconds_;
  result_.stats.rays = rays_;
  result_.stats.hits = hits_;
  result_.stats.rays_per_second = ray_seconds_ > 0 ? double(rays_) / ray_seconds_ : 0.0;
  result_.stats.ranks = {{0, rays_, ray_seconds_, 0}};
  for (const HapticBox& box : result_.scene.parts().boxes)
    result_.stats.table_bytes += box.raw_table_bytes() + box.triangle_id_bytes();
  report_progress(1.0);
  return std::move(result_);
}

} // namespace hb
