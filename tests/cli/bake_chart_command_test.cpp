// The default bake's query times end to end: `bake --json` holds a query time for
// every raw sampling the bake tried, the box file keeps them (`info`, `info --json`), and the
// report's first chart carries the raw samplings beside the default bake and exact.
#include "mesh/generators.h"
#include "mesh/mesh_io.h"
#include "run_cli.h"
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>
#include <filesystem>
#include <fstream>
#include <unistd.h>

namespace {

namespace fs = std::filesystem;

class BakeChartCommandTest : public ::testing::Test {
protected:
  static void SetUpTestSuite() {
    dir_ = fs::temp_directory_path() / ("hb_bake_chart_test_" + std::to_string(::getpid()));
    fs::create_directories(dir_);
    hb::BumpySphereOptions o;
    o.radius = 50.f;
    o.subdivisions = 3;  // 1,280 triangles
    hb::write_mesh(hb::make_bumpy_sphere(o), (dir_ / "bumpy.off").string());
  }
  static void TearDownTestSuite() { fs::remove_all(dir_); }
  static std::string path(const std::string& name) { return (dir_ / name).string(); }
  static hb::test::CommandResult run(const std::string& args) { return hb::test::run_cli(args, dir_.string()); }
  static fs::path dir_;
};
fs::path BakeChartCommandTest::dir_;

} // namespace

TEST_F(BakeChartCommandTest, EveryRawSamplingTheBakeTriedHasItsQueryTimeInBakeJsonAndInfo) {
  const auto bake = run("bake " + path("bumpy.off") + " -o " + path("bumpy.hbox") + " --cache none --json");
  ASSERT_EQ(bake.code, 0) << bake.err;
  const auto b = nlohmann::json::parse(bake.out)["budget"];
  ASSERT_FALSE(b["raw_tried"].empty()) << b;
  for (const auto& t : b["raw_tried"]) {
    EXPECT_GT(t["box_ns"].get<double>(), 0.0) << t;  // timed, whatever its outcome
    EXPECT_GT(t["exact_ns"].get<double>(), 0.0) << t;
  }
  EXPECT_GT(b["answer_ns"].get<double>(), 0.0) << b;
  EXPECT_GT(b["exact_ns"].get<double>(), 0.0) << b;
  // The file keeps them: info reads the same times back.
  const auto info = run("info " + path("bumpy.hbox") + " --json");
  ASSERT_EQ(info.code, 0) << info.err;
  const auto r = nlohmann::json::parse(info.out)["budget_report"];
  ASSERT_EQ(r["raw_tried"].size(), b["raw_tried"].size());
  for (std::size_t i = 0; i < r["raw_tried"].size(); ++i) {
    EXPECT_NEAR(r["raw_tried"][i]["box_ns"].get<double>(), b["raw_tried"][i]["box_ns"].get<double>(), 1e-3);
    EXPECT_NEAR(r["raw_tried"][i]["exact_ns"].get<double>(), b["raw_tried"][i]["exact_ns"].get<double>(), 1e-3);
  }
  EXPECT_NEAR(r["answer_ns"].get<double>(), b["answer_ns"].get<double>(), 1e-3);
  const auto text = run("info " + path("bumpy.hbox"));
  ASSERT_EQ(text.code, 0) << text.err;
  EXPECT_NE(text.out.find("raw m16 n8 "), std::string::npos) << text.out;
  EXPECT_NE(text.out.find(" ns a query against exact's "), std::string::npos) << text.out;
}

TEST_F(BakeChartCommandTest, ReportOfTheDefaultBakeChartsTheRawSamplingsItTried) {
  const auto rep = run("report " + path("bumpy.off") + " -o " + path("rep") +
                       " --samples 2000 --rounds 1 --sweep none --field probes=0 --cache none");
  ASSERT_EQ(rep.code, 0) << rep.err;
  std::ifstream in(path("rep/summary.json"));
  const auto s = nlohmann::json::parse(in);
  const auto& rows = s["sweep"];
  ASSERT_FALSE(rows.empty());
  // The box itself stays the last row, named as the default bake.
  EXPECT_EQ(rows.back()["label"].get<std::string>().rfind("default bake: ", 0), 0u) << rows.back();
  bool exact = false;
  std::size_t raw = 0;
  for (const auto& row : rows) {
    exact = exact || row["method"] == "exact_embree";
    if (!row["tried_by_the_bake"].get<bool>()) continue;
    ++raw;
    EXPECT_EQ(row["label"].get<std::string>().rfind("raw m", 0), 0u) << row;
    EXPECT_GT(row["query_ns"].get<double>(), 0.0) << row;
    EXPECT_TRUE(row["contact_agreement"].is_null()) << row;  // the trial judges what a hand feels only
    EXPECT_FALSE(row["pareto"].get<bool>()) << row;
  }
  EXPECT_TRUE(exact);
  EXPECT_GE(raw, 1u);
  EXPECT_TRUE(fs::exists(path("rep/report.html")));
}
