// A scene answered by exact Embree keeps its boxes as frames (BoxScene::without_tables): no
// tables, no triangle ids, the OBBs and samplings kept; the same answers; a smaller file that
// loads back on the Embree route; the routes and operations that need tables refuse it.
#include "contact/workspace.h"
#include "errors.h"
#include "evaluation/probe_sampling.h"
#include "haptic_box/bake.h"
#include "haptic_box/box_file.h"
#include "recipe/bake_recipe.h"
#include "same_answers.h"
#include "two_spheres.h"
#include <gtest/gtest.h>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <unistd.h>

namespace hb {
namespace {

// The two spheres' cells scene (no triangle ids) routed to Embree, its report naming that
// route, as the budgeted bake leaves it before dropping the tables.
BoxScene embree_scene(const test::TwoSpheres& two) {
  BoxScene scene = test::refined_two_spheres(two).without_triangle_ids();
  BudgetReport rep;
  rep.present = true;
  rep.answer = "embree";
  scene.set_budget_report(rep);
  return scene;
}

std::string scratch(const char* name) { return "/tmp/hb_frames_" + std::to_string(::getpid()) + "_" + name + ".hbox"; }

std::uint32_t file_version(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  char head[12] = {};
  in.read(head, sizeof head);
  std::uint32_t v = 0;
  std::memcpy(&v, head + 8, 4);
  return v;
}

TEST(EmbreeFramesTest, AnEmbreeRoutedScenesFileHoldsFramesNotTablesAndAnswersTheSame) {
  const test::TwoSpheres two = test::two_spheres(3.f);
  const BoxScene tables = embree_scene(two);
  ASSERT_EQ(tables.answering_route(), SceneRoute::embree);
  const BoxScene frames = tables.without_tables();
  ASSERT_TRUE(tables.has_tables());
  EXPECT_FALSE(frames.has_tables());
  EXPECT_EQ(frames.answering_route(), SceneRoute::embree);
  EXPECT_EQ(frames.table_bytes(), 0u);
  EXPECT_LT(frames.memory_bytes(), tables.memory_bytes());
  ASSERT_EQ(frames.boxes().size(), tables.boxes().size());
  for (std::size_t b = 0; b < frames.boxes().size(); ++b) {
    const HapticBox& f = frames.boxes()[b];
    EXPECT_FALSE(f.has_table());
    EXPECT_EQ(f.raw_table_bytes(), 0u);
    EXPECT_EQ(f.params().m, tables.boxes()[b].params().m);
    EXPECT_EQ(f.params().n, tables.boxes()[b].params().n);
    EXPECT_EQ(f.obb().center, tables.boxes()[b].obb().center);
    EXPECT_EQ(f.obb().half, tables.boxes()[b].obb().half);
  }
  EXPECT_EQ(frames.piece_of_triangle(), tables.piece_of_triangle());
  EXPECT_EQ(frames.surface(), tables.surface());

  const std::string with = scratch("tables"), without = scratch("frames");
  save_box_file(tables, with);
  save_box_file(frames, without);
  // Only a file with frames needs format version 8; the others are written as before.
  EXPECT_EQ(file_version(with), 7u);
  EXPECT_EQ(file_version(without), 8u);
  const auto with_bytes = std::filesystem::file_size(with), without_bytes = std::filesystem::file_size(without);
  EXPECT_GE(with_bytes, without_bytes + tables.table_bytes()) << without_bytes << " " << with_bytes;
  const BoxScene loaded = load_box_file(without, LoadOptions{true});
  std::filesystem::remove(with);
  std::filesystem::remove(without);
  EXPECT_FALSE(loaded.has_tables());
  EXPECT_EQ(loaded.answering_route(), SceneRoute::embree);
  EXPECT_EQ(loaded.boxes().size(), tables.boxes().size());
  EXPECT_EQ(loaded.boxes()[1].obb().center, tables.boxes()[1].obb().center);
  EXPECT_EQ(loaded.piece_of_triangle(), tables.piece_of_triangle());
  EXPECT_EQ(loaded.budget_report().serialize(), tables.budget_report().serialize());

  const ForceLaw law = make_workspace(two.mesh.bounds().diagonal()).law();
  const std::vector<Segment> probes = sample_probes(two.mesh, 3000, ProbeOptions{});
  EXPECT_GT(test::expect_same_answers(tables, loaded, probes, law), 300u);
  EXPECT_GT(test::expect_same_answers(tables, frames, probes, law), 300u);
}

TEST(EmbreeFramesTest, FramesRefuseTheBoxesRouteAndCompressionNamingWhy) {
  const test::TwoSpheres two = test::two_spheres(3.f);
  BoxScene frames = embree_scene(two).without_tables();
  try {
    frames.set_route(SceneRoute::boxes);
    FAIL() << "frames took the boxes route";
  } catch (const InvalidInput& e) {
    EXPECT_NE(std::string(e.what()).find("frames without tables"), std::string::npos) << e.what();
  }
  EXPECT_EQ(frames.answering_route(), SceneRoute::embree);
  // The surface cells still answer (exactly) where the grid has them.
  frames.set_route(SceneRoute::cells);
  EXPECT_EQ(frames.answering_route(), SceneRoute::cells);
  EXPECT_THROW(frames.compressed(CodecOptions{CodecId::block}), InvalidInput);
  // A frame answers nothing by itself, one query or many.
  const HapticBox& f = frames.boxes()[0];
  const Segment s{f.obb().center + Vec3(3.f, 0.f, 0.f), f.obb().center};
  EXPECT_FALSE(f.query(s, ForceLaw{}).contact);
  Contact many[2];
  many[0].contact = many[1].contact = true;
  const Segment two_segments[2] = {s, s};
  f.query_many(two_segments, 2, ForceLaw{}, many);
  EXPECT_FALSE(many[0].contact || many[1].contact);
}

// One refined box (no grid, no cells): its frame leaves Embree the only route, which a file
// must name (its budget report); one that does not is corrupt.
TEST(EmbreeFramesTest, AFramesFileNamingNoRouteToAnswerItIsCorrupt) {
  const test::TwoSpheres two = test::two_spheres(3.f);
  BakeOptions o;
  o.params = {8, 4};
  o.refine = true;
  const BoxScene one = bake_scene(two.mesh, {}, o, SourceInfo{});
  ASSERT_EQ(one.boxes().size(), 1u);
  const BoxScene frame = one.without_tables();
  EXPECT_EQ(frame.answering_route(), SceneRoute::embree);
  const std::string path = scratch("unrouted");
  save_box_file(frame, path);  // no budget report: nothing names the Embree route
  try {
    load_box_file(path);
    FAIL() << "a frame without a route loaded";
  } catch (const InvalidInput& e) {
    EXPECT_NE(std::string(e.what()).find(path + ": corrupt box file (box frames without tables"), std::string::npos)
        << e.what();
  }
  std::filesystem::remove(path);
}

TEST(EmbreeFramesTest, AScenesEmbreeTreeServesAnotherOnlyOverTheSameSurface) {
  const test::TwoSpheres two = test::two_spheres(3.f);
  const BoxScene cells = test::refined_two_spheres(two).without_triangle_ids();
  BoxScene routed = cells;
  routed.set_route(SceneRoute::embree);
  BoxScene same = cells;  // the same surface object
  EXPECT_EQ(same.embree_bytes(), 0u);
  EXPECT_TRUE(same.take_embree_tree(routed));
  EXPECT_EQ(same.embree_bytes(), routed.embree_bytes());
  EXPECT_EQ(same.answering_route(), SceneRoute::cells);  // the route is still the caller's to set
  BoxScene other = test::refined_two_spheres(two).without_triangle_ids();  // an equal surface, not the same
  EXPECT_FALSE(other.take_embree_tree(routed));
  EXPECT_EQ(other.embree_bytes(), 0u);
}

// The default bake's scene answered by Embree (small meshes; the clock decides) holds frames
// only; one answered by the cells keeps its tables; --keep-ids keeps them either way.
TEST(EmbreeFramesTest, ABudgetedBakeRoutedToEmbreeKeepsOnlyFramesUnlessIdsAreKept) {
  const test::TwoSpheres two = test::two_spheres(3.f);
  BakeRecipe recipe = default_recipe();
  recipe.pieces.kind = PiecesRecipe::Kind::given;
  recipe.pieces.given = two.piece;
  recipe.budget.probes = 1000;
  recipe.budget.samplings = {{0.1f, 6}};
  recipe.budget.budget.raw = false;  // the raw box is another test's (RawBoxTrialTest)
  const BakeResult baked = bake(two.mesh, recipe);
  const bool embree = baked.scene.budget_report().answer == "embree";
  EXPECT_EQ(baked.scene.answering_route() == SceneRoute::embree, embree);
  EXPECT_EQ(baked.scene.has_tables(), !embree) << baked.scene.budget_report().summary();
  if (embree) {
    EXPECT_EQ(baked.stats.table_bytes, 0u);
  }
  recipe.budget.keep_triangle_ids = true;
  const BakeResult kept = bake(two.mesh, recipe);
  EXPECT_TRUE(kept.scene.has_tables());
}

} // namespace
} // namespace hb
