#include "recipe/sweep.h"
#include "recipe/box_cache.h"
#include "exact/exact_query.h"
#include "errors.h"
#include "mesh/generators.h"
#include <gtest/gtest.h>
#include <filesystem>
#include <unistd.h>

TEST(SweepTest, ParetoFrontKeepsOnlyUndominatedRows) {
  std::vector<hb::SweepRow> rows(4);
  rows[0].query_ns = 100, rows[0].force_error_median = 0.10;  // fast, inaccurate: front
  rows[1].query_ns = 200, rows[1].force_error_median = 0.05;  // front
  rows[2].query_ns = 300, rows[2].force_error_median = 0.06;  // dominated by 1
  rows[3].query_ns = 900, rows[3].force_error_median = 0.0;   // exact: front
  hb::mark_pareto_front(rows);
  EXPECT_TRUE(rows[0].pareto);
  EXPECT_TRUE(rows[1].pareto);
  EXPECT_FALSE(rows[2].pareto);
  EXPECT_TRUE(rows[3].pareto);
  // What a hand feels decides first: a row with a lower median but a higher perceptible
  // share does not dominate a slower one a hand tells apart less often.
  rows[1].perceptible_share = 0.3, rows[2].perceptible_share = 0.1, rows[0].perceptible_share = 0.5;
  hb::mark_pareto_front(rows);
  EXPECT_TRUE(rows[1].pareto);
  EXPECT_TRUE(rows[2].pareto);
}

TEST(SweepTest, ABoxRowIsNamedByItsLabelOrSamplingThenItsCodecAndRefinement) {
  hb::SweepRow raw;
  raw.m = 8, raw.n = 4, raw.codec = "none";
  EXPECT_EQ(hb::configuration_name(raw), "m8 n4");
  hb::SweepRow refined = raw;
  refined.codec = "block", refined.refine = true;
  EXPECT_EQ(hb::configuration_name(refined), "m8 n4 block ref");
  refined.label = "default bake: 19 boxes";
  EXPECT_EQ(hb::configuration_name(refined), "default bake: 19 boxes block ref");
}

TEST(SweepTest, RunsReferencesAndConfigurationsAndReusesTheCache) {
  const hb::TriangleMesh mesh = hb::make_sphere(1.f, 3);
  const hb::ExactQuery exact(mesh);
  const std::string cache = "/tmp/vtk_hb_sweep_test_" + std::to_string(::getpid());
  hb::SweepOptions options;
  options.configs = hb::sweep_grid({4, 8}, {3});
  options.samples = 1000;
  options.timing_rounds = 1;
  options.cache_dir = cache;
  const hb::SourceInfo source{"sphere", 0x1234, mesh.triangle_count(), mesh.bounds().diagonal()};
  const auto rows = hb::run_sweep(mesh, source, {{"exact_embree", &exact, 0, 0.0}}, options);
  ASSERT_EQ(rows.size(), 3u);
  EXPECT_EQ(rows[0].method, "exact_embree");
  EXPECT_EQ(rows[0].force_error_median, 0.0);
  EXPECT_EQ(rows[0].contact_agreement, 1.0);
  EXPECT_EQ(rows[2].m, 8);
  EXPECT_FALSE(rows[2].from_cache);
  EXPECT_EQ(hb::BoxCache(cache).usage().files, 2u);
  const auto again = hb::run_sweep(mesh, source, {{"exact_embree", &exact, 0, 0.0}}, options);
  EXPECT_TRUE(again[2].from_cache);
  EXPECT_EQ(again[2].force_error_median, rows[2].force_error_median);
  std::filesystem::remove_all(cache);
  options.configs = {{8, 3, "nonsense"}};
  EXPECT_THROW(hb::run_sweep(mesh, source, {{"exact_embree", &exact, 0, 0.0}}, options), hb::InvalidInput);
}

TEST(SweepTest, PiecesAndRefinementAreSweptAndCachedApart) {
  // A torus split in two by a plane through its axis: one box per half, seams shared.
  const hb::TriangleMesh torus = hb::make_torus(1.f, 0.3f, 48, 16);
  std::vector<std::uint32_t> pieces(torus.triangle_count());
  for (std::uint32_t t = 0; t < pieces.size(); ++t) {
    const auto& tri = torus.triangles[t];
    pieces[t] = torus.positions[tri[0]].x() + torus.positions[tri[1]].x() + torus.positions[tri[2]].x() > 0.f ? 1u : 0u;
  }
  const hb::ExactQuery exact(torus);
  const std::string cache = "/tmp/hb_sweep_pieces_test_" + std::to_string(::getpid());
  hb::SweepOptions options;
  options.configs = hb::sweep_grid({8}, {4}, {"none"}, {false, true});
  options.samples = 1500;
  options.timing_rounds = 1;
  options.cache_dir = cache;
  const hb::SourceInfo source{"torus", 0x77, torus.triangle_count(), torus.bounds().diagonal()};
  const auto one = hb::run_sweep(torus, source, {{"exact_embree", &exact, 0, 0.0}}, options);
  options.recipe.pieces.kind = hb::PiecesRecipe::Kind::given;
  options.recipe.pieces.given = pieces;
  const auto two = hb::run_sweep(torus, source, {{"exact_embree", &exact, 0, 0.0}}, options);
  ASSERT_EQ(two.size(), 3u);
  EXPECT_FALSE(two[1].from_cache);  // not the one-box scene of the same densities
  EXPECT_FALSE(two[1].refine);
  EXPECT_TRUE(two[2].refine);
  // Two halves remove the pocket of the hole; refinement makes the answers exact.
  EXPECT_GT(two[1].contact_agreement, one[1].contact_agreement);
  EXPECT_LT(two[2].force_error_median, 1e-4);
  EXPECT_GT(two[2].memory_bytes, two[1].memory_bytes);
  const auto again = hb::run_sweep(torus, source, {{"exact_embree", &exact, 0, 0.0}}, options);
  EXPECT_TRUE(again[1].from_cache);
  EXPECT_TRUE(again[2].from_cache);
  EXPECT_EQ(again[2].force_error_median, two[2].force_error_median);
  std::filesystem::remove_all(cache);
}

TEST(SweepTest, TheDefaultBakeIsMeasuredOnTheSameProbesAndTakenFromTheCacheTheSecondTime) {
  // The row a user compares the configurations with: the budgeted bake `bake MESH -o BOX` makes.
  const hb::TriangleMesh mesh = hb::make_sphere(1.f, 3);
  const hb::ExactQuery exact(mesh);
  const std::string cache = "/tmp/hb_sweep_default_test_" + std::to_string(::getpid());
  hb::SweepOptions options;
  options.configs = hb::sweep_grid({4}, {3});
  options.samples = 2000;
  options.timing_rounds = 1;
  options.cache_dir = cache;
  options.default_bake = true;
  const hb::SourceInfo source{"sphere", 0x4321, mesh.triangle_count(), mesh.bounds().diagonal()};
  const auto rows = hb::run_sweep(mesh, source, {{"exact_embree", &exact, 0, 0.0}}, options);
  ASSERT_EQ(rows.size(), 3u);
  const hb::SweepRow& d = rows[2];
  EXPECT_EQ(d.method, "haptic_box");
  EXPECT_EQ(d.label.rfind("default bake: ", 0), 0u) << d.label;
  EXPECT_TRUE(d.refine);
  EXPECT_FALSE(d.from_cache);
  EXPECT_GT(d.bake_seconds, 0.0);
  EXPECT_GT(d.query_ns, 0.0);
  EXPECT_GT(d.memory_bytes, 0u);
  // The default budget on these probes too, and far above the raw box beside it.
  EXPECT_GE(d.contact_agreement, 0.995);
  EXPECT_LE(d.force_error_p95, 0.07);
  EXPECT_LT(d.force_error_median, rows[1].force_error_median);
  // Checked against the default budget: exact and the default bake are within it, the coarse
  // raw box is not, and the default bake is the cheapest box that is.
  EXPECT_TRUE(rows[0].within_budget);
  EXPECT_FALSE(rows[1].within_budget);
  EXPECT_TRUE(d.within_budget);
  EXPECT_EQ(hb::fastest_within_budget(rows), &rows[2]);
  const auto again = hb::run_sweep(mesh, source, {{"exact_embree", &exact, 0, 0.0}}, options);
  ASSERT_EQ(again.size(), 3u);
  EXPECT_TRUE(again[2].from_cache);
  EXPECT_EQ(again[2].bake_seconds, 0.0);
  EXPECT_EQ(again[2].contact_agreement, d.contact_agreement);
  EXPECT_EQ(again[2].force_error_median, d.force_error_median);
  std::filesystem::remove_all(cache);
}
