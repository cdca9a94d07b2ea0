// `hapticbox bake`'s help states the defaults a bake really uses (each read back from the help
// and compared with hb::default_recipe() and the one-sampling BakeRecipe), and a bake writes its
// box file once: a fresh bake is serialised into the box cache and -o is a copy of that entry.
#include "codec/codec.h"
#include "mesh/generators.h"
#include "mesh/mesh_io.h"
#include "recipe/bake_recipe.h"
#include "run_cli.h"
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <regex>
#include <string>
#include <unistd.h>

namespace {

namespace fs = std::filesystem;

class BakeDefaultsTest : public ::testing::Test {
protected:
  static void SetUpTestSuite() {
    dir_ = fs::temp_directory_path() / ("hb_bake_defaults_test_" + std::to_string(::getpid()));
    fs::create_directories(dir_);
    hb::write_mesh(hb::make_sphere(10.f, 4), path("sphere.off"));
  }
  static void TearDownTestSuite() { fs::remove_all(dir_); }
  static hb::test::CommandResult run(const std::string& args) { return hb::test::run_cli(args, dir_.string()); }
  static std::string path(const std::string& name) { return (dir_ / name).string(); }
  static std::string slurp(const std::string& p) {
    std::ifstream in(p, std::ios::binary);
    return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
  }
  static fs::path dir_;
};
fs::path BakeDefaultsTest::dir_;

// The help with its line breaks and indentation folded into single spaces.
std::string bake_help() {
  const hb::test::CommandResult r = hb::test::run_cli("bake --help", fs::temp_directory_path().string());
  EXPECT_EQ(r.code, 0) << r.err;
  return std::regex_replace(r.out, std::regex("\\s+"), " ");
}

// The text `pattern`'s first group captures in `help` (fails the test when absent).
std::string captured(const std::string& help, const std::string& pattern) {
  std::smatch m;
  if (!std::regex_search(help, m, std::regex(pattern))) {
    ADD_FAILURE() << "bake --help does not say: " << pattern;
    return "nan";
  }
  return m[1].str();
}

void expect_number(const std::string& help, const std::string& pattern, double value) {
  const std::string text = captured(help, pattern);
  EXPECT_NEAR(std::stod(text), value, 1e-5 * std::max(1.0, std::abs(value))) << pattern << " printed " << text;
}

TEST_F(BakeDefaultsTest, HelpPrintsTheDefaultBakesOwnDefaults) {
  const std::string help = bake_help();
  const hb::BakeRecipe dr = hb::default_recipe(), one;
  const hb::ErrorBudget& b = dr.budget.budget;
  expect_number(help, R"(felt=PERCENT \(default ([-0-9.e+]+))", b.perceptible * 100.0);
  EXPECT_EQ(captured(help, R"(raw=on\|off \(default (on|off))"), b.raw ? "on" : "off");
  expect_number(help, R"(memory=MB \(its cap, default ([-0-9.e+]+))", b.raw_memory_bytes / 1e6);
  expect_number(help, R"(simplify-above=N triangles \(default ([0-9]+))", double(dr.budget.simplify_above));
  EXPECT_EQ(captured(help, R"(simplify=on\|off \(default (on|off))"), dr.budget.simplify ? "on" : "off");
  expect_number(help, R"(deviation=F of the diagonal, default ([-0-9.e+]+))", dr.budget.simplify_deviation);
  expect_number(help, R"(a sixteenth of the force threshold, ([-0-9.e+]+))", hb::simplification_bound(b));
  expect_number(help, R"(shading-map=S, default ([-0-9]+))", dr.budget.shading_map_side);
  // --pieces: the default bake's value first (and one sampling's where it differs).
  expect_number(help, R"(probability of a piece; default ([-0-9.e+]+))", dr.pieces.automatic.threshold);
  if (one.pieces.automatic.threshold != dr.pieces.automatic.threshold)
    expect_number(help, R"(probability of a piece; default [-0-9.e+]+ for the default bake, ([-0-9.e+]+) for one sampling)",
                  one.pieces.automatic.threshold);
  expect_number(help, R"(most pieces; default ([0-9]+))", dr.pieces.automatic.max_pieces);
  expect_number(help, R"(seam-rings=R \(least rings of seam triangles neighbouring pieces share; default ([0-9]+))",
                dr.seams.rings);
  expect_number(help, R"(seam-cells=C \(seam overlap, position cells; default ([-0-9.e+]+))", dr.seams.cells);
  expect_number(help, R"(fraction of its diagonal; default ([-0-9.e+]+))", dr.options.obb.padding);
  // --codec, --cell and the one-sampling options.
  EXPECT_EQ(captured(help, R"(block \(ours\) \(default (\w+) for the default bake, \w+ for one sampling\))"), hb::codec_name(dr.codec.codec));
  EXPECT_EQ(captured(help, R"(block \(ours\) \(default \w+ for the default bake, (\w+) for one sampling\))"), hb::codec_name(one.codec.codec));
  expect_number(help, R"(box diagonal, default ([-0-9.e+]+))", dr.codec.max_error);
  expect_number(help, R"(coordinate, 6-14; default ([0-9]+))", dr.codec.normal_bits);
  expect_number(help, R"(takes only max-m, default ([0-9]+))", dr.options.density.max_m);
  expect_number(help, R"(Position points per PBB face edge \(default ([0-9]+))", one.options.params.m);
  expect_number(help, R"(Directional points per sub-block face edge \(default ([0-9]+))", one.options.params.n);
}

// A fresh bake writes the scene once, into the cache, and -o is a copy of that entry; without a
// cache the scene is saved to -o; from the cache, -o is copied again; -o naming the entry
// itself writes nothing.
TEST_F(BakeDefaultsTest, AFreshBakeIsWrittenOnceAndTheOutputIsACopyOfTheCacheEntry) {
  const std::string cache = path("cache"), bake = "bake " + path("sphere.off") + " -m 8 -n 6 --json";
  const hb::test::CommandResult fresh = run(bake + " -o " + path("fresh.hbox") + " --cache " + cache);
  ASSERT_EQ(fresh.code, 0) << fresh.err;
  const nlohmann::json f = nlohmann::json::parse(fresh.out);
  EXPECT_FALSE(f["from_cache"].get<bool>());
  EXPECT_EQ(f["output_written"], "copy of the cache entry");
  const std::string entry = f["cache_path"].get<std::string>();
  ASSERT_TRUE(fs::exists(entry));
  EXPECT_EQ(slurp(entry), slurp(path("fresh.hbox")));
  EXPECT_FALSE(fs::exists(path("fresh.hbox.tmp")));

  const hb::test::CommandResult cached = run(bake + " -o " + path("again.hbox") + " --cache " + cache);
  ASSERT_EQ(cached.code, 0) << cached.err;
  const nlohmann::json c = nlohmann::json::parse(cached.out);
  EXPECT_TRUE(c["from_cache"].get<bool>());
  EXPECT_EQ(c["output_written"], "copy of the cache entry");
  EXPECT_EQ(slurp(path("again.hbox")), slurp(entry));

  const hb::test::CommandResult itself = run(bake + " -o " + entry + " --cache " + cache);
  ASSERT_EQ(itself.code, 0) << itself.err;
  EXPECT_EQ(nlohmann::json::parse(itself.out)["output_written"], "entry");

  const hb::test::CommandResult uncached = run(bake + " -o " + path("plain.hbox") + " --cache none");
  ASSERT_EQ(uncached.code, 0) << uncached.err;
  EXPECT_EQ(nlohmann::json::parse(uncached.out)["output_written"], "saved");
  EXPECT_EQ(slurp(path("plain.hbox")), slurp(entry));
}

} // namespace
