// The box cache: a key from the mesh hash and the whole recipe, one directory, size and clear.
#include "errors.h"
#include "recipe/box_cache.h"
#include "store/box_file.h"
#include "mesh/generators.h"
#include <gtest/gtest.h>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <vector>
#include <unistd.h>

namespace hb {
namespace {

std::string temp_dir(const std::string& name) {
  return testing::TempDir() + "hb_cache_" + name + "_" + std::to_string(::getpid());
}

TEST(BoxCacheTest, KeyCoversTheWholeRecipe) {
  const BakeRecipe base;
  const std::uint64_t k = recipe_key(base);
  EXPECT_EQ(recipe_key(base), k);
  BakeRecipe r = base;
  r.options.progress = [](double) { return true; };  // not part of the key
  EXPECT_EQ(recipe_key(r), k);
  r = base; r.options.obb.padding = 0.02f;  // left out by the old cache names
  EXPECT_NE(recipe_key(r), k);
  r = base; r.options.params.m = 31;
  EXPECT_NE(recipe_key(r), k);
  r = base; r.options.refine = true;
  EXPECT_NE(recipe_key(r), k);
  r = base; r.options.density.cell = 0.01f;
  EXPECT_NE(recipe_key(r), k);
  r = base; r.codec.codec = CodecId::block;
  const std::uint64_t block = recipe_key(r);
  EXPECT_NE(block, k);
  r.codec.max_error = 0.001f;
  EXPECT_NE(recipe_key(r), block);
  r = base; r.pieces.kind = PiecesRecipe::Kind::automatic;
  const std::uint64_t automatic = recipe_key(r);
  EXPECT_NE(automatic, k);
  r.pieces.automatic.threshold = 0.001;
  EXPECT_NE(recipe_key(r), automatic);
  r = base; r.seams.cells = 2.f;
  EXPECT_NE(recipe_key(r), k);
  r = base; r.pieces.kind = PiecesRecipe::Kind::given; r.pieces.given = {0, 1, 1};
  const std::uint64_t given = recipe_key(r);
  r.pieces.given = {0, 0, 1};
  EXPECT_NE(recipe_key(r), given);
  r = base; r.pieces.kind = PiecesRecipe::Kind::file; r.pieces.file = temp_dir("missing.txt");
  EXPECT_THROW(recipe_key(r), IoError);
}

// Every recipe field that changes the baked scene gives its own key (one field changed at a
// time from the defaults, automatic pieces and a codec so their options count); what does not
// change the scene (progress, the ranks) leaves the key alone.
TEST(BoxCacheTest, KeyChangesWithEveryFieldThatChangesTheScene) {
  BakeRecipe base;
  base.pieces.kind = PiecesRecipe::Kind::automatic;
  base.codec.codec = CodecId::block;
  std::vector<std::pair<std::string, BakeRecipe>> variants;
  const auto vary = [&](const std::string& name, auto change) {
    BakeRecipe r = base;
    change(r);
    variants.emplace_back(name, r);
  };
  vary("defaults", [](BakeRecipe&) {});
  vary("m", [](BakeRecipe& r) { r.options.params.m = 31; });
  vary("n", [](BakeRecipe& r) { r.options.params.n = 15; });
  vary("density.cell", [](BakeRecipe& r) { r.options.density.cell = 0.01f; });
  vary("density.min_m", [](BakeRecipe& r) { r.options.density.min_m = 9; });
  vary("density.max_m", [](BakeRecipe& r) { r.options.density.max_m = 63; });
  vary("obb.padding", [](BakeRecipe& r) { r.options.obb.padding = 0.02f; });
  vary("obb.refine_iterations", [](BakeRecipe& r) { r.options.obb.refine_iterations = 0; });
  vary("refine", [](BakeRecipe& r) { r.options.refine = true; });
  vary("scene_grid", [](BakeRecipe& r) { r.options.scene_grid = false; });
  vary("grid.cell", [](BakeRecipe& r) { r.options.grid.cell = 1.f / 64.f; });
  vary("grid.max_cells", [](BakeRecipe& r) { r.options.grid.max_cells = 1000; });
  vary("automatic.threshold", [](BakeRecipe& r) { r.pieces.automatic.threshold = 0.001; });
  vary("automatic.min_area_fraction", [](BakeRecipe& r) { r.pieces.automatic.min_area_fraction = 0.01; });
  vary("automatic.max_pieces", [](BakeRecipe& r) { r.pieces.automatic.max_pieces = 8; });
  vary("automatic.leaves", [](BakeRecipe& r) { r.pieces.automatic.leaves = 512; });
  vary("automatic.lines", [](BakeRecipe& r) { r.pieces.automatic.lines = 100000; });
  vary("automatic.seed", [](BakeRecipe& r) { r.pieces.automatic.seed = 2; });
  vary("pieces none", [](BakeRecipe& r) { r.pieces.kind = PiecesRecipe::Kind::none; });
  vary("seams.rings", [](BakeRecipe& r) { r.seams.rings = 2; });
  vary("seams.cells", [](BakeRecipe& r) { r.seams.cells = 2.f; });
  vary("codec", [](BakeRecipe& r) { r.codec.codec = CodecId::haar; });
  vary("codec.max_error", [](BakeRecipe& r) { r.codec.max_error = 0.001f; });
  vary("codec.ratio", [](BakeRecipe& r) { r.codec.ratio = 20.f; });
  vary("codec.normal_bits", [](BakeRecipe& r) { r.codec.normal_bits = 10; });
  vary("codec none", [](BakeRecipe& r) { r.codec.codec = CodecId::none; });
  vary("budget", [](BakeRecipe& r) { r.budget.enabled = true; });
  vary("budget.surface_tolerance", [](BakeRecipe& r) {
    r.budget.enabled = true;
    r.budget.surface_tolerance = 0.002;
  });
  vary("budget without the surface check", [](BakeRecipe& r) {
    r.budget.enabled = true;
    r.budget.surface_tolerance = 0;
  });
  std::map<std::uint64_t, std::string> seen;
  for (const auto& [name, r] : variants) {
    const auto [at, fresh] = seen.emplace(recipe_key(r), name);
    EXPECT_TRUE(fresh) << name << " has the key of " << at->second;
  }
  BakeRecipe same = base;
  same.options.progress = [](double) { return true; };
  same.pieces.automatic.progress = [](double) { return true; };
  same.options.scene_on_every_rank = true;
  EXPECT_EQ(recipe_key(same), recipe_key(base));
  // Without a scene grid its options change nothing.
  BakeRecipe a = base, b = base;
  a.options.scene_grid = b.options.scene_grid = false;
  b.options.grid.cell = 1.f / 64.f;
  EXPECT_EQ(recipe_key(a), recipe_key(b));
}

TEST(BoxCacheTest, StoresLoadsSizesAndClears) {
  const TriangleMesh sphere = make_sphere(1.f, 2);
  const BoxCache cache(temp_dir("store"));
  BakeRecipe recipe;
  recipe.options.params = {4, 2};
  const SourceInfo source{"sphere", 0xabc, sphere.triangle_count(), sphere.bounds().diagonal()};
  EXPECT_EQ(cache.usage().files, 0u);
  const CachedBake first = bake_cached(sphere, recipe, source, &cache);
  EXPECT_FALSE(first.from_cache);
  EXPECT_TRUE(first.warning.empty());
  EXPECT_EQ(first.path, cache.path_for(0xabc, recipe));
  const BoxCacheUsage u = cache.usage();
  EXPECT_EQ(u.files, 1u);
  EXPECT_EQ(u.bytes, std::filesystem::file_size(first.path));
  const CachedBake again = bake_cached(sphere, recipe, source, &cache);
  EXPECT_TRUE(again.from_cache);
  EXPECT_EQ(again.result.stats.rays, 0u);
  EXPECT_EQ(again.result.scene.bytes().tables, first.result.scene.bytes().tables);
  // Another mesh hash or padding: another entry.
  EXPECT_FALSE(cache.load(0xabd, recipe).has_value());
  recipe.options.obb.padding = 0.05f;
  EXPECT_FALSE(cache.load(0xabc, recipe).has_value());
  // No mesh hash: a plain bake, nothing stored.
  const CachedBake plain = bake_cached(sphere, recipe, SourceInfo{}, &cache);
  EXPECT_FALSE(plain.from_cache);
  EXPECT_TRUE(plain.path.empty());
  EXPECT_EQ(cache.usage().files, 1u);
  // Other files of the directory are left alone by clear().
  std::ofstream(cache.dir() + "/note.txt") << "keep";
  const BoxCacheUsage removed = cache.clear();
  EXPECT_EQ(removed.files, 1u);
  EXPECT_EQ(removed.bytes, u.bytes);
  EXPECT_EQ(cache.usage().files, 0u);
  EXPECT_TRUE(std::filesystem::exists(cache.dir() + "/note.txt"));
  std::filesystem::remove_all(cache.dir());
}

TEST(BoxCacheTest, CorruptEntryIsRebakedAndReplaced) {
  const TriangleMesh sphere = make_sphere(1.f, 2);
  const BoxCache cache(temp_dir("corrupt"));
  BakeRecipe recipe;
  recipe.options.params = {4, 2};
  const SourceInfo source{"sphere", 0x5, sphere.triangle_count(), sphere.bounds().diagonal()};
  const std::string path = bake_cached(sphere, recipe, source, &cache).path;
  std::filesystem::resize_file(path, 100);
  EXPECT_FALSE(cache.load(0x5, recipe).has_value());
  const CachedBake rebaked = bake_cached(sphere, recipe, source, &cache);
  EXPECT_FALSE(rebaked.from_cache);
  EXPECT_NO_THROW(load_box_file(path, {true, false}));
  std::filesystem::remove_all(cache.dir());
}

TEST(BoxCacheTest, DirectoryFollowsXdg) {
  const char* old_xdg = std::getenv("XDG_CACHE_HOME");
  const std::string saved = old_xdg ? old_xdg : "";
  const char* old_home = std::getenv("HOME");
  const std::string saved_home = old_home ? old_home : "";
  ::setenv("XDG_CACHE_HOME", "/somewhere/cache", 1);
  EXPECT_EQ(default_box_cache_dir(), "/somewhere/cache/hapticbox/boxes");
  ::setenv("XDG_CACHE_HOME", "relative", 1);  // the spec ignores relative paths
  ::setenv("HOME", "/home/someone", 1);
  EXPECT_EQ(default_box_cache_dir(), "/home/someone/.cache/hapticbox/boxes");
  if (old_xdg) ::setenv("XDG_CACHE_HOME", saved.c_str(), 1); else ::unsetenv("XDG_CACHE_HOME");
  if (old_home) ::setenv("HOME", saved_home.c_str(), 1); else ::unsetenv("HOME");
}

} // namespace
} // namespace hb
