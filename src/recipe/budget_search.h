#pragma once
// The budgeted bake on one surface (steps 0-6 of budgeted_bake.cpp's overview) as one object:
// the constructor takes the inputs, run() performs the steps in order, one method a step.
// The state the steps share (the surface, the probes' ownership, the boxes baked so far per
// sampling, the grids per choice of samplings, each piece's failure counts per variant, the
// current choice) lives in the members. Internal to recipe/ (budgeted_bake.cpp).
#include "evaluation/comparison.h"
#include "evaluation/query_timing.h"
#include "surface/scene_grid.h"
#include "recipe/bake_recipe.h"
#include "recipe/budget_probes.h"
#include "recipe/budget_surface.h"
#include <chrono>
#include <cstdint>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

namespace hb {

class BudgetSearch {
public:
  /// `ref`: the full mesh's exact reference and tuning probes, built on first use and kept
  /// for the caller's next attempt. Throws hb::InvalidInput for samplings out of range,
  /// several ranks or an empty mesh.
  BudgetSearch(const TriangleMesh& mesh, const BakeRecipe& recipe, const SourceInfo& source, BudgetReference& ref);
  /// The cheapest scene found on this attempt's surface, its BudgetReport set;
  /// BakeResult::surface_miss says what a simplified surface missed. Runs once.
  BakeResult run();

private:
  /// Per piece and variant: its bytes and, on the probes it owns, the counts the budget
  /// limits: contact disagreements, and among probes in contact on both sides those whose
  /// force error exceeds the median bound, the p95 bound, and whose direction error exceeds
  /// the p99 bound.
  struct Counts {
    double bytes = 0;
    double disagree = 0, both = 0, over_median = 0, over_p95 = 0, over_dir = 0;
    double felt = 0;         // perceptibly different (the budget's perceptual criterion)
    double off_surface = 0;  // answered off the surface (not a budget figure: see step 3)
  };
  using Lists = std::vector<std::vector<std::uint32_t>>;

  void stage_done(const char* name, double seconds);
  void report_progress(double fraction) const;
  BudgetStageDone stage_callback();

  // Steps 0-1: the surface, the reference, the pieces, the refinement surface, ownership.
  void prepare_surface();
  void decompose();
  void assign_ownership();
  // Step 2: the variants' boxes and grids.
  BakeOptions options_for(std::size_t sampling) const;
  const Lists& lists_at(std::size_t sampling);
  void bake_pieces(std::size_t sampling, const std::vector<std::size_t>& which);
  std::shared_ptr<const SceneGrid> grid_for(const std::vector<std::size_t>& sampling_of_piece);
  BoxScene compose();
  // Step 2a-3: the variants' failures and the choice.
  SceneRoute score(std::size_t variant, BoxScene* keep = nullptr);
  SceneRoute timed_score(std::size_t variant, BoxScene* keep = nullptr);
  bool score_variants(BoxScene& refined_coarse);
  bool exact_first(BoxScene& refined_coarse, bool exact_scene);
  BakeResult drop_surface(BoxScene refined_coarse);
  Counts totals() const;
  double excess(const Counts& t) const;
  double piece_bytes(std::size_t p, std::size_t v) const { return counts_[p][v].bytes; }
  void select_variants();
  void start_at_cheapest_uniform();
  void lower_each_piece();
  void make_best_moves();
  // Step 4: the whole scene on the tuning probes.
  ComparisonStats check_whole_scene(BoxScene& scene);
  std::vector<bool> ghost_pieces(const BoxScene& scene, const std::vector<ProbeRecord>& records) const;
  // Steps 5-6: ids, route, fresh probes, trajectories.
  void choose_route(BoxScene& scene);
  void check_fresh(const BoxScene& scene, const ComparisonStats& tuned);
  void check_trajectories(const BoxScene& scene);
  BakeResult finish(BoxScene scene);

  const TriangleMesh& mesh_;
  const BakeRecipe& recipe_;
  const BudgetRecipe& br_;
  const SourceInfo& source_;
  BudgetReference& ref_;
  std::chrono::steady_clock::time_point t0_;
  float diagonal_ = 0.f;
  BakeResult result_;
  BudgetReport rep_;
  BudgetSurface surface_mesh_;  // step 0: base() and cast()
  const TriangleMesh* base_ = nullptr;
  const TriangleMesh* cast_ = nullptr;
  ForceLaw law_;
  const TuningProbes* tuning_ = nullptr;
  const ExactQuery* exact_ = nullptr;
  std::vector<std::uint32_t> ids_;        // piece id per triangle of base_
  std::vector<std::uint32_t> scene_ids_;  // what the scene records (none on a simplified surface)
  SourceInfo src_;
  std::shared_ptr<const SurfaceTriangles> surface_;
  std::size_t samplings_ = 0, pieces_ = 0, variants_ = 0;
  // Per sampling: the seamed lists of every piece (cheap) and the boxes baked so far.
  std::vector<Lists> lists_;
  std::vector<std::map<std::size_t, HapticBox>> baked_;
  std::map<std::vector<std::size_t>, std::shared_ptr<const SceneGrid>> grids_;
  std::uint64_t rays_ = 0, hits_ = 0;
  double ray_seconds_ = 0.0, scoring_seconds_ = 0.0;
  std::uint32_t tried_ = 0;
  std::vector<std::vector<std::size_t>> owned_;  // per piece: the tuning probes it owns
  double owned_probes_ = 0;
  std::vector<std::size_t> all_;                 // every piece
  float surface_tolerance_ = 0.f;
  std::vector<std::vector<Counts>> counts_;      // per piece and variant
  std::vector<std::size_t> choice_;              // per piece: its variant
  std::vector<Segment> timed_;                   // the tuning probes the routes are timed on
  std::optional<PairedTiming> early_;            // step 2b's timing of the exact scene taken
  BoxScene embree_tree_;                         // step 2b's scene on Embree: its tree serves step 5b
  bool slower_than_exact_ = false;               // step 2b: the simplified surface is dropped
};

} // namespace hb
