// hapticbox under mpirun: 2 and 3 ranks (oversubscribed) against one process on the same
// input; the .hbox byte for byte, the JSON key for key (timings aside); a failing rank.
#include "mesh/generators.h"
#include "mesh/mesh_io.h"
#include "run_cli.h"
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>
#include <filesystem>
#include <fstream>
#include <set>
#include <unistd.h>

namespace {

namespace fs = std::filesystem;
using hb::test::CommandResult;

// Open MPI refuses root without --allow-run-as-root (CI runs as root); --oversubscribe lets 3
// ranks share 2 cores. Each rank gets one thread so the ranks do not fight over the cores.
const std::string kMpirun = std::string(HB_MPIRUN) + " --oversubscribe --allow-run-as-root -np ";

class MpiTest : public ::testing::Test {
protected:
  static void SetUpTestSuite() {
    dir_ = fs::temp_directory_path() / ("hb_mpi_test_" + std::to_string(::getpid()));
    fs::create_directories(dir_);
    const hb::TriangleMesh torus = hb::make_torus(10.f, 3.f, 48, 16);
    hb::write_mesh(torus, path("torus.off"));
    // Two pieces (the halves of the triangle list) so the scene has two boxes.
    std::ofstream pieces(path("torus_pieces.txt"));
    for (std::size_t t = 0; t < torus.triangle_count(); ++t) pieces << (t < torus.triangle_count() / 2 ? 0 : 1) << "\n";
  }
  static void TearDownTestSuite() { fs::remove_all(dir_); }
  static std::string path(const std::string& name) { return (dir_ / name).string(); }
  // One process: the binary as is.
  static CommandResult run(const std::string& args) { return hb::test::run_cli(args, dir_.string()); }
  // `ranks` ranks: `mpirun ... hapticbox args` (stderr in the scratch directory).
  static CommandResult run_mpi(int ranks, const std::string& args) {
    return run_shell(kMpirun + std::to_string(ranks) + " " + HB_CLI_PATH + " " + args);
  }
  static CommandResult run_shell(const std::string& command) {
    const std::string err_path = path("mpi_stderr.txt");
    CommandResult r;
    // A box cache of its own per call: every mpirun bakes across its ranks (never a cache hit).
    static int call = 0;
    const std::string cache = path("xdg-mpi-" + std::to_string(++call));
    FILE* pipe = popen(("env -u DISPLAY XDG_CACHE_HOME=" + cache + " " + command + " 2>" + err_path).c_str(), "r");
    if (!pipe) return r;
    char buf[4096];
    std::size_t n;
    while ((n = fread(buf, 1, sizeof buf, pipe)) > 0) r.out.append(buf, n);
    const int status = pclose(pipe);
    r.code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
    std::ifstream e(err_path);
    r.err.assign(std::istreambuf_iterator<char>(e), {});
    return r;
  }
  static std::string read(const std::string& name) {
    std::ifstream in(path(name), std::ios::binary);
    return std::string(std::istreambuf_iterator<char>(in), {});
  }
  static fs::path dir_;
};
fs::path MpiTest::dir_;

// Every key of `one` has the same value in `many`, except timings and the work split.
void expect_same_keys(const nlohmann::json& one, const nlohmann::json& many, const std::string& where = "") {
  static const std::set<std::string> kSkip = {"ranks", "seconds", "rays_per_second", "bake_seconds", "query_ns",
                                              "pareto", "rank_work", "load_balance", "bytes_sent",
                                              "bytes_sent_over_tables", "output", "cache_path"};
  ASSERT_EQ(one.type(), many.type()) << where;
  if (one.is_object()) {
    for (const auto& [key, value] : one.items()) {
      if (kSkip.count(key)) continue;
      ASSERT_TRUE(many.contains(key)) << where << "/" << key;
      expect_same_keys(value, many[key], where + "/" + key);
    }
  } else if (one.is_array()) {
    ASSERT_EQ(one.size(), many.size()) << where;
    for (std::size_t i = 0; i < one.size(); ++i) expect_same_keys(one[i], many[i], where + "/" + std::to_string(i));
  } else {
    EXPECT_EQ(one, many) << where;
  }
}

} // namespace

TEST_F(MpiTest, BakeOnTwoAndThreeRanksWritesTheBytesOfOneProcess) {
  const std::string recipe = " --pieces " + path("torus_pieces.txt") + " -m 10 -n 6 --refine --codec block --json";
  const CommandResult one = run("bake " + path("torus.off") + " -o " + path("one.hbox") + recipe);
  ASSERT_EQ(one.code, 0) << one.err;
  for (int ranks : {2, 3}) {
    const std::string out = "ranks" + std::to_string(ranks) + ".hbox";
    const CommandResult many = run_mpi(ranks, "bake " + path("torus.off") + " -o " + path(out) + recipe);
    ASSERT_EQ(many.code, 0) << many.err;
    EXPECT_EQ(read(out), read("one.hbox")) << ranks << " ranks";
    // One JSON document, from rank 0, stating the ranks and what each did.
    const auto j = nlohmann::json::parse(many.out);
    EXPECT_EQ(j["ranks"], ranks);
    // Baked across the ranks (each call has a cache of its own), under the same cache key.
    EXPECT_FALSE(j["from_cache"].get<bool>());
    EXPECT_EQ(fs::path(j["cache_path"].get<std::string>()).filename(),
              fs::path(nlohmann::json::parse(one.out)["cache_path"].get<std::string>()).filename());
    ASSERT_EQ(j["rank_work"].size(), std::size_t(ranks));
    std::uint64_t rays = 0;
    for (const auto& w : j["rank_work"]) rays += w["rays"].get<std::uint64_t>();
    EXPECT_EQ(rays, j["rays"].get<std::uint64_t>());
    EXPECT_EQ(j["rank_work"][0]["bytes_sent"], 0);
    // Each table travels once: what the other ranks sent is their share of the tables.
    EXPECT_NEAR(j["bytes_sent_over_tables"].get<double>(), 1.0, 0.05);
    expect_same_keys(nlohmann::json::parse(one.out), j);
  }
}

TEST_F(MpiTest, EvalJsonOnTwoAndThreeRanksHasTheValuesOfOneProcess) {
  ASSERT_EQ(run("bake " + path("torus.off") + " -o " + path("eval.hbox") + " -m 8 -n 6").code, 0);
  const std::string args = "eval " + path("eval.hbox") + " " + path("torus.off") + " --samples 4000 --seed 3 --json";
  const CommandResult one = run(args);
  ASSERT_EQ(one.code, 0) << one.err;
  for (int ranks : {2, 3}) {
    const CommandResult many = run_mpi(ranks, args);
    ASSERT_EQ(many.code, 0) << many.err;
    const auto j = nlohmann::json::parse(many.out);  // printed once: one document
    EXPECT_EQ(j["ranks"], ranks);
    const auto o = nlohmann::json::parse(one.out);
    EXPECT_EQ(o["ranks"], 1);
    for (const auto& [key, value] : o.items())
      if (key != "ranks") {
        EXPECT_EQ(j[key], value) << key << " on " << ranks << " ranks";
      }
  }
}

#ifdef HB_WITH_VTK
TEST_F(MpiTest, SweepRowsOnTwoAndThreeRanksHaveTheFiguresOfOneProcess) {
  const std::string args = "sweep " + path("torus.off") + " -m 4,8 -n 4,6 --samples 1500 --rounds 1 --cache none --json";
  const CommandResult one = run(args);
  ASSERT_EQ(one.code, 0) << one.err;
  for (int ranks : {2, 3}) {
    const CommandResult many = run_mpi(ranks, args);
    ASSERT_EQ(many.code, 0) << many.err;
    const auto j = nlohmann::json::parse(many.out);
    EXPECT_EQ(j["ranks"], ranks);
    ASSERT_EQ(j["rank_work"].size(), std::size_t(ranks));
    for (const auto& w : j["rank_work"]) EXPECT_GT(w["work"].get<std::uint64_t>(), 0u) << "a rank did nothing";
    expect_same_keys(nlohmann::json::parse(one.out), j);
  }
}
#endif

TEST_F(MpiTest, ARankThatFailsEndsTheJobNamingItAndLeavesNoOutput) {
  // Rank 1 is given a mesh that does not exist: bad input on one rank only.
  const std::string out = path("failed.hbox");
  const std::string script = "if [ \"$OMPI_COMM_WORLD_RANK\" = 1 ]; then exec " + std::string(HB_CLI_PATH) + " bake " +
                             path("missing.off") + " -o " + out + " -m 8 -n 6; else exec " + HB_CLI_PATH + " bake " +
                             path("torus.off") + " -o " + out + " -m 8 -n 6; fi";
  const CommandResult r = run_shell("timeout 120 " + kMpirun + "2 sh -c '" + script + "'");
  EXPECT_NE(r.code, 0);
  EXPECT_NE(r.code, 124) << "the job hung instead of ending";
  EXPECT_NE(r.err.find("rank 1 of 2"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("missing.off"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(out));
  EXPECT_FALSE(fs::exists(out + ".tmp"));
}

TEST_F(MpiTest, AKilledRankEndsTheJobWithAFailure) {
  const std::string out = path("killed.hbox");
  const std::string script = "if [ \"$OMPI_COMM_WORLD_RANK\" = 1 ]; then kill -9 $$; else exec " +
                             std::string(HB_CLI_PATH) + " bake " + path("torus.off") + " -o " + out + " -m 8 -n 6; fi";
  const CommandResult r = run_shell("timeout 120 " + kMpirun + "2 sh -c '" + script + "'");
  EXPECT_NE(r.code, 0);
  EXPECT_NE(r.code, 124) << "the job hung instead of ending";
  // mpirun tells, in words that depend on when the rank died ("noticed that process rank 1
  // ... exited on signal 9", or "1 process returned a non-zero exit code"); nothing is written.
  EXPECT_NE(r.err.find("job"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(out));
}

TEST_F(MpiTest, StabilityOnTwoAndThreeRanksGivesTheReportOfOneProcess) {
  ASSERT_EQ(run("bake " + path("torus.off") + " -o " + path("stab.hbox") + " -m 12 -n 6 --refine").code, 0);
  // The gate, two tests on the model and on the generated wall: 5 tasks to deal.
  const std::string args = "stability " + path("stab.hbox") + " " + path("torus.off") + " --tests T1,T7 --sites 2 --json";
  const CommandResult one = run(args);
  ASSERT_EQ(one.code, 0) << one.err;
  const auto o = nlohmann::json::parse(one.out);
  ASSERT_FALSE(o["metrics"].empty()) << one.out;
  for (int ranks : {2, 3}) {
    const CommandResult many = run_mpi(ranks, args);
    ASSERT_EQ(many.code, 0) << many.err;
    const auto j = nlohmann::json::parse(many.out);  // printed once: one document
    EXPECT_EQ(j["ranks"], ranks);
    expect_same_keys(o, j, std::to_string(ranks) + " ranks");
  }
}

TEST_F(MpiTest, ACommandThatDoesNotSplitRefusesSeveralRanks) {
  const CommandResult r = run_mpi(2, "subdivide " + path("torus.off") + " -o " + path("sub.off") + " --levels 1");
  EXPECT_NE(r.code, 0);
  EXPECT_NE(r.err.find("does not split its work"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(path("sub.off")));
}

TEST_F(MpiTest, WithoutMpirunTheBinaryIsOneProcess) {
  const CommandResult r = run("eval --help");
  EXPECT_EQ(r.code, 0) << r.err;
  ASSERT_EQ(run("bake " + path("torus.off") + " -o " + path("alone.hbox") + " -m 6 -n 4").code, 0);
  const CommandResult j = run("eval " + path("alone.hbox") + " " + path("torus.off") + " --samples 200 --json");
  ASSERT_EQ(j.code, 0) << j.err;
  EXPECT_EQ(nlohmann::json::parse(j.out)["ranks"], 1);
}
