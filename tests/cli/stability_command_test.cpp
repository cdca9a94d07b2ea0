// `hapticbox stability` end to end (label `stability`): the real binary on a small sphere.
#include "mesh/generators.h"
#include "mesh/mesh_io.h"
#include "run_cli.h"
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>
#include <filesystem>
#include <unistd.h>

namespace {

namespace fs = std::filesystem;

class StabilityCommandTest : public ::testing::Test {
protected:
  static void SetUpTestSuite() {
    dir_ = fs::temp_directory_path() / ("hb_stability_test_" + std::to_string(::getpid()));
    fs::create_directories(dir_);
    hb::write_mesh(hb::make_sphere(10.f, 4), path("sphere.off"));
    ASSERT_EQ(run("bake " + path("sphere.off") + " -o " + path("sphere.hbox") + " -m 12 -n 6 --refine").code, 0);
  }
  static void TearDownTestSuite() { fs::remove_all(dir_); }
  static hb::test::CommandResult run(const std::string& args) { return hb::test::run_cli(args, dir_.string()); }
  static std::string path(const std::string& name) { return (dir_ / name).string(); }
  static fs::path dir_;
};
fs::path StabilityCommandTest::dir_;

} // namespace

TEST_F(StabilityCommandTest, JsonHasTheGateAndEveryFigureAsBoxExactAndVerdict) {
  const auto r = run("stability " + path("sphere.hbox") + " " + path("sphere.off") +
                     " --json --sites 3 --tests T2,T6,T7 --no-generated");
  ASSERT_EQ(r.code, 0) << r.err;
  const auto j = nlohmann::json::parse(r.out);
  EXPECT_TRUE(j.at("calibration_pass").get<bool>());
  EXPECT_EQ(j.at("device"), "falcon");
  EXPECT_EQ(j.at("depth_law"), "normal");
  ASSERT_FALSE(j.at("metrics").empty());
  for (const auto& m : j.at("metrics")) {
    for (const char* key : {"test", "scene", "metric", "box", "exact", "difference", "threshold", "verdict"})
      EXPECT_TRUE(m.contains(key)) << key;
    EXPECT_TRUE(m.at("test") == "T2" || m.at("test") == "T6" || m.at("test") == "T7");
  }
}

TEST_F(StabilityCommandTest, BadTestOrDeviceIsAUsageError) {
  EXPECT_EQ(run("stability " + path("sphere.hbox") + " " + path("sphere.off") + " --tests T9").code, 2);
  EXPECT_EQ(run("stability " + path("sphere.hbox") + " " + path("sphere.off") + " --device phantom").code, 2);
  const auto missing = run("stability " + path("nope.hbox") + " " + path("sphere.off"));
  EXPECT_EQ(missing.code, 1);
  EXPECT_NE(missing.err.find("nope.hbox"), std::string::npos);
}

TEST_F(StabilityCommandTest, TheTextOutputEndsWithItsVerdict) {
  const auto r = run("stability " + path("sphere.hbox") + " " + path("sphere.off") +
                     " --sites 3 --tests T2 --no-generated");
  ASSERT_EQ(r.code, 0) << r.err;
  const std::size_t gate = r.out.rfind("calibration gate: pass"), tests = r.out.rfind("tests: ");
  ASSERT_NE(gate, std::string::npos) << r.out;
  ASSERT_NE(tests, std::string::npos) << r.out;
  EXPECT_GT(tests, gate);
  // Nothing but the verdict's line after it.
  EXPECT_EQ(r.out.find('\n', tests), r.out.size() - 1) << r.out;
}
