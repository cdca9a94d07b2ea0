// Tools with volume end to end: `query --tool`, `bench --tool`, `eval --tool` and
// `stability --tool` on a refined sphere of radius 10 (the real binary, no display).
#include "mesh/generators.h"
#include "mesh/mesh_io.h"
#include "run_cli.h"
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <unistd.h>

namespace {

namespace fs = std::filesystem;

class ToolCommandsTest : public ::testing::Test {
protected:
  static void SetUpTestSuite() {
    dir_ = fs::temp_directory_path() / ("hb_tool_test_" + std::to_string(::getpid()));
    fs::create_directories(dir_);
    hb::write_mesh(hb::make_sphere(10.f, 4), path("sphere.off"));
    ASSERT_EQ(run("bake " + path("sphere.off") + " -o " + path("sphere.hbox") + " -m 12 -n 6 --refine").code, 0);
  }
  static void TearDownTestSuite() { fs::remove_all(dir_); }
  static hb::test::CommandResult run(const std::string& args) { return hb::test::run_cli(args, dir_.string()); }
  static std::string path(const std::string& name) { return (dir_ / name).string(); }
  static fs::path dir_;
};
fs::path ToolCommandsTest::dir_;

std::vector<std::vector<double>> read_rows(const std::string& csv, std::string& header) {
  std::istringstream in(csv);
  std::getline(in, header);
  std::vector<std::vector<double>> rows;
  std::string line;
  while (std::getline(in, line)) {
    std::vector<double> row;
    std::stringstream cells(line);
    std::string cell;
    while (std::getline(cells, cell, ',')) row.push_back(std::atof(cell.c_str()));
    rows.push_back(row);
  }
  return rows;
}

} // namespace

TEST_F(ToolCommandsTest, QueryToolAnswersEachPoseWithForceTorqueAndContactsBesideExact) {
  // The sphere's diagonal 34.6 units at 80 mm: a 2 mm burr is 0.866 units. Poses above the
  // pole, from clear to 0.2 units in.
  const double units_per_mm = std::sqrt(3.0) * 20.0 / 80.0;
  const double r = 2.0 * units_per_mm;
  std::ofstream poses(path("poses.csv"));
  poses << "x,y,z,qw,qx,qy,qz\n";
  for (double d : {-0.1, 0.05, 0.1, 0.2}) poses << "0,0," << 10.0 + r - d << ",1,0,0,0\n";
  poses.close();
  const auto q = run("query " + path("sphere.hbox") + " --tool sphere,radius-mm=2,points=1000 --poses " +
                     path("poses.csv") + " --exact " + path("sphere.off"));
  ASSERT_EQ(q.code, 0) << q.err;
  std::string header;
  const auto rows = read_rows(q.out, header);
  EXPECT_EQ(header, "fx,fy,fz,tx,ty,tz,contacts,exact_fx,exact_fy,exact_fz,exact_tx,exact_ty,exact_tz,exact_contacts,"
                    "perceptible");
  ASSERT_EQ(rows.size(), 4u);
  EXPECT_EQ(rows[0][6], 0.0);  // clear of the surface: no contact, no force
  EXPECT_EQ(rows[0][2], 0.0);
  for (std::size_t k = 1; k < 4; ++k) {
    EXPECT_GT(rows[k][6], 0.0);
    EXPECT_GT(rows[k][2], rows[k - 1][2]);  // deeper, harder
    EXPECT_NEAR(rows[k][2], rows[k][9], 0.04);  // box and exact agree within what a hand feels
    EXPECT_NEAR(rows[k][0], 0.0, 0.01);  // the lattice is not symmetric: a few mN sideways
  }
  // 0.2 units in is 0.8 mm at the device: k d = 1.2 N (a sphere on a sphere: a little less).
  EXPECT_NEAR(rows[3][9], 1500.0 * 0.2 / units_per_mm * 1e-3, 0.1);
}

TEST_F(ToolCommandsTest, QueryToolRefusesMissingPosesAndBadSpecsWithTheCause) {
  const auto no_poses = run("query " + path("sphere.hbox") + " --tool sphere,radius-mm=2");
  EXPECT_EQ(no_poses.code, 2);
  EXPECT_NE(no_poses.err.find("--poses"), std::string::npos);
  std::ofstream(path("p.csv")) << "x,y,z\n0,0,12\n";
  const auto bad = run("query " + path("sphere.hbox") + " --tool cube,points=10 --poses " + path("p.csv"));
  EXPECT_NE(bad.code, 0);
  EXPECT_NE(bad.err.find("unknown tool 'cube'"), std::string::npos);
  std::ofstream(path("bad.csv")) << "x,y\n0,0\n";
  const auto cols = run("query " + path("sphere.hbox") + " --tool sphere --poses " + path("bad.csv"));
  EXPECT_NE(cols.code, 0);
  EXPECT_NE(cols.err.find("no column 'z'"), std::string::npos);
}

TEST_F(ToolCommandsTest, BenchEvalAndStabilityToolPrintTheirDocumentedFigures) {
  const auto bench = run("bench " + path("sphere.hbox") + " " + path("sphere.off") +
                         " --tool sphere,radius-mm=2,points=500 --tool-slides 3 --tool-ticks 50 --rounds 1 --json");
  ASSERT_EQ(bench.code, 0) << bench.err;
  const auto b = nlohmann::json::parse(bench.out);
  for (const char* key : {"tool_points", "box_tool_tick_p50_us", "box_tool_tick_p99_us", "exact_tool_tick_p50_us",
                          "exact_tool_tick_p99_us", "sdf_tool_tick_p99_us", "tool_perceptible_tick_share",
                          "sdf_perceptible_tick_share"})
    EXPECT_TRUE(b.contains(key)) << key;
  EXPECT_EQ(b["tool_points"], 500);
  EXPECT_GT(b["tool_contact_ticks"].get<double>(), 100.0);
  EXPECT_GE(b["tool_perceptible_tick_share"].get<double>(), 0.0);

  const auto eval = run("eval " + path("sphere.hbox") + " " + path("sphere.off") +
                        " --samples 500 --tool capsule,radius-mm=1,length-mm=8,points=500 --tool-slides 3 --json");
  ASSERT_EQ(eval.code, 0) << eval.err;
  const auto e = nlohmann::json::parse(eval.out);
  ASSERT_TRUE(e.contains("tool"));
  EXPECT_GT(e["tool"]["tool_contact_ticks"].get<double>(), 100.0);

}

TEST_F(ToolCommandsTest, StabilityToolPassesTheDefaultBakeAndCatchesACoarseBoxsGhosts) {
  ASSERT_EQ(run("bake " + path("sphere.off") + " -o " + path("default.hbox")).code, 0);
  const auto st = run("stability " + path("default.hbox") + " " + path("sphere.off") +
                      " --tool sphere,radius-mm=2,points=300 --json");
  ASSERT_EQ(st.code, 0) << st.err;
  const auto s = nlohmann::json::parse(st.out);
  ASSERT_EQ(s["tests"].size(), 14u);
  for (const auto& t : s["tests"]) {
    EXPECT_TRUE(t["pass"].get<bool>()) << t["test"] << " " << t["method"];
    EXPECT_EQ(t["pop_throughs"], 0) << t["test"];
    EXPECT_EQ(t["ghost_ticks"], 0) << t["test"];
  }
  // The refined m12 n6 box's blends stand off the sphere: its slides render ghost forces, which
  // exact never does; --strict makes that the exit code.
  const auto coarse = run("stability " + path("sphere.hbox") + " " + path("sphere.off") +
                          " --tool sphere,radius-mm=2,points=300 --json --strict");
  EXPECT_EQ(coarse.code, 1);
  const auto c = nlohmann::json::parse(coarse.out);
  EXPECT_GT(c["box_failed_where_exact_passed"].get<int>(), 0);
  for (const auto& t : c["tests"])
    if (t["method"] == "exact") EXPECT_EQ(t["ghost_ticks"], 0) << t["test"];
}
