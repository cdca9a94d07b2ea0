// The command line's small promises: `info` prints figures one way (thousands separators from
// 10,000 up for counts too, 4 significant digits, no raw doubles, a minimum before its maximum,
// the mesh hash in hex as the report), an unknown --unit is a usage error (exit 2), a misspelt
// option is named with the nearest real one, an
// unwritable output fails before the long work, and `sweep`'s rows on a terminal never share
// a line with its progress bar.
#include "mesh/generators.h"
#include "mesh/mesh_io.h"
#include "run_cli.h"
#include <gtest/gtest.h>
#include <chrono>
#include <filesystem>
#include <regex>
#include <sstream>

namespace fs = std::filesystem;
using hb::test::run_cli;

namespace {

struct Scratch {
  fs::path dir;
  std::string mesh;
  Scratch() {
    dir = fs::temp_directory_path() / ("hb_cli_figures_" + std::to_string(::getpid()) + "_" +
                                       ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::create_directories(dir);
    hb::BumpySphereOptions o;
    o.radius = 40.f;
    o.subdivisions = 3;
    mesh = (dir / "bumpy.off").string();
    hb::write_mesh(hb::make_bumpy_sphere(o), mesh);
  }
  ~Scratch() {
    std::error_code ec;
    fs::remove_all(dir, ec);
  }
};

}  // namespace

TEST(CliFiguresTest, InfoPrintsCountsAndFiguresOneWayWithTheHashInHexAndMinBeforeMax) {
  Scratch s;
  const auto r = run_cli("info " + s.mesh, s.dir.string());
  ASSERT_EQ(r.code, 0) << r.err;
  // 1,280 triangles would read "1280" (below 10,000), but 20,480 must carry its separator.
  EXPECT_NE(r.out.find("triangles: 1280\n"), std::string::npos) << r.out;
  const auto min = r.out.find("bounds_min:"), max = r.out.find("bounds_max:");
  ASSERT_NE(min, std::string::npos);
  ASSERT_NE(max, std::string::npos);
  EXPECT_LT(min, max);
  EXPECT_TRUE(std::regex_search(r.out, std::regex("mesh_hash: [0-9a-f]{16}\n"))) << r.out;
  // No raw double anywhere: at most 4 significant digits after a decimal point.
  EXPECT_FALSE(std::regex_search(r.out, std::regex("[0-9]\\.[0-9]{6,}"))) << r.out;

  const std::string phantom = std::string(HB_DATASETS_DIR) + "/generated/ct_phantom.nii.gz";
  if (!fs::exists(phantom)) GTEST_SKIP() << "run datasets/fetch.sh build/datasets/hb_generate_datasets";
  const auto v = run_cli("info " + phantom, s.dir.string());
  ASSERT_EQ(v.code, 0) << v.err;
  EXPECT_NE(v.out.find("triangles: 51,164"), std::string::npos) << v.out;
  EXPECT_NE(v.out.find("voxels: 553,000"), std::string::npos) << v.out;
  EXPECT_FALSE(std::regex_search(v.out + v.err, std::regex("[0-9]\\.[0-9]{6,}"))) << v.out << v.err;
  EXPECT_NE(v.err.find("spacing 0.9 x 0.9 x 1.4 mm"), std::string::npos) << v.err;
  // A box file's source hash reads as the report's: 16 hex digits.
  const std::string box = (s.dir / "b.hbox").string();
  ASSERT_EQ(run_cli("bake " + s.mesh + " -m 8 -n 4 -o " + box, s.dir.string()).code, 0);
  const auto b = run_cli("info " + box, s.dir.string());
  EXPECT_TRUE(std::regex_search(b.out, std::regex("source_mesh_hash: [0-9a-f]{16}\n"))) << b.out;
}

TEST(CliFiguresTest, AnUnknownUnitIsAUsageError) {
  Scratch s;
  const auto r = run_cli("info " + s.mesh + " --unit furlong", s.dir.string());
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.err.find("unknown unit 'furlong'"), std::string::npos) << r.err;
  EXPECT_EQ(run_cli("info " + s.mesh + " --unit inch", s.dir.string()).code, 0);
}

TEST(CliFiguresTest, AMisspeltOptionIsNamedWithTheNearestRealOne) {
  Scratch s;
  const auto r = run_cli("bake " + s.mesh + " --ouput x.hbox", s.dir.string());
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.err.find("unknown option --ouput for 'bake' (did you mean --output?)"), std::string::npos) << r.err;
  const auto e = run_cli("eval x.hbox " + s.mesh + " --sampels=100", s.dir.string());
  EXPECT_EQ(e.code, 2);
  EXPECT_NE(e.err.find("did you mean --samples?"), std::string::npos) << e.err;
  // A box file under another name is written, with a warning that says so.
  const auto txt = run_cli("bake " + s.mesh + " -m 8 -n 4 -o x.txt", s.dir.string());
  EXPECT_EQ(txt.code, 0) << txt.err;
  EXPECT_NE(txt.err.find("x.txt: a box file is written under a name that does not end in .hbox"), std::string::npos)
      << txt.err;
  // Nothing near: the option is still named, without a guess.
  const auto far = run_cli("info " + s.mesh + " --zzzzzzzz", s.dir.string());
  EXPECT_EQ(far.code, 2);
  EXPECT_NE(far.err.find("unknown option --zzzzzzzz for 'info'"), std::string::npos) << far.err;
  EXPECT_EQ(far.err.find("did you mean"), std::string::npos) << far.err;
}

TEST(CliFiguresTest, AnUnwritableOutputFailsBeforeTheBake) {
  Scratch s;
  const auto start = std::chrono::steady_clock::now();
  const auto r = run_cli("bake " + s.mesh + " -o " + (s.dir / "no-such-folder" / "x.hbox").string(), s.dir.string());
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  EXPECT_EQ(r.code, 1);
  EXPECT_NE(r.err.find("no-such-folder"), std::string::npos) << r.err;
  EXPECT_LT(seconds, 2.0) << "the default bake ran before the output was checked";
  // A folder given as the box file, and a report into a file rather than a folder.
  EXPECT_NE(run_cli("bake " + s.mesh + " -o " + s.dir.string(), s.dir.string()).err.find("is a folder"), std::string::npos);
  const auto rep = run_cli("report " + s.mesh + " -o " + s.mesh, s.dir.string());
  EXPECT_EQ(rep.code, 1);
  EXPECT_NE(rep.err.find("is a file"), std::string::npos) << rep.err;
  EXPECT_FALSE(fs::exists(s.dir / "no-such-folder"));
}

TEST(CliFiguresTest, SweepRowsOnATerminalNeverShareALineWithTheProgressBar) {
  Scratch s;
  // `script` gives the command a terminal (the bar draws only on one).
  const std::string inner = std::string(HB_CLI_PATH) + " sweep " + s.mesh + " -m 8 -n 4 --samples 300 --no-default-bake";
  const std::string cmd = "env -u DISPLAY XDG_CACHE_HOME=" + (s.dir / "cache").string() + " script -qec '" + inner + "' /dev/null";
  FILE* pipe = popen(cmd.c_str(), "r");
  ASSERT_NE(pipe, nullptr);
  std::string out;
  char buf[4096];
  std::size_t n;
  while ((n = fread(buf, 1, sizeof buf, pipe)) > 0) out.append(buf, n);
  ASSERT_EQ(pclose(pipe), 0) << out;
  ASSERT_NE(out.find("sweep ["), std::string::npos) << "no progress bar on the terminal";
  std::istringstream lines(out);
  std::string line;
  int rows = 0;
  while (std::getline(lines, line)) {
    if (!line.empty() && line.back() == '\r') line.pop_back();
    // What the terminal shows of this line: the text after the last carriage return.
    std::string shown = line.substr(line.rfind('\r') == std::string::npos ? 0 : line.rfind('\r') + 1);
    if (shown.rfind("\033[K", 0) == 0) shown = shown.substr(3);
    const bool row = shown.find("haptic_box") != std::string::npos || shown.find("exact_embree") != std::string::npos;
    if (!row) continue;
    ++rows;
    EXPECT_EQ(shown.find("sweep ["), std::string::npos) << "row after the bar: " << shown;
    EXPECT_TRUE(shown.rfind("haptic_box", 0) == 0 || shown.rfind("exact_embree", 0) == 0) << shown;
  }
  EXPECT_GE(rows, 2);
}
