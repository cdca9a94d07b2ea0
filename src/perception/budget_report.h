#pragma once
// The error budget a budgeted bake meets ("model no more than a scene needs"), and
// the record of what a bake achieved against it, stored in the box file (version 6). The
// budget search that fills it is in recipe/ (recipe/bake_recipe.h, recipe/error_budget.h).
#include "perception/answerer.h"
#include <cstdint>
#include <string>
#include <utility>
#include <vector>

namespace hb {

/// Accuracy a scene must have against the exact answer (the paper's accuracy measure, on the
/// default probes of hb::sample_probes). The defaults are what a hand cannot tell apart: the
/// force-magnitude JND is about 7%.
struct ErrorBudget {
  /// Whether the relative criteria below (p95, median, dir99, agree) bind too. Off by default:
  /// the perceptual criterion alone decides (a 20% error on a 0.01 N force is felt by no one);
  /// naming any of their keys in the spec turns them on.
  bool relative = false;
  double force_p95 = 0.07;        ///< 95th percentile of the relative force error, fraction.
  double force_median = 0.02;     ///< median relative force error, fraction.
  double direction_p99_deg = 10;  ///< 99th percentile of the force direction error, degrees.
  double agreement = 0.995;       ///< contact agreement, fraction of probes.
  /// The perceptual criterion: at most this share of the probes perceptibly different from
  /// exact (hb::perceive at the nominal thresholds, forces at the workspace's scale: the
  /// model fitted to an 80 mm workspace at 1500 N/m). 0.1 % by default.
  double perceptible = 0.001;
  /// Whether the bake first tries the paper's raw haptic box (recipe/raw_box_trial.h).
  bool raw = true;
  /// The raw box's memory at most, bytes (the memory cap).
  double raw_memory_bytes = 48e6;
};

/// Parses "felt=0.1,raw=on,memory=48" (percent of probes and slide ticks perceptibly
/// different; whether to try the raw box; its memory cap in MB) and the relative criteria
/// "p95=7,median=2,dir99=10,agree=99.5" (percent, percent, degrees, percent; naming any turns
/// them on, `relative=on` all at their defaults): any subset of the keys, in any order, the
/// others at their defaults; "default" or "" is the default budget. Throws hb::InvalidInput
/// naming the bad key or value.
ErrorBudget parse_budget(const std::string& spec);
/// The spec parse_budget reads back (every key).
std::string budget_spec(const ErrorBudget& budget);

/// What one piece of a budgeted bake was given.
struct PieceChoice {
  float cell = 0.f;         ///< position cell, fraction of the mesh diagonal.
  int n = 0;                ///< directional points per sub-block face edge.
  bool refine = false;      ///< triangle ids kept (exact refinement) for this piece.
  std::uint32_t probes = 0; ///< tuning probes the piece owned (routed to it by the grid).
};

/// What a budgeted bake chose and achieved, measured against exact Embree on probes of a seed
/// the choice never saw. Stored in the box file (version 6) and shown by `info`, `--json`,
/// the report and the window's speed chart.
struct BudgetReport {
  bool present = false;             ///< false: the scene was not baked to a budget.
  ErrorBudget budget;
  bool met = false;                 ///< the fresh probes meet the budget.
  std::uint64_t probes = 0;         ///< fresh probes.
  std::uint64_t seed = 0;           ///< their seed.
  double agreement = 0, force_median = 0, force_p95 = 0, direction_p99_deg = 0;
  double perceptible = 0;           ///< share of the fresh probes perceptibly different.
  std::uint64_t tuning_probes = 0, tuning_seed = 0;
  double tuning_agreement = 0, tuning_force_median = 0, tuning_force_p95 = 0, tuning_direction_p99_deg = 0;
  double seconds = 0;               ///< the whole budgeted bake.
  std::uint32_t candidates_tried = 0;
  std::vector<PieceChoice> pieces;  ///< one per box, in box order.
  /// What answers the scene's queries (Answerer::embree where Embree was measured faster than
  /// the cells at bake time); Answerer::none when not recorded (the cells answer).
  Answerer answer = Answerer::none;
  /// The raw samplings tried (recipe/raw_box_trial.h): "m n bytes probes_felt ticks_felt
  /// outcome box_ns exact_ns" with outcome one of kept, serves (a finer one that a cheaper kept
  /// one made unneeded), felt-probes, felt-light, felt-slides, over-cap, slower, slower-strokes; box_ns and
  /// exact_ns the raw box's query time and exact Embree's beside it at bake time (one core,
  /// random order, on the tuning probes; 0 in older files, whose lines have six fields), then along strokes when timed (box_stroke_ns, exact_stroke_ns).
  struct RawTried {
    int m = 0, n = 0;
    double bytes = 0, probes_felt = 0, ticks_felt = -1;
    /// Share of the light touches at any angle felt (-1: not judged; an eleventh field, the
    /// stroke times then written even when 0).
    double light_felt = -1;
    std::string outcome;
    double box_ns = 0, exact_ns = 0;
    /// Along strokes (SceneProbe against exact), for a sampling that reached that timing
    /// (0: not timed; two fields more when timed).
    double box_stroke_ns = 0, exact_stroke_ns = 0;
  };
  std::vector<RawTried> raw_tried;
  /// The query times measured at bake time, one core, random order, ns: the answer chosen and
  /// exact Embree's; the cells route's and Embree's over the scene's surface when both were
  /// timed. In the file form (the speed chart a loaded box shows, hb::bake_chart_rows), so
  /// two bakes of the same inputs differ in these values only; 0 in older files.
  double answer_ns = 0, exact_ns = 0, cells_ns = 0, embree_ns = 0;
  /// Along strokes (a probe's successive queries through its SceneQueryState, as the servo
  /// loop asks), for a scene the cells answer (recipe/stroke_route.h): Answerer::embree when
  /// exact Embree over the full mesh was measured faster there and answers them (the scene's
  /// stroke route, SceneParts::stroke), Answerer::cells when the cells were as fast or the
  /// mesh too large to keep, Answerer::none when not timed; the two times, ns a query at bake
  /// time, one core (0: not timed).
  Answerer stroke_answer = Answerer::none;
  double stroke_cells_ns = 0, stroke_embree_ns = 0;
  /// This report with every query time above set to 0: what the same inputs bake to byte for
  /// byte (the file form of two bakes differs in nothing else).
  BudgetReport without_times() const;
  /// The surface the boxes were baked and refined against (BudgetRecipe::simplify):
  /// surface_triangles 0 when it is the full mesh; otherwise the simplified triangle count,
  /// the deviation bound asked (model units) and the deviation measured from the full surface
  /// along its normals (hb::measure_deviation: mean, p99, max), the seconds it took.
  std::uint64_t full_triangles = 0;
  std::uint64_t surface_triangles = 0;
  double surface_bound = 0, surface_deviation_mean = 0, surface_deviation_p99 = 0, surface_deviation_max = 0;
  /// The angle between the full mesh's shaded normals and the surface's (its corner normals
  /// fitted to them, hb::fit_shading) at the same points (median, p99; degrees); 0 with a
  /// normal map (surface_map_side), whose shading the fresh check's direction error judges.
  double surface_normal_median_deg = 0, surface_normal_p99_deg = 0;
  /// The side of the surface's normal map (SurfaceTriangles::set_normal_map: the full mesh's
  /// shading on a lattice over each simplified triangle, hb::fit_normal_map); 0 for none.
  std::uint32_t surface_map_side = 0;
  /// The triangles of the last simplified surface that was tried and missed the budget on
  /// the fresh probes or along T2's trajectories (the scene is then one simplified within a
  /// tighter bound, when surface_triangles > 0, or the full mesh's); 0 when none was.
  std::uint64_t surface_rejected = 0;
  /// What that surface missed, one line (BakeResult::surface_miss); empty when none was
  /// rejected, or in older files.
  std::string surface_rejected_why;
  /// Every simplified surface this run tried and dropped, in order: its triangles, its bound
  /// (model units) and what it missed. Like `seconds`, not in the file form (bake --json).
  struct SurfaceMissed {
    std::uint64_t triangles = 0;
    double bound = 0;
    std::string why;
  };
  std::vector<SurfaceMissed> surfaces_missed;
  double simplify_seconds = 0;
  /// This run's wall seconds per stage of the budgeted bake, in step order ("simplify",
  /// "decompose", "tables", ...; budgeted_bake.cpp names them), so anyone can see where a
  /// bake's time goes. Like `seconds`, not in the file form (same inputs, same bytes): `bake`
  /// prints them, `bake --json` holds them; a box file read back has none.
  std::vector<std::pair<std::string, double>> stage_seconds;
  /// Adds `s` to the stage `name` (appended the first time it is named).
  void add_stage(const std::string& name, double s) {
    for (auto& st : stage_seconds)
      if (st.first == name) {
        st.second += s;
        return;
      }
    stage_seconds.emplace_back(name, s);
  }

  /// "key=value" lines (the file form); parse() reads them back and throws hb::InvalidInput on
  /// anything else, so a corrupt section cannot load.
  std::string serialize() const;
  static BudgetReport parse(const std::string& text);
  /// One line: "budget p95=7,... met on 20000 fresh probes (seed 102): agreement 99.61%, ...".
  std::string summary() const;
};

} // namespace hb
