// The bake recipe: one bake(mesh, recipe) for every front end; the scene keeps its piece ids.
#include "decomposition/piece_file.h"
#include "decomposition/plane_split.h"
#include "errors.h"
#include "recipe/bake_recipe.h"
#include "recipe/box_cache.h"
#include "recipe/recipe_choice.h"
#include "recipe/route_rule.h"
#include "scene/box_scene.h"
#include "scene/density_range.h"
#include "store/box_file.h"
#include "mesh/generators.h"
#include <gtest/gtest.h>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <unistd.h>

namespace hb {
namespace {

std::string recipe_temp_path(const std::string& name) { return testing::TempDir() + "hb_recipe_" + name; }

bool same_tables(const BoxScene& a, const BoxScene& b) {
  if (a.parts().boxes.size() != b.parts().boxes.size()) return false;
  for (std::size_t k = 0; k < a.parts().boxes.size(); ++k) {
    const HapticBox& x = a.parts().boxes[k];
    const HapticBox& y = b.parts().boxes[k];
    if (x.table_bytes() != y.table_bytes() || x.codec() != y.codec() ||
        std::memcmp(x.samples().data(), y.samples().data(), x.table_bytes()) != 0)
      return false;
  }
  return true;
}

TEST(BakeRecipeTest, BakeIsTheSeamedPiecesBakedAndCompressed) {
  const TriangleMesh sphere = make_sphere(1.f, 3);
  const std::vector<std::uint32_t> ids = split_by_planes(sphere, {{Vec3::Zero(), Vec3::UnitZ()}});
  BakeRecipe recipe;
  recipe.options.params = {6, 3};
  recipe.options.obb.padding = 0.03f;
  recipe.pieces.kind = PiecesRecipe::Kind::given;
  recipe.pieces.given = ids;
  recipe.codec.codec = CodecId::block;
  const BakeResult baked = bake(sphere, recipe);
  ASSERT_EQ(baked.scene.parts().boxes.size(), 2u);
  EXPECT_EQ(baked.scene.parts().boxes[0].codec(), CodecId::block);
  EXPECT_EQ(baked.scene.parts().piece_of_triangle, ids);
  EXPECT_GT(baked.stats.rays, 0u);
  // By hand: seams in the cells of the boxes the bake fits (the recipe's padding), then the codec.
  const auto lists = seamed_piece_lists(sphere, ids, recipe.seams, recipe.options);
  EXPECT_GT(lists[0].size() + lists[1].size(), sphere.triangle_count());
  const BoxScene by_hand(compressed(bake_scene_from_lists(sphere, lists, recipe.options, {}), recipe.codec));
  EXPECT_TRUE(same_tables(baked.scene, by_hand));
}

// Automatic pieces the caller already decomposed (the VTK decomposition filter upstream of the
// bake filter) stand for the decomposition: the same scene, and the same cache key, as the
// recipe decomposing itself; ids for another triangle count are refused.
TEST(BakeRecipeTest, ResolvedAutomaticPiecesAreTheDecompositionsOwn) {
  TriangleMesh two = make_sphere(1.f, 2), other = make_sphere(1.f, 2);
  const std::uint32_t offset = std::uint32_t(two.vertex_count());
  for (Vec3& p : other.positions) p.x() += 3.f;
  two.positions.insert(two.positions.end(), other.positions.begin(), other.positions.end());
  for (Triangle t : other.triangles) two.triangles.push_back({t[0] + offset, t[1] + offset, t[2] + offset});
  two.compute_vertex_normals();
  BakeRecipe recipe;
  recipe.options.params = {4, 3};
  recipe.pieces.kind = PiecesRecipe::Kind::automatic;
  recipe.pieces.automatic.lines = 20000;
  const BakeResult decomposing = bake(two, recipe);
  ASSERT_GE(decomposing.scene.parts().boxes.size(), 2u);
  BakeRecipe given = recipe;
  given.pieces.resolved = decompose_auto(two, recipe.pieces.automatic).piece_of_triangle;
  EXPECT_EQ(recipe_key(given), recipe_key(recipe));
  const BakeResult resolved = bake(two, given);
  EXPECT_EQ(resolved.scene.parts().piece_of_triangle, decomposing.scene.parts().piece_of_triangle);
  EXPECT_TRUE(same_tables(resolved.scene, decomposing.scene));
  given.pieces.resolved.pop_back();
  EXPECT_THROW(bake(two, given), InvalidInput);
}

TEST(BakeRecipeTest, PieceFileIdsAreNumberedCompactlyLikeGivenOnes) {
  const TriangleMesh sphere = make_sphere(1.f, 2);
  std::vector<std::uint32_t> sparse = split_by_planes(sphere, {{Vec3::Zero(), Vec3::UnitX()}});
  for (auto& id : sparse) id = id * 5 + 2;  // 2 and 7
  const std::string file = recipe_temp_path("sparse.txt");
  write_piece_file(file, sphere, sparse);
  PiecesRecipe from_file = pieces_from_spec(file);
  EXPECT_EQ(from_file.kind, PiecesRecipe::Kind::file);
  PiecesRecipe given;
  given.kind = PiecesRecipe::Kind::given;
  given.given = sparse;
  const auto a = resolve_piece_ids(sphere, from_file);
  EXPECT_EQ(a, resolve_piece_ids(sphere, given));
  EXPECT_EQ(*std::max_element(a.begin(), a.end()), 1u);
  EXPECT_EQ(pieces_from_spec("auto").kind, PiecesRecipe::Kind::automatic);
  EXPECT_EQ(pieces_from_spec("none").kind, PiecesRecipe::Kind::none);
  EXPECT_TRUE(resolve_piece_ids(sphere, pieces_from_spec("")).empty());
  given.given.pop_back();
  EXPECT_THROW(resolve_piece_ids(sphere, given), InvalidInput);
  std::filesystem::remove(file);
}

TEST(BakeRecipeTest, BoxFileKeepsThePieceIds) {
  const TriangleMesh sphere = make_sphere(1.f, 2);
  BakeRecipe recipe;
  recipe.options.params = {4, 2};
  recipe.pieces.kind = PiecesRecipe::Kind::given;
  recipe.pieces.given = split_by_planes(sphere, {{Vec3::Zero(), Vec3::UnitY()}});
  const BakeResult baked = bake(sphere, recipe, {"sphere", 42, 0, 0.f});
  EXPECT_EQ(baked.scene.parts().source.triangles, sphere.triangle_count());
  const std::string path = recipe_temp_path("pieces.hbox");
  save_box_file(baked.scene, path);
  const BoxScene loaded = load_box_file(path, {true, false});
  EXPECT_EQ(loaded.parts().piece_of_triangle, recipe.pieces.given);
  EXPECT_TRUE(same_tables(loaded, baked.scene));
  // One piece: no ids stored.
  recipe.pieces = {};
  save_box_file(bake(sphere, recipe).scene, path);
  EXPECT_TRUE(load_box_file(path).parts().piece_of_triangle.empty());
  std::filesystem::remove(path);
}

TEST(BakeRecipeTest, SceneRejectsPieceIdsNamingMissingBoxes) {
  const TriangleMesh sphere = make_sphere(1.f, 1);
  BakeRecipe recipe;
  recipe.options.params = {3, 2};
  BoxScene scene = bake(sphere, recipe).scene;
  SceneParts bad = scene.parts();
  bad.piece_of_triangle.assign(sphere.triangle_count(), 1u);
  EXPECT_THROW(BoxScene{bad}, InvalidInput);
}

TEST(RecipeChoiceTest, AnySamplingOptionBakesExactlyThatSamplingElseTheDefault) {
  EXPECT_TRUE(bakes_default_recipe({}));
  EXPECT_TRUE(bakes_default_recipe(SamplingGiven::advanced(false)));
  for (const SamplingGiven given : {SamplingGiven{true, false, false, false}, SamplingGiven{false, true, false, false},
                                    SamplingGiven{false, false, true, false}, SamplingGiven{false, false, false, true},
                                    SamplingGiven::advanced(true)})
    EXPECT_FALSE(bakes_default_recipe(given));
  BakeRecipe sampling;
  sampling.options.params = {6, 3};
  EXPECT_EQ(choose_recipe({}, sampling).budget.enabled, default_recipe().budget.enabled);
  EXPECT_TRUE(choose_recipe({}, sampling).budget.enabled);
  const BakeRecipe chosen = choose_recipe({false, true, false, false}, sampling);
  EXPECT_FALSE(chosen.budget.enabled);
  EXPECT_EQ(chosen.options.params.m, 6);
  EXPECT_EQ(chosen.options.params.n, 3);
}

TEST(DensityRangeTest, ASceneIsItsBoxesRangeNotItsFirstBox) {
  EXPECT_EQ(range_text(8, 8), "8");
  EXPECT_EQ(range_text(8, 15), "8..15");
  EXPECT_EQ(density_range_text({8, 15, 6, 6}), "m=8..15 n=6");
  const DensityRange none = density_range(BoxScene{});
  EXPECT_EQ(none.m_max, 0);
  BakeRecipe recipe;
  recipe.options.params = {6, 3};
  const DensityRange one = density_range(bake(make_sphere(1.f, 2), recipe).scene);
  EXPECT_EQ(density_range_text(one), "m=6 n=3");
}

} // namespace
} // namespace hb

namespace hb {
namespace {

std::string file_bytes(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}

// The route rule (recipe/route_rule.h) settles near-ties for Embree: the same model baked
// again on the same machine takes the same route and writes the same bytes, apart from the
// query times the bake recorded.
TEST(RouteRuleTest, ADefaultBakeRepeatedGivesTheSameRouteAndTheSameBytesApartFromTimes) {
  const TriangleMesh torus = make_torus(1.f, 0.35f, 48, 24);
  BakeRecipe recipe = default_recipe();
  recipe.budget.probes = 1000;
  const std::string path = (std::filesystem::temp_directory_path() / ("hb_route_rule_" + std::to_string(::getpid()))).string();
  std::string first_bytes;
  Answerer first_answer = Answerer::none;
  for (int run = 0; run < 3; ++run) {
    const BakeResult baked = bake(torus, recipe);
    const BoxScene timeless = with_budget(baked.scene, baked.scene.parts().budget.without_times());
    save_box_file(timeless, path);
    if (run == 0) {
      first_bytes = file_bytes(path);
      first_answer = baked.scene.parts().budget.answer;
      continue;
    }
    EXPECT_EQ(baked.scene.parts().budget.answer, first_answer) << "run " << run;
    EXPECT_TRUE(file_bytes(path) == first_bytes) << "run " << run << ": " << baked.scene.parts().budget.summary();
  }
  std::filesystem::remove(path);
  EXPECT_TRUE(clearly_faster_than_embree(70.0, 100.0));
  EXPECT_FALSE(clearly_faster_than_embree(90.0, 100.0));  // a near-tie goes to Embree
  EXPECT_FALSE(clearly_faster_than_embree(0.0, 100.0));   // not timed
  EXPECT_TRUE(not_slower_than_embree(90.0, 100.0));        // along strokes, after a clear win at random
  EXPECT_FALSE(not_slower_than_embree(101.0, 100.0));
}

} // namespace
} // namespace hb
