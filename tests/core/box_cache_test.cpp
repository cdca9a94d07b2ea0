// The box cache: a key from the mesh hash and the whole recipe, one directory, size and clear.
#include "errors.h"
#include "haptic_box/box_cache.h"
#include "haptic_box/box_file.h"
#include "mesh/generators.h"
#include <gtest/gtest.h>
#include <cstdlib>
#include <filesystem>
#include <fstream>
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
  EXPECT_EQ(again.result.scene.table_bytes(), first.result.scene.table_bytes());
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
