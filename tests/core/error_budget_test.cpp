// The error budget: its syntax, the budgeted bake (the cheapest sampling meeting the budget
// per piece, the report on fresh probes) and the report's file round trip.
#include "contact/workspace.h"
#include "errors.h"
#include "evaluation/comparison.h"
#include "evaluation/probe_sampling.h"
#include "exact/exact_query.h"
#include "recipe/bake_recipe.h"
#include "store/box_file.h"
#include "same_answers.h"
#include "two_spheres.h"
#include <gtest/gtest.h>
#include <algorithm>
#include <filesystem>
#include <unistd.h>

namespace hb {
namespace {

TEST(ErrorBudgetTest, SpecParsesAnySubsetAndRoundTrips) {
  const ErrorBudget d = parse_budget("");
  EXPECT_DOUBLE_EQ(d.force_p95, 0.07);
  EXPECT_DOUBLE_EQ(d.force_median, 0.02);
  EXPECT_DOUBLE_EQ(d.direction_p99_deg, 10.0);
  EXPECT_DOUBLE_EQ(d.agreement, 0.995);
  EXPECT_DOUBLE_EQ(d.perceptible, 0.001);  // at most 0.1 % of probes perceptibly different
  const ErrorBudget b = parse_budget("agree=99, p95=12.5, felt=0.5");
  EXPECT_DOUBLE_EQ(b.perceptible, 0.005);
  EXPECT_DOUBLE_EQ(b.agreement, 0.99);
  EXPECT_DOUBLE_EQ(b.force_p95, 0.125);
  EXPECT_DOUBLE_EQ(b.force_median, 0.02);
  const ErrorBudget back = parse_budget(budget_spec(b));
  EXPECT_DOUBLE_EQ(back.agreement, b.agreement);
  EXPECT_DOUBLE_EQ(back.force_p95, b.force_p95);
  EXPECT_DOUBLE_EQ(back.direction_p99_deg, b.direction_p99_deg);
  EXPECT_DOUBLE_EQ(back.perceptible, b.perceptible);
  EXPECT_THROW(parse_budget("felt=101"), InvalidInput);
  EXPECT_THROW(parse_budget("p95"), InvalidInput);
  EXPECT_THROW(parse_budget("p96=3"), InvalidInput);
  EXPECT_THROW(parse_budget("agree=101"), InvalidInput);
  EXPECT_THROW(parse_budget("dir99=nan"), InvalidInput);
  EXPECT_THROW(parse_budget("median=-1"), InvalidInput);
}

TEST(ErrorBudgetTest, MissesNameEveryFigureOutsideTheBudget) {
  ComparisonStats s;
  s.contact_agreement = 0.999;
  s.force_error_median = 0.01;
  s.force_error_p95 = 0.05;
  s.angle_error_p99_deg = 3;
  const ErrorBudget relative = parse_budget("relative=on");
  ASSERT_TRUE(relative.relative);
  EXPECT_TRUE(meets_budget(s, relative));
  s.force_error_p95 = 0.08;
  s.angle_error_p99_deg = 11;
  EXPECT_FALSE(meets_budget(s, relative));
  const std::string why = budget_misses(s, relative);
  EXPECT_NE(why.find("p95"), std::string::npos) << why;
  EXPECT_NE(why.find("dir99"), std::string::npos) << why;
  EXPECT_EQ(why.find("agreement"), std::string::npos) << why;
}

// The default budget is what a hand feels: relative figures far outside the old criteria
// pass while no probe is perceptibly different, and one felt probe too many misses it.
TEST(ErrorBudgetTest, TheDefaultBudgetIsThePerceptualOneAndRelativeKeysTurnTheOldCriteriaOn) {
  ComparisonStats s;
  s.contact_agreement = 0.9;
  s.force_error_median = 0.3;
  s.force_error_p95 = 0.9;
  s.angle_error_p99_deg = 40;
  s.perceptible_share = 0.0;
  const ErrorBudget b;
  EXPECT_FALSE(b.relative);
  EXPECT_TRUE(meets_budget(s, b)) << budget_misses(s, b);
  s.perceptible_share = 0.002;
  EXPECT_NE(budget_misses(s, b).find("felt 0.2% > 0.1%"), std::string::npos) << budget_misses(s, b);
  EXPECT_EQ(budget_spec(b), "felt=0.1");
  EXPECT_TRUE(parse_budget("p95=7").relative);
  EXPECT_EQ(parse_budget(budget_spec(parse_budget("p95=7,felt=0.2"))).force_p95, 0.07);
  const ErrorBudget capped = parse_budget("raw=off,memory=20");
  EXPECT_FALSE(capped.raw);
  EXPECT_EQ(capped.raw_memory_bytes, 20e6);
  EXPECT_EQ(parse_budget(budget_spec(capped)).raw_memory_bytes, 20e6);
  EXPECT_THROW(parse_budget("raw=maybe"), InvalidInput);
  EXPECT_THROW(parse_budget("memory=0"), InvalidInput);
}

TEST(ErrorBudgetTest, ReportRoundTripsAndCorruptTextThrows) {
  BudgetReport r;
  r.present = true;
  r.met = true;
  r.probes = 2000;
  r.seed = 102;
  r.agreement = 0.9971;
  r.force_p95 = 0.0012;
  r.pieces = {{0.032f, 6, false, 10}, {0.016f, 8, true, 300}};
  r.seconds = 12.5;
  r.surface_rejected = 20308;
  r.surface_rejected_why = "T2's trajectories: share of exact's contact ticks the box loses 0.013 (exact 0)";
  // The wall time stays out of the file form (same inputs, same bytes); older files that hold
  // it still read.
  EXPECT_EQ(r.serialize().find("seconds"), std::string::npos) << r.serialize();
  EXPECT_DOUBLE_EQ(BudgetReport::parse("met=1\nseconds=3.5\n").seconds, 3.5);
  const BudgetReport back = BudgetReport::parse(r.serialize());
  EXPECT_TRUE(back.present && back.met);
  EXPECT_EQ(back.probes, 2000u);
  EXPECT_DOUBLE_EQ(back.agreement, 0.9971);
  ASSERT_EQ(back.pieces.size(), 2u);
  EXPECT_FLOAT_EQ(back.pieces[1].cell, 0.016f);
  EXPECT_TRUE(back.pieces[1].refine);
  EXPECT_FALSE(back.pieces[0].refine);
  EXPECT_EQ(back.surface_rejected_why, r.surface_rejected_why);
  EXPECT_NE(back.summary().find("(T2's trajectories: share of exact's"), std::string::npos) << back.summary();
  EXPECT_THROW(BudgetReport::parse("met=1\nbogus=3\n"), InvalidInput);
  EXPECT_THROW(BudgetReport::parse("surface_rejected_why=" + std::string(5000, 'x') + "\n"), InvalidInput);
  EXPECT_THROW(BudgetReport::parse("piece=0.1 8\n"), InvalidInput);
  EXPECT_THROW(BudgetReport::parse("agreement=2\n"), InvalidInput);
}

// The query times a budgeted bake measured (its answer's, exact's, each raw sampling's) are in
// the file form, so a loaded box's speed chart has them; a file written before them (six-field
// raw_tried lines, no *_ns keys) still reads, with no times; the times are all two bakes of the
// same inputs differ in (without_times).
TEST(ErrorBudgetTest, ReportKeepsTheBakesQueryTimesAndReadsOlderFilesWithout) {
  BudgetReport r;
  r.present = true;
  r.met = true;
  r.answer = Answerer::cells;
  r.answer_ns = 812.5;
  r.exact_ns = 1450.25;
  BudgetReport::RawTried t;
  t.m = 16, t.n = 8, t.bytes = 4.5e6, t.probes_felt = 0.71, t.ticks_felt = -1, t.outcome = "felt-probes";
  t.box_ns = 210.5, t.exact_ns = 1398;
  r.raw_tried = {t};
  const BudgetReport back = BudgetReport::parse(r.serialize());
  EXPECT_DOUBLE_EQ(back.answer_ns, 812.5);
  EXPECT_DOUBLE_EQ(back.exact_ns, 1450.25);
  ASSERT_EQ(back.raw_tried.size(), 1u);
  EXPECT_DOUBLE_EQ(back.raw_tried[0].box_ns, 210.5);
  EXPECT_DOUBLE_EQ(back.raw_tried[0].exact_ns, 1398.0);
  EXPECT_EQ(back.raw_tried[0].outcome, "felt-probes");
  EXPECT_NE(back.summary().find("raw m16 n8 felt-probes: 71% of probes felt, 4.5 MB, 210.5 ns a query against exact's 1398"),
            std::string::npos)
      << back.summary();
  // A sampling that was faster at random but slower along strokes keeps both pairs of times.
  BudgetReport::RawTried u = t;
  u.m = 32, u.n = 16, u.probes_felt = 0, u.ticks_felt = 0.0003, u.outcome = "slower-strokes";
  u.box_stroke_ns = 181.5, u.exact_stroke_ns = 130.5;
  r.raw_tried.push_back(u);
  const BudgetReport both = BudgetReport::parse(r.serialize());
  ASSERT_EQ(both.raw_tried.size(), 2u);
  EXPECT_DOUBLE_EQ(both.raw_tried[1].box_stroke_ns, 181.5);
  EXPECT_DOUBLE_EQ(both.raw_tried[1].exact_stroke_ns, 130.5);
  EXPECT_EQ(both.raw_tried[1].outcome, "slower-strokes");
  EXPECT_EQ(both.raw_tried[0].box_stroke_ns, 0.0);
  EXPECT_NE(both.summary().find("raw m32 n16 slower-strokes: 0% of probes, 0.03% of slide ticks felt, 4.5 MB, 210.5 ns a query "
                                "against exact's 1398, along strokes 181.5 ns against 130.5"),
            std::string::npos)
      << both.summary();
  EXPECT_EQ(both.without_times().raw_tried[1].box_stroke_ns, 0.0);
  // A sampling judged on light touches at any angle (an eleventh field, the stroke times
  // written as 0 when not timed), and one felt there.
  BudgetReport::RawTried v = t;
  v.m = 24, v.n = 12, v.probes_felt = 0, v.light_felt = 0.0025, v.outcome = "felt-light";
  BudgetReport light = r;
  light.raw_tried = {v};
  const BudgetReport light_back = BudgetReport::parse(light.serialize());
  ASSERT_EQ(light_back.raw_tried.size(), 1u);
  EXPECT_DOUBLE_EQ(light_back.raw_tried[0].light_felt, 0.0025);
  EXPECT_EQ(light_back.raw_tried[0].box_stroke_ns, 0.0);
  EXPECT_EQ(light_back.raw_tried[0].outcome, "felt-light");
  EXPECT_NE(light_back.summary().find("raw m24 n12 felt-light: 0% of probes, 0.25% of light touches felt"),
            std::string::npos)
      << light_back.summary();
  EXPECT_EQ(both.raw_tried[1].light_felt, -1.0);  // not judged
  EXPECT_THROW(BudgetReport::parse("raw_tried=16 8 4500000 0.71 -1 felt-light 210 300 0 0 0.5 9\n"), InvalidInput);
  r.raw_tried.pop_back();
  // An older file: six fields, no times.
  const BudgetReport old = BudgetReport::parse("met=1\nraw_tried=16 8 4500000 0.71 -1 felt-probes\n");
  ASSERT_EQ(old.raw_tried.size(), 1u);
  EXPECT_EQ(old.raw_tried[0].box_ns, 0.0);
  EXPECT_EQ(old.answer_ns, 0.0);
  // A time without exact's beside it is a corrupt line.
  EXPECT_THROW(BudgetReport::parse("raw_tried=16 8 4500000 0.71 -1 felt-probes 210\n"), InvalidInput);
  EXPECT_THROW(BudgetReport::parse("raw_tried=16 8 4500000 0.71 -1 slower-strokes 210 300 400\n"), InvalidInput);
  EXPECT_THROW(BudgetReport::parse("answer_ns=-3\n"), InvalidInput);
  // Another run's times: the same bytes once the times are left out.
  BudgetReport again = r;
  again.answer_ns = 640, again.raw_tried[0].box_ns = 190;
  EXPECT_NE(again.serialize(), r.serialize());
  EXPECT_EQ(again.without_times().serialize(), r.without_times().serialize());
  EXPECT_EQ(r.without_times().serialize().find("_ns="), std::string::npos);
}

/// The default recipe over the two spheres' own pieces, tuned on `probes` probes.
BakeRecipe two_piece_recipe(const test::TwoSpheres& two, std::size_t probes) {
  BakeRecipe recipe = default_recipe();
  recipe.pieces.kind = PiecesRecipe::Kind::given;
  recipe.pieces.given = two.piece;
  recipe.budget.probes = probes;
  recipe.budget.fastest_exact = false;  // the cells answer, whatever a clock says (EmbreeRouteTest: the other route)
  return recipe;
}

// Two spheres in two pieces: the budgeted bake meets the budget, reports it on fresh probes
// (which eval confirms), picks the cheapest sampling that does, and the file keeps the report.
TEST(ErrorBudgetTest, BudgetedBakeMeetsTheBudgetOnFreshProbesAndTheFileKeepsIt) {
  const test::TwoSpheres two = test::two_spheres(3.f);
  BakeRecipe recipe = two_piece_recipe(two, 3000);
  recipe.budget.samplings = {{0.2f, 4}, {0.1f, 6}};
  const BakeResult baked = bake(two.mesh, recipe);
  const BudgetReport& rep = baked.scene.parts().budget;
  ASSERT_TRUE(rep.present);
  EXPECT_TRUE(rep.met) << rep.summary();
  EXPECT_EQ(rep.probes, 3000u);
  EXPECT_EQ(rep.seed, recipe.budget.check_seed);
  ASSERT_EQ(rep.pieces.size(), 2u);
  ASSERT_EQ(baked.scene.parts().boxes.size(), 2u);
  bool any_refined = false;
  for (std::size_t b = 0; b < 2; ++b) {
    EXPECT_EQ(baked.scene.parts().boxes[b].params().n, rep.pieces[b].n);
    // The surface cells answer a refined scene: no box keeps triangle ids.
    EXPECT_FALSE(baked.scene.parts().boxes[b].refines());
    EXPECT_GT(rep.pieces[b].probes, 0u);
    any_refined = any_refined || rep.pieces[b].refine;
  }
  EXPECT_EQ(baked.scene.refines(), any_refined);
  // The recorded figures are the scene's own on those probes.
  ProbeOptions po;
  po.seed = recipe.budget.check_seed;
  const ExactQuery exact(two.mesh);
  // At the workspace scale the bake judges at (the perceptual criterion is in newtons).
  const ComparisonStats s = compare_queries(baked.scene, exact, sample_probes(two.mesh, 3000, po),
                                            make_workspace(two.mesh.bounds().diagonal()).law(),
                                            two.mesh.bounds().diagonal());
  EXPECT_DOUBLE_EQ(s.contact_agreement, rep.agreement);
  EXPECT_DOUBLE_EQ(s.force_error_p95, rep.force_p95);
  EXPECT_TRUE(meets_budget(s, recipe.budget.budget));

  const std::string path = "/tmp/hb_budget_test_" + std::to_string(::getpid()) + ".hbox";
  save_box_file(baked.scene, path);
  const BoxScene loaded = load_box_file(path, LoadOptions{true});
  std::filesystem::remove(path);
  ASSERT_TRUE(loaded.parts().budget.present);
  EXPECT_EQ(loaded.parts().budget.serialize(), rep.serialize());
  ASSERT_TRUE(loaded.parts().grid != nullptr);
}

// The default bake keeps no triangle ids where the surface cells answer: the same answers,
// probe for probe, as the same bake with them, in fewer bytes, through a file round trip;
// --keep-ids keeps them for the boxes' route.
TEST(ErrorBudgetTest, DefaultBakeDropsTheTriangleIdsTheCellsRouteDoesNotRead) {
  const test::TwoSpheres two = test::two_spheres(3.f);
  BakeRecipe recipe = two_piece_recipe(two, 2000);
  recipe.budget.samplings = {{0.1f, 6}};
  const BakeResult dropped = bake(two.mesh, recipe);
  recipe.budget.keep_triangle_ids = true;
  const BakeResult kept = bake(two.mesh, recipe);
  ASSERT_EQ(kept.scene.route(), SceneRoute::cells);
  ASSERT_TRUE(has_triangle_ids(kept.scene.parts()));
  EXPECT_FALSE(has_triangle_ids(dropped.scene.parts()));
  EXPECT_TRUE(dropped.scene.refines());
  EXPECT_EQ(dropped.scene.route(), SceneRoute::cells);
  ASSERT_TRUE(dropped.scene.parts().surface != nullptr);
  EXPECT_EQ(dropped.scene.bytes().refinement, dropped.scene.parts().surface->bytes());
  EXPECT_LT(dropped.scene.bytes().refinement, kept.scene.bytes().refinement);
  // The same choice and figures; only the query times each bake measured differ.
  EXPECT_EQ(dropped.scene.parts().budget.without_times().serialize(), kept.scene.parts().budget.without_times().serialize());

  const std::string path = "/tmp/hb_ids_test_" + std::to_string(::getpid()) + ".hbox";
  save_box_file(dropped.scene, path);
  const BoxScene loaded = load_box_file(path, LoadOptions{true});
  std::filesystem::remove(path);
  EXPECT_FALSE(has_triangle_ids(loaded.parts()));
  EXPECT_EQ(loaded.route(), SceneRoute::cells);
  ProbeOptions po;
  po.seed = 7;
  EXPECT_GT(test::expect_same_answers(kept.scene, loaded, sample_probes(two.mesh, 3000, po), ForceLaw{}), 300u);
}

// A scene the surface cells answer gives exact's answers whatever its pieces' samplings: the
// default bake takes it at the coarsest sampling alone (one sampling baked, every piece
// refined there), with the same answers probe for probe as the search over every sampling
// and no larger tables.
TEST(ErrorBudgetTest, ASceneTheSurfaceCellsAnswerIsBakedAtTheCoarsestSamplingOnly) {
  const test::TwoSpheres two = test::two_spheres(3.f);
  BakeRecipe recipe = two_piece_recipe(two, 2000);
  recipe.budget.samplings = {{0.2f, 4}, {0.1f, 6}, {0.07f, 8}};
  const BakeResult quick = bake(two.mesh, recipe);
  recipe.budget.full_search = true;
  const BakeResult full = bake(two.mesh, recipe);
  const BudgetReport& rep = quick.scene.parts().budget;
  ASSERT_EQ(quick.scene.route(), SceneRoute::cells);
  ASSERT_EQ(full.scene.route(), SceneRoute::cells);
  EXPECT_TRUE(rep.met) << rep.summary();
  EXPECT_EQ(rep.candidates_tried, 1u);
  EXPECT_GT(full.scene.parts().budget.candidates_tried, 1u);
  ASSERT_EQ(rep.pieces.size(), 2u);
  for (std::size_t b = 0; b < 2; ++b) {
    EXPECT_TRUE(rep.pieces[b].refine);
    EXPECT_FLOAT_EQ(rep.pieces[b].cell, 0.2f);
    EXPECT_EQ(rep.pieces[b].n, 4);
    EXPECT_EQ(quick.scene.parts().boxes[b].params().n, 4);
  }
  std::size_t quick_tables = 0, full_tables = 0;
  for (const HapticBox& b : quick.scene.parts().boxes) quick_tables += b.table_bytes();
  for (const HapticBox& b : full.scene.parts().boxes) full_tables += b.table_bytes();
  EXPECT_LE(quick_tables, full_tables);
  ProbeOptions po;
  po.seed = 9;
  EXPECT_GT(test::expect_same_answers(quick.scene, full.scene, sample_probes(two.mesh, 3000, po), ForceLaw{}), 300u);
}

// The bake records where its time went, stage by stage in step order (a 13M-triangle bake's
// minutes must be attributable); the times stay out of the file form like `seconds`.
TEST(ErrorBudgetTest, BudgetedBakeRecordsItsStageTimesButTheFileDoesNot) {
  const test::TwoSpheres two = test::two_spheres(3.f);
  BakeRecipe recipe = two_piece_recipe(two, 1000);
  recipe.budget.samplings = {{0.2f, 4}};
  const BakeResult baked = bake(two.mesh, recipe);
  const BudgetReport& rep = baked.scene.parts().budget;
  std::vector<std::string> names;
  for (const auto& st : rep.stage_seconds) {
    names.push_back(st.first);
    EXPECT_GE(st.second, 0.0) << st.first;
  }
  for (const char* must : {"decompose", "exact_build", "tuning_probes", "tables", "variant_scoring", "fresh_check"})
    EXPECT_NE(std::find(names.begin(), names.end(), must), names.end()) << must;
  EXPECT_LT(std::find(names.begin(), names.end(), "decompose"), std::find(names.begin(), names.end(), "fresh_check"));
  EXPECT_EQ(rep.serialize().find("tables"), std::string::npos);
  EXPECT_TRUE(BudgetReport::parse(rep.serialize()).stage_seconds.empty());
}

// A coarse unrefined sampling meets a lax budget, but its blends answer probes from off the
// surface (ghost surfaces on a trajectory): with the surface check the pieces are refined at
// that sampling, and the scene answers no more probes off the surface than without it.
TEST(ErrorBudgetTest, PiecesWhoseBlendsAnswerOffTheSurfaceAreRefined) {
  const test::TwoSpheres two = test::two_spheres(3.f);
  BakeRecipe recipe = two_piece_recipe(two, 1000);
  recipe.budget.samplings = {{0.3f, 3}};
  recipe.budget.budget = parse_budget("p95=100,median=100,dir99=90,agree=50,felt=100");
  const ExactQuery exact(two.mesh);
  ProbeOptions po;
  po.seed = recipe.budget.tuning_seed;
  const auto probes = sample_probes(two.mesh, recipe.budget.probes, po);
  const float tolerance = float(recipe.budget.surface_tolerance) * two.mesh.bounds().diagonal();
  const auto off_surface = [&](const BoxScene& scene) {
    std::size_t off = 0;
    for (const Segment& s : probes) {
      const Contact e = exact.query(s, ForceLaw{}), a = scene.query(s, ForceLaw{});
      off += a.contact && (!e.contact || std::fabs(e.depth - a.depth) > tolerance);
    }
    return off;
  };
  recipe.budget.surface_tolerance = 0;  // the first budgeted bakes
  const BakeResult loose = bake(two.mesh, recipe);
  recipe.budget.surface_tolerance = BudgetRecipe{}.surface_tolerance;
  const BakeResult checked = bake(two.mesh, recipe);
  ASSERT_EQ(loose.scene.parts().budget.pieces.size(), 2u);
  ASSERT_EQ(checked.scene.parts().budget.pieces.size(), 2u);
  for (const PieceChoice& p : loose.scene.parts().budget.pieces) EXPECT_FALSE(p.refine);
  for (const PieceChoice& p : checked.scene.parts().budget.pieces) EXPECT_TRUE(p.refine);
  const std::size_t before = off_surface(loose.scene), after = off_surface(checked.scene);
  EXPECT_GT(before, 0u);
  EXPECT_LT(after, before);
}

TEST(ErrorBudgetTest, AnUnreachableBudgetIsReportedMissedNotHidden) {
  const test::TwoSpheres two = test::two_spheres(3.f);
  BakeRecipe recipe = two_piece_recipe(two, 1000);
  recipe.budget.samplings = {{0.3f, 3}};
  recipe.budget.budget = parse_budget("p95=0,median=0,dir99=0,agree=100");
  const BakeResult baked = bake(two.mesh, recipe);
  EXPECT_TRUE(baked.scene.parts().budget.present);
  EXPECT_FALSE(baked.scene.parts().budget.met);
  EXPECT_NE(baked.scene.parts().budget.summary().find("MISSED"), std::string::npos);
}

TEST(ErrorBudgetTest, BadSamplingsThrow) {
  const test::TwoSpheres two = test::two_spheres(3.f);
  BakeRecipe recipe = default_recipe();
  recipe.budget.samplings = {{0.f, 6}};
  EXPECT_THROW(bake(two.mesh, recipe), InvalidInput);
  recipe.budget.samplings.clear();
  EXPECT_THROW(bake(two.mesh, recipe), InvalidInput);
}

} // namespace
} // namespace hb
