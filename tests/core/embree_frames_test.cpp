// A scene answered by exact Embree keeps its boxes as frames (BoxScene::without_tables): no
// tables, no triangle ids, the OBBs and samplings kept; the same answers; a smaller file that
// loads back on the Embree route; the routes and operations that need tables refuse it.
#include "contact/workspace.h"
#include "errors.h"
#include "evaluation/probe_sampling.h"
#include "scene/bake.h"
#include "store/box_file.h"
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
  SceneParts parts = without_triangle_ids(test::refined_two_spheres(two));
  parts.budget.present = true;
  parts.budget.answer = Answerer::embree;
  parts.route = SceneRoute::embree;
  return BoxScene(std::move(parts));
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
  ASSERT_EQ(tables.route(), SceneRoute::embree);
  const BoxScene frames = BoxScene(without_tables(tables));
  ASSERT_TRUE(has_tables(tables.parts()));
  EXPECT_FALSE(has_tables(frames.parts()));
  EXPECT_EQ(frames.route(), SceneRoute::embree);
  EXPECT_EQ(frames.bytes().tables, 0u);
  EXPECT_LT(frames.bytes().memory, tables.bytes().memory);
  ASSERT_EQ(frames.parts().boxes.size(), tables.parts().boxes.size());
  for (std::size_t b = 0; b < frames.parts().boxes.size(); ++b) {
    const HapticBox& f = frames.parts().boxes[b];
    EXPECT_FALSE(f.has_table());
    EXPECT_EQ(f.raw_table_bytes(), 0u);
    EXPECT_EQ(f.params().m, tables.parts().boxes[b].params().m);
    EXPECT_EQ(f.params().n, tables.parts().boxes[b].params().n);
    EXPECT_EQ(f.obb().center, tables.parts().boxes[b].obb().center);
    EXPECT_EQ(f.obb().half, tables.parts().boxes[b].obb().half);
  }
  EXPECT_EQ(frames.parts().piece_of_triangle, tables.parts().piece_of_triangle);
  EXPECT_EQ(frames.parts().surface, tables.parts().surface);

  const std::string with = scratch("tables"), without = scratch("frames");
  save_box_file(tables, with);
  save_box_file(frames, without);
  // Only a file with frames needs format version 8; the others are written as before.
  EXPECT_EQ(file_version(with), 7u);
  EXPECT_EQ(file_version(without), 8u);
  const auto with_bytes = std::filesystem::file_size(with), without_bytes = std::filesystem::file_size(without);
  EXPECT_GE(with_bytes, without_bytes + tables.bytes().tables) << without_bytes << " " << with_bytes;
  const BoxScene loaded = load_box_file(without, LoadOptions{true});
  std::filesystem::remove(with);
  std::filesystem::remove(without);
  EXPECT_FALSE(has_tables(loaded.parts()));
  EXPECT_EQ(loaded.route(), SceneRoute::embree);
  EXPECT_EQ(loaded.parts().boxes.size(), tables.parts().boxes.size());
  EXPECT_EQ(loaded.parts().boxes[1].obb().center, tables.parts().boxes[1].obb().center);
  EXPECT_EQ(loaded.parts().piece_of_triangle, tables.parts().piece_of_triangle);
  EXPECT_EQ(loaded.parts().budget.serialize(), tables.parts().budget.serialize());

  const ForceLaw law = make_workspace(two.mesh.bounds().diagonal()).law();
  const std::vector<Segment> probes = sample_probes(two.mesh, 3000, ProbeOptions{});
  EXPECT_GT(test::expect_same_answers(tables, loaded, probes, law), 300u);
  EXPECT_GT(test::expect_same_answers(tables, frames, probes, law), 300u);
}

TEST(EmbreeFramesTest, FramesRefuseTheBoxesRouteAndCompressionNamingWhy) {
  const test::TwoSpheres two = test::two_spheres(3.f);
  const BoxScene frames(without_tables(embree_scene(two)));
  try {
    with_route(frames, SceneRoute::boxes);
    FAIL() << "frames took the boxes route";
  } catch (const InvalidInput& e) {
    EXPECT_NE(std::string(e.what()).find("frames without tables"), std::string::npos) << e.what();
  }
  EXPECT_EQ(frames.route(), SceneRoute::embree);
  // The surface cells still answer (exactly) where the grid has them.
  EXPECT_EQ(with_route(frames, SceneRoute::cells).route(), SceneRoute::cells);
  EXPECT_THROW(compressed(frames, CodecOptions{CodecId::block}), InvalidInput);
  // A frame answers nothing by itself, one query or many.
  const HapticBox& f = frames.parts().boxes[0];
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
  ASSERT_EQ(one.parts().boxes.size(), 1u);
  const BoxScene frame = BoxScene(without_tables(one));
  EXPECT_EQ(frame.route(), SceneRoute::embree);
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
  const BoxScene cells(without_triangle_ids(test::refined_two_spheres(two)));
  const BoxScene routed = with_route(cells, SceneRoute::embree);
  ASSERT_NE(routed.parts().embree, nullptr);
  EXPECT_EQ(routed.bytes().embree, with_route(cells, SceneRoute::embree).bytes().embree);
  // Parts carrying the tree over the same surface object: the new scene builds none.
  SceneParts same = cells.parts();
  same.embree = routed.parts().embree;
  same.route = SceneRoute::embree;
  EXPECT_EQ(BoxScene(same).parts().embree, routed.parts().embree);
  // An equal surface, not the same object: its own tree.
  SceneParts other = without_triangle_ids(test::refined_two_spheres(two));
  other.embree = routed.parts().embree;
  other.route = SceneRoute::embree;
  EXPECT_NE(BoxScene(other).parts().embree, routed.parts().embree);
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
  const bool embree = baked.scene.parts().budget.answer == Answerer::embree;
  EXPECT_EQ(baked.scene.route() == SceneRoute::embree, embree);
  EXPECT_EQ(has_tables(baked.scene.parts()), !embree) << baked.scene.parts().budget.summary();
  if (embree) {
    EXPECT_EQ(baked.stats.table_bytes, 0u);
  }
  recipe.budget.keep_triangle_ids = true;
  const BakeResult kept = bake(two.mesh, recipe);
  EXPECT_TRUE(has_tables(kept.scene.parts()));
}

} // namespace
} // namespace hb
