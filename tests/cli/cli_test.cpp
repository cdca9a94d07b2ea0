// The hapticbox command end to end: real files in a temp folder, the real binary, no display.
// Checks exit codes (0 ok, 2 usage, 1 failure), that errors name the file and the cause, and
// that the JSON outputs carry the documented keys.
#include "contact/contact.h"
#include "mesh/generators.h"
#include "mesh/mesh_io.h"
#include "run_cli.h"
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>
#include <array>
#include <cctype>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <map>
#include <vector>
#include <sstream>
#include <sys/wait.h>

namespace {

namespace fs = std::filesystem;

using Result = hb::test::CommandResult;

class CliTest : public ::testing::Test {
protected:
  static void SetUpTestSuite() {
    dir_ = fs::temp_directory_path() / ("hb_cli_test_" + std::to_string(::getpid()));
    fs::create_directories(dir_);
    hb::write_mesh(hb::make_sphere(10.f, 4), (dir_ / "sphere.off").string());
  }
  static void TearDownTestSuite() { fs::remove_all(dir_); }

  static Result run(const std::string& args) { return hb::test::run_cli(args, dir_.string()); }
  /// With measurement-only switches (HB_MEASURE, e.g. "keep-ids").
  static Result measure(const std::string& switches, const std::string& args) {
    return hb::test::run_cli(args, dir_.string(), "HB_MEASURE=" + switches);
  }
  static std::string path(const std::string& name) { return (dir_ / name).string(); }
  static std::string write(const std::string& name, const std::string& text) {
    std::ofstream(path(name)) << text;
    return path(name);
  }
  static void bake_once() {
    if (!fs::exists(path("sphere.hbox"))) {
      ASSERT_EQ(run("bake " + path("sphere.off") + " -o " + path("sphere.hbox") + " -m 8 -n 6").code, 0);
    }
  }
  static fs::path dir_;
};
fs::path CliTest::dir_;

// `bake MESH -o BOX` alone is the budgeted default: it reports the budget it met on fresh
// probes, info shows it, and a bad --budget or --budget with a sampling option is a usage error.
TEST_F(CliTest, DefaultBakeMeetsTheBudgetAndInfoReportsIt) {
  const Result bake = run("bake " + path("sphere.off") + " -o " + path("budget.hbox") + " --budget agree=99 --json");
  ASSERT_EQ(bake.code, 0) << bake.err;
  const auto b = nlohmann::json::parse(bake.out);
  ASSERT_TRUE(b["budget"].is_object()) << bake.out;
  EXPECT_TRUE(b["budget"]["met"].get<bool>()) << bake.out;
  EXPECT_NE(b["budget"]["fresh_seed"], b["budget"]["tuning_seed"]);
  EXPECT_EQ(b["budget"]["budget"].get<std::string>().find("agree=99"), std::string("felt=0.1,p95=7,median=2,dir99=10,").size());
  const Result info = run("info " + path("budget.hbox"));
  ASSERT_EQ(info.code, 0) << info.err;
  EXPECT_NE(info.out.find("budget: felt=0.1,p95=7"), std::string::npos) << info.out;
  EXPECT_NE(info.out.find("met on 20000 fresh probes"), std::string::npos) << info.out;
  const auto ij = nlohmann::json::parse(run("info " + path("budget.hbox") + " --json").out);
  EXPECT_TRUE(ij["budget_report"]["met"].get<bool>());
  EXPECT_EQ(run("bake " + path("sphere.off") + " -o " + path("x.hbox") + " --budget p95=abc").code, 2);
  EXPECT_EQ(run("bake " + path("sphere.off") + " -o " + path("x.hbox") + " --budget p95=5 -n 4").code, 2);
  // A box baked with given options has no budget.
  bake_once();
  EXPECT_NE(run("info " + path("sphere.hbox")).out.find("budget: none"), std::string::npos);
}

// The default bake of several pieces answers through the surface cells and stores no
// triangle ids (info says so); `--route boxes` on it is a usage error that says why and what
// to do; HB_MEASURE=keep-ids keeps them (and belongs to the default bake only).
TEST_F(CliTest, DefaultBakeOfPiecesStoresNoTriangleIdsUnlessKept) {
  ASSERT_EQ(run("decompose " + path("sphere.off") + " -o " + path("halves.txt") + " --plane 0,0,0,1,0,0").code, 0);
  const std::string bake = "bake " + path("sphere.off") + " --pieces " + path("halves.txt") + " --budget agree=99 ";
  const Result lean = run(bake + "-o " + path("lean.hbox"));
  ASSERT_EQ(lean.code, 0) << lean.err;
  EXPECT_NE(lean.out.find("no triangle ids"), std::string::npos) << lean.out;
  const auto li = nlohmann::json::parse(run("info " + path("lean.hbox") + " --json").out);
  EXPECT_EQ(li["triangle_id_bytes"].get<std::uint64_t>(), 0u);
  EXPECT_GT(li["surface_bytes"].get<std::uint64_t>(), 0u);
  EXPECT_EQ(li["refine"].get<std::string>().rfind("yes", 0), 0u) << li["refine"];
  const Result cells = run("eval " + path("lean.hbox") + " " + path("sphere.off") + " --samples 2000 --json");
  ASSERT_EQ(cells.code, 0) << cells.err;
  EXPECT_GE(nlohmann::json::parse(cells.out)["contact_agreement"].get<double>(), 0.99);
  const Result boxes = run("eval " + path("lean.hbox") + " " + path("sphere.off") + " --samples 200 --route boxes");
  EXPECT_EQ(boxes.code, 2);
  EXPECT_NE(boxes.err.find("HB_MEASURE=keep-ids"), std::string::npos) << boxes.err;
  const Result kept = measure("keep-ids", bake + "-o " + path("kept.hbox") + " --json");
  ASSERT_EQ(kept.code, 0) << kept.err;
  const auto kj = nlohmann::json::parse(kept.out);
  EXPECT_GT(kj["triangle_id_bytes"].get<std::uint64_t>(), 0u);
  EXPECT_GT(kj["bytes"].get<std::uint64_t>(), li["bytes"].get<std::uint64_t>());
  EXPECT_EQ(run("eval " + path("kept.hbox") + " " + path("sphere.off") + " --samples 200 --route boxes").code, 0);
  EXPECT_EQ(measure("keep-ids", "bake " + path("sphere.off") + " -o " + path("x.hbox") + " -n 4").code, 2);
  // full-search bakes every sampling for the same exact answers; it too is the default bake's.
  const Result full = measure("full-search", bake + "-o " + path("full.hbox") + " --json");
  ASSERT_EQ(full.code, 0) << full.err;
  EXPECT_GE(nlohmann::json::parse(full.out)["budget"]["sampling_bakes"].get<int>(),
            kj["budget"]["sampling_bakes"].get<int>());
  EXPECT_EQ(measure("full-search", "bake " + path("sphere.off") + " -o " + path("x.hbox") + " -n 4").code, 2);
  // An unknown switch is a usage error naming it.
  const Result unknown = measure("fast", "bake " + path("sphere.off") + " -o " + path("x.hbox"));
  EXPECT_EQ(unknown.code, 2);
  EXPECT_NE(unknown.err.find("HB_MEASURE: unknown switch 'fast'"), std::string::npos) << unknown.err;
}

// `simplify`: a flat-subdivided sphere comes back to fewer triangles within its bound, the
// figures in JSON; a bad deviation is a usage error; --simplify is the default bake's only.
TEST_F(CliTest, SimplifyReducesAFlatSubdivisionAndReportsTheDeviation) {
  ASSERT_EQ(run("subdivide " + path("sphere.off") + " -o " + path("fine.off") + " --levels 1").code, 0);
  const Result r = run("simplify " + path("fine.off") + " -o " + path("simple.off") + " --shading 180 --json");
  ASSERT_EQ(r.code, 0) << r.err;
  const auto j = nlohmann::json::parse(r.out);
  EXPECT_EQ(j["triangles"].get<std::size_t>(), 20480u);
  EXPECT_LT(j["simplified_triangles"].get<std::size_t>(), 20480u);
  EXPECT_GE(j["deviation_max"].get<double>(), 0.0);
  EXPECT_TRUE(fs::exists(path("simple.off")));
  EXPECT_EQ(run("simplify " + path("fine.off") + " -o " + path("x.off") + " --deviation -1").code, 2);
  EXPECT_EQ(run("bake " + path("fine.off") + " -o " + path("x.hbox") + " -n 4 --simplify").code, 2);
}

// A scene of several boxes: info names their count and the m/n range (not the first box's m),
// its figures read with 4 significant digits, and an automatic decomposition's time reads with 3.
TEST_F(CliTest, InfoShowsASceneAsItsBoxesAndFiguresReadable) {
  const auto mesh = nlohmann::json::parse(run("info " + path("sphere.off") + " --json").out);
  const std::size_t triangles = mesh["triangles"].get<std::size_t>();
  std::ofstream ids(path("halves.txt"));
  for (std::size_t t = 0; t < triangles; ++t) ids << (t < triangles / 2 ? 0 : 1) << "\n";
  ids.close();
  ASSERT_EQ(run("bake " + path("sphere.off") + " -o " + path("halves.hbox") + " -m 8 -n 6 --pieces " + path("halves.txt")).code, 0);
  const Result info = run("info " + path("halves.hbox"));
  ASSERT_EQ(info.code, 0) << info.err;
  EXPECT_NE(info.out.find("\nm: 8 (over 2 boxes)\n"), std::string::npos) << info.out;
  EXPECT_NE(info.out.find("\nbox 1: m 8 n 6, centre ["), std::string::npos) << info.out;
  const auto j = nlohmann::json::parse(run("info " + path("halves.hbox") + " --json").out);
  // Not the raw doubles of the JSON form ("9.183012008666992").
  const std::string raw = j["box_list"][0]["half_extents"][0].dump();
  EXPECT_GT(raw.size(), 8u);
  EXPECT_EQ(info.out.find(raw), std::string::npos) << "raw precision: " << info.out;
  EXPECT_EQ(j["m_min"].get<int>(), 8);
  EXPECT_EQ(j["m_max"].get<int>(), 8);
  const Result decomposed = run("bake " + path("sphere.off") + " -o " + path("auto.hbox") + " -m 8 -n 4 --pieces auto");
  ASSERT_EQ(decomposed.code, 0) << decomposed.err;
  const std::size_t at = decomposed.err.find("decomposed into ");
  ASSERT_NE(at, std::string::npos) << decomposed.err;
  const std::string line = decomposed.err.substr(at, decomposed.err.find('\n', at) - at);
  const std::size_t in = line.find(" in ");
  ASSERT_NE(in, std::string::npos) << line;
  const std::string figure = line.substr(in + 4, line.find(' ', in + 4) - in - 4);
  std::size_t digits = 0;
  for (char c : figure) digits += std::isdigit(static_cast<unsigned char>(c)) ? 1 : 0;
  EXPECT_LE(digits, 3u) << line;
}

TEST_F(CliTest, BakeInfoEvalBenchProduceDocumentedJson) {
  const Result bake = run("bake " + path("sphere.off") + " -o " + path("sphere.hbox") + " -m 8 -n 6 --json");
  ASSERT_EQ(bake.code, 0) << bake.err;
  const auto b = nlohmann::json::parse(bake.out);
  for (const char* key : {"seconds", "rays_per_second", "bytes"}) EXPECT_TRUE(b.contains(key)) << key;
  EXPECT_EQ(b["rays"].get<double>(), 6.0 * 64 * 12 * 36);

  const auto info = nlohmann::json::parse(run("info " + path("sphere.hbox") + " --json").out);
  EXPECT_EQ(info["boxes"], 1);
  EXPECT_EQ(info["m"], 8);
  EXPECT_EQ(info["n"], 6);
  EXPECT_GT(info["bytes"].get<double>(), 0.0);

  const Result eval = run("eval " + path("sphere.hbox") + " " + path("sphere.off") + " --samples 2000 --json");
  ASSERT_EQ(eval.code, 0) << eval.err;
  const auto e = nlohmann::json::parse(eval.out);
  for (const char* key : {"samples", "contact_agreement", "false_contacts", "missed_contacts", "force_error_median",
                          "force_error_p95", "force_error_max", "angle_error_median_deg", "angle_error_p99_deg",
                          "depth_rms_over_diag"})
    EXPECT_TRUE(e.contains(key)) << key;
  EXPECT_EQ(e["samples"], 2000);
  EXPECT_GT(e["contact_agreement"].get<double>(), 0.95);
  // The second figure: as many light touches at any angle, their perceptible share.
  ASSERT_TRUE(e.contains("light_touch"));
  EXPECT_EQ(e["light_touch"]["samples"], 2000);
  EXPECT_GT(e["light_touch"]["exact_contacts"].get<double>(), 1000.0);
  EXPECT_GE(e["light_touch"]["perceptible_share"].get<double>(), 0.0);
  EXPECT_LE(e["light_touch"]["perceptible_share"].get<double>(), 1.0);

  const Result bench = run("bench " + path("sphere.hbox") + " " + path("sphere.off") + " --samples 2000 --rounds 1 --json");
  ASSERT_EQ(bench.code, 0) << bench.err;
  const auto k = nlohmann::json::parse(bench.out);
  for (const char* key : {"box_ns", "exact_ns", "speedup", "box_batched_ns", "exact_batched_ns", "speedup_batched", "box_stroke_ns",
                          "exact_stroke_ns", "speedup_stroke", "triangles", "batched_isa", "batched_lanes",
                          "batched_walks_side_by_side"})
    EXPECT_TRUE(k.contains(key)) << key;
  // The tail of single queries, ordered, and a verdict per order.
  for (const char* tail : {"box_single_tail", "exact_single_tail"}) {
    ASSERT_TRUE(k.contains(tail)) << tail;
    const auto& t = k[tail];
    EXPECT_EQ(t["queries"].get<std::size_t>(), 2000u);
    EXPECT_LE(t["p50_ns"].get<double>(), t["p99_ns"].get<double>());
    EXPECT_LE(t["p99_ns"].get<double>(), t["p999_ns"].get<double>());
    EXPECT_LE(t["p999_ns"].get<double>(), t["max_ns"].get<double>());
    // One round: each probe's median is its only time, so the probes' tail is the pooled one.
    for (const char* q : {"p50_ns", "p99_ns", "p999_ns", "max_ns"})
      EXPECT_EQ(t[std::string("probe_") + q].get<double>(), t[q].get<double>()) << tail << " " << q;
  }
  for (const char* order : {"random", "batched", "coherent", "strokes", "p99", "p999", "probe_p999"}) {
    const std::string v = k["verdict"][order].get<std::string>();
    EXPECT_TRUE(v.find("x faster than exact") != std::string::npos || v.find("x slower than exact") != std::string::npos ||
                v.rfind("as fast as exact (", 0) == 0)
        << order << ": " << v;
  }
  const std::string isa = k["batched_isa"].get<std::string>();
  EXPECT_TRUE(isa == "sse2" || isa == "avx" || isa == "avx2" || isa == "avx512") << isa;
}

TEST_F(CliTest, RefinedBakeIsShownByInfoAndAgreesWithTheExactAnswer) {
  const std::string box = path("sphere_refined.hbox");
  const Result bake = run("bake " + path("sphere.off") + " -o " + box + " -m 6 -n 4 --refine --codec block --json");
  ASSERT_EQ(bake.code, 0) << bake.err;
  EXPECT_TRUE(nlohmann::json::parse(bake.out)["refine"].get<bool>());
  const auto info = nlohmann::json::parse(run("info " + box + " --json --verify").out);
  EXPECT_EQ(info["refine"], "yes");
  // 5,120 triangles: 16-bit ids.
  EXPECT_EQ(info["triangle_id_bytes"].get<double>(), 6.0 * 36 * 12 * 16 * 2);
  EXPECT_GT(info["surface_bytes"].get<double>(), 0.0);
  const Result eval = run("eval " + box + " " + path("sphere.off") + " --samples 2000 --json");
  ASSERT_EQ(eval.code, 0) << eval.err;
  const auto e = nlohmann::json::parse(eval.out);
  // So coarse a box blends errors of several percent; refined, it answers exactly.
  EXPECT_LT(e["force_error_median"].get<double>(), 1e-3);
  EXPECT_GT(e["contact_agreement"].get<double>(), 0.99);
}

TEST_F(CliTest, QueryCsvKeepsRowOrderAndAddsExactColumns) {
  bake_once();
  const std::string in = write("segs.csv", "sx,sy,sz,ex,ey,ez\n0,0.1,30,0,0.1,9\n30,30,30,31,31,31\n0,25,0.2,0,9.5,0.2\n");
  const Result r = run("query " + path("sphere.hbox") + " --segments " + in + " --exact " + path("sphere.off"));
  ASSERT_EQ(r.code, 0) << r.err;
  std::istringstream lines(r.out);
  std::string header, row1, row2, row3;
  std::getline(lines, header);
  std::getline(lines, row1);
  std::getline(lines, row2);
  std::getline(lines, row3);
  EXPECT_EQ(header.rfind("contact,depth,nx,ny,nz,fx,fy,fz,exact_contact", 0), 0u);
  EXPECT_EQ(row1.rfind("1,", 0), 0u);
  EXPECT_EQ(row2.rfind("0,", 0), 0u);
  EXPECT_EQ(row3.rfind("1,", 0), 0u);
}

TEST_F(CliTest, CacheCommandShowsAndClearsTheSharedBoxCache) {
  // The cache lives under $XDG_CACHE_HOME (shared with sweep, report and the window).
  bake_once();
  const fs::path boxes = dir_ / "xdg" / "hapticbox" / "boxes";
  fs::create_directories(boxes);
  fs::copy_file(path("sphere.hbox"), boxes / "0000000000000001_0000000000000002.hbox",
                fs::copy_options::overwrite_existing);
  const auto cache = [&](const std::string& args) {
    const std::string cmd = "env XDG_CACHE_HOME=" + path("xdg") + " " + HB_CLI_PATH + " cache " + args;
    std::string out;
    FILE* p = popen(cmd.c_str(), "r");
    if (!p) return nlohmann::json();
    for (int c; (c = fgetc(p)) != EOF;) out += char(c);
    pclose(p);
    return nlohmann::json::parse(out);
  };
  const auto shown = cache("--json");
  EXPECT_EQ(shown["dir"], boxes.string());
  EXPECT_EQ(shown["files"], 1);
  EXPECT_EQ(shown["bytes"].get<std::uint64_t>(), fs::file_size(path("sphere.hbox")));
  const auto cleared = cache("--clear --json");
  EXPECT_EQ(cleared["files"], 0);
  EXPECT_EQ(cleared["removed"]["files"], 1);
  EXPECT_TRUE(fs::is_empty(boxes));
}

// `bake` goes through the box cache the window, sweep and report share (hb::bake_cached): a
// miss bakes and stores the entry (the output file's very bytes), a hit copies the entry and says
// so, --cache none bakes again and stores nothing, and `cache` then lists and clears the entry.
TEST_F(CliTest, BakeStoresInAndCopiesFromTheSharedBoxCache) {
  const std::string cache = path("bake-cache");
  fs::remove_all(cache);
  const std::string bake = "bake " + path("sphere.off") + " -m 6 -n 4 --cache " + cache + " -o ";
  const Result miss = run(bake + path("miss.hbox") + " --json");
  ASSERT_EQ(miss.code, 0) << miss.err;
  const auto m = nlohmann::json::parse(miss.out);
  EXPECT_FALSE(m["from_cache"].get<bool>());
  const std::string entry = m["cache_path"].get<std::string>();
  EXPECT_EQ(fs::path(entry).parent_path(), fs::path(cache));
  ASSERT_TRUE(fs::exists(entry)) << entry;
  const auto bytes = [](const std::string& p) {
    std::ifstream f(p, std::ios::binary);
    return std::string(std::istreambuf_iterator<char>(f), {});
  };
  EXPECT_EQ(bytes(entry), bytes(path("miss.hbox")));

  const Result hit = run(bake + path("hit.hbox"));
  ASSERT_EQ(hit.code, 0) << hit.err;
  EXPECT_NE(hit.out.find("from cache (" + entry + ")"), std::string::npos) << hit.out;
  EXPECT_EQ(bytes(path("hit.hbox")), bytes(entry));
  const auto h = nlohmann::json::parse(run(bake + path("hit2.hbox") + " --json").out);
  EXPECT_TRUE(h["from_cache"].get<bool>());
  EXPECT_EQ(h["cache_path"], entry);

  // Another recipe is another entry; --cache none bakes (the same bytes) and stores nothing.
  fs::remove(entry);
  const Result fresh = run("bake " + path("sphere.off") + " -m 6 -n 4 --cache none -o " + path("fresh.hbox") + " --json");
  ASSERT_EQ(fresh.code, 0) << fresh.err;
  const auto f = nlohmann::json::parse(fresh.out);
  EXPECT_FALSE(f["from_cache"].get<bool>());
  EXPECT_EQ(f["cache_path"], "");
  EXPECT_FALSE(fs::exists(entry));
  EXPECT_EQ(bytes(path("fresh.hbox")), bytes(path("miss.hbox"))) << "the same inputs must give the same file";
  ASSERT_EQ(run("bake " + path("sphere.off") + " -m 6 -n 6 --cache " + cache + " -o " + path("other.hbox")).code, 0);
  std::size_t entries = 0;
  for (const auto& e : fs::directory_iterator(cache)) entries += e.path().extension() == ".hbox" ? 1 : 0;
  EXPECT_EQ(entries, 1u);

  // The bake's entry is what `cache` shows and clears (XDG_CACHE_HOME/hapticbox/boxes).
  const std::string xdg = path("bake-xdg");
  fs::remove_all(xdg);
  const std::string env = "env XDG_CACHE_HOME=" + xdg + " " + HB_CLI_PATH + " ";
  ASSERT_EQ(std::system((env + "bake " + path("sphere.off") + " -m 6 -n 4 -o " + path("xdg.hbox") + " >/dev/null").c_str()), 0);
  const auto cache_json = [&](const std::string& args) {
    std::string out;
    FILE* p = popen((env + "cache --json " + args).c_str(), "r");
    if (!p) return nlohmann::json();
    for (int c; (c = fgetc(p)) != EOF;) out += char(c);
    pclose(p);
    return nlohmann::json::parse(out, nullptr, false);
  };
  const auto shown = cache_json("");
  EXPECT_EQ(shown["files"], 1);
  EXPECT_EQ(shown["bytes"].get<std::uint64_t>(), fs::file_size(path("xdg.hbox")));
  EXPECT_EQ(cache_json("--clear")["files"], 0);
}

TEST_F(CliTest, VersionSaysWhatPagesTheHeapGets) {
  // main() re-executes itself with glibc.malloc.hugetlb=1 for inputs of 16 MB and more where
  // THP is "madvise" (parallel/huge_pages.h); --version says what the heap got.
  const auto version = [&](const std::string& env) {
    std::string out;
    FILE* p = popen(("env " + env + " " + std::string(HB_CLI_PATH) + " --version").c_str(), "r");
    if (!p) return out;
    for (int c; (c = fgetc(p)) != EOF;) out += char(c);
    pclose(p);
    return out;
  };
  std::ifstream thp("/sys/kernel/mm/transparent_hugepage/enabled");
  const std::string mode((std::istreambuf_iterator<char>(thp)), {});
  const std::string advised = version("GLIBC_TUNABLES=glibc.malloc.hugetlb=1");
  const std::string refused = version("GLIBC_TUNABLES=glibc.malloc.hugetlb=0");
  ASSERT_NE(advised.find("hapticbox "), std::string::npos) << advised;
  if (mode.find("[madvise]") != std::string::npos) {
    EXPECT_NE(advised.find("heap: transparent huge pages"), std::string::npos) << advised;
    EXPECT_NE(refused.find("heap: 4 KB pages"), std::string::npos) << refused;
  } else if (mode.find("[always]") != std::string::npos) {
    EXPECT_NE(refused.find("heap: transparent huge pages"), std::string::npos) << refused;
  } else {
    EXPECT_NE(advised.find("heap: 4 KB pages"), std::string::npos) << advised;
  }
}

TEST_F(CliTest, MissingMeshFailsWithExitOneAndNamesTheFile) {
  const Result r = run("bake " + path("nope.off") + " -o " + path("x.hbox"));
  EXPECT_EQ(r.code, 1);
  EXPECT_NE(r.err.find("nope.off"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(path("x.hbox")));
}

TEST_F(CliTest, GarbageMeshFailsWithExitOne) {
  const Result r = run("info " + write("garbage.off", "OFF\n3 1 0\n1 2 zz\n"));
  EXPECT_EQ(r.code, 1);
  EXPECT_NE(r.err.find("garbage.off"), std::string::npos) << r.err;
}

TEST_F(CliTest, CorruptBoxFailsWithExitOne) {
  bake_once();
  std::ifstream in(path("sphere.hbox"), std::ios::binary);
  std::string bytes((std::istreambuf_iterator<char>(in)), {});
  bytes.resize(bytes.size() / 3);
  std::ofstream(path("cut.hbox"), std::ios::binary) << bytes;
  const Result r = run("eval " + path("cut.hbox") + " " + path("sphere.off"));
  EXPECT_EQ(r.code, 1);
  EXPECT_NE(r.err.find("cut.hbox"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("truncated"), std::string::npos) << r.err;
}

TEST_F(CliTest, UsageErrorsExitTwo) {
  EXPECT_EQ(run("").code, 2);
  EXPECT_EQ(run("bake").code, 2);
  EXPECT_EQ(run("bake " + path("sphere.off") + " -o " + path("y.hbox") + " -m 1").code, 2);
  EXPECT_EQ(run("no-such-command").code, 2);
  bake_once();
  EXPECT_EQ(run("query " + path("sphere.hbox")).code, 2);
}

TEST_F(CliTest, BadSegmentsCsvNamesFileAndLine) {
  bake_once();
  const std::string in = write("bad.csv", "sx,sy,sz,ex,ey,ez\n0,0,30,0,0,9\n1,2,three,4,5,6\n");
  const Result r = run("query " + path("sphere.hbox") + " --segments " + in);
  EXPECT_EQ(r.code, 1);
  EXPECT_NE(r.err.find("bad.csv:3"), std::string::npos) << r.err;
}

// --- hostile input ---------------------------------------------------------------------

// Finding 6: `query --stiffness nan` printed NaN forces, 1e38 infinities; `servo --seconds nan`
// ran 0 ticks and exited 0. Every numeric option now refuses non-finite and absurd values.
TEST_F(CliTest, NonFiniteOrAbsurdOptionValuesAreUsageErrorsNamingTheValue) {
  bake_once();
  const std::string q = "query " + path("sphere.hbox") + " --segment 0 0.1 30 0 0.1 9 ";
  for (const char* opt : {"--workspace stiffness=nan", "--workspace stiffness=1e38", "--workspace stiffness=-5",
                          "--workspace metres-per-unit=inf"}) {
    const Result r = run(q + opt);
    EXPECT_EQ(r.code, 2) << opt;
    const std::string value = "'" + std::string(opt).substr(std::string(opt).find('=') + 1) + "'";
    EXPECT_NE(r.err.find(value), std::string::npos) << opt << ": " << r.err;
  }
  for (const char* opt : {"--seconds nan", "--seconds inf", "--workspace stiffness=1e38", "--rate nan",
                          "--workspace metres-per-unit=-inf", "--workspace mm=0", "--workspace max-force=nan",
                          "--perceptual w=x"}) {
    const Result r = run(std::string("servo plane --no-realtime ") + opt);
    EXPECT_EQ(r.code, 2) << opt << ": " << r.err;
  }
  EXPECT_EQ(measure("spin-us=nan", "servo plane --no-realtime").code, 2);
  EXPECT_EQ(run("bake " + path("sphere.off") + " -o " + path("nan.hbox") + " --pieces none,padding=nan").code, 2);
}

// Finding 7: 1e-40 and 1e-300 were "not a number", a UTF-8 BOM failed the header, a folder
// was an "empty segments file", `--segment ""` read as 0.
TEST_F(CliTest, SegmentsCsvAcceptsTinyValuesAndAByteOrderMark) {
  bake_once();
  const std::string in = write("tiny.csv", "\xEF\xBB\xBFsx,sy,sz,ex,ey,ez\r\n0,0.1,30,0,0.1,1e-40\r\n1e-300,0.1,30,0,0.1,9\r\n");
  const Result r = run("query " + path("sphere.hbox") + " --segments " + in);
  ASSERT_EQ(r.code, 0) << r.err;
  std::istringstream lines(r.out);
  std::string header, row1, row2;
  std::getline(lines, header);
  std::getline(lines, row1);
  std::getline(lines, row2);
  EXPECT_EQ(row1.rfind("1,", 0), 0u) << row1;
  EXPECT_EQ(row2.rfind("1,", 0), 0u) << row2;
  const Result big = run("query " + path("sphere.hbox") + " --segments " + write("big.csv", "sx,sy,sz,ex,ey,ez\n0,0,1e39,0,0,0\n"));
  EXPECT_EQ(big.code, 1);
  EXPECT_NE(big.err.find("big.csv:2"), std::string::npos) << big.err;
}

TEST_F(CliTest, SegmentsGivenAFolderSaysItIsAFolder) {
  bake_once();
  fs::create_directories(path("segments_dir"));
  const Result r = run("query " + path("sphere.hbox") + " --segments " + path("segments_dir"));
  EXPECT_EQ(r.code, 1);
  EXPECT_NE(r.err.find("is a folder"), std::string::npos) << r.err;
}

TEST_F(CliTest, EmptySegmentValueIsAUsageError) {
  bake_once();
  const Result r = run("query " + path("sphere.hbox") + " --segment '' 0 30 0 0 9");
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.err.find("value 1"), std::string::npos) << r.err;
  EXPECT_EQ(run("query " + path("sphere.hbox") + " --segment 0 0 30 0 0 x9").code, 2);
}

TEST_F(CliTest, InfoVerifyRejectsBytesAfterTheLastSection) {
  bake_once();
  fs::copy_file(path("sphere.hbox"), path("appended.hbox"), fs::copy_options::overwrite_existing);
  std::ofstream(path("appended.hbox"), std::ios::binary | std::ios::app) << "trailing bytes";
  const Result r = run("info " + path("appended.hbox") + " --verify");
  EXPECT_EQ(r.code, 1);
  EXPECT_NE(r.err.find("after the last section"), std::string::npos) << r.err;
  EXPECT_EQ(run("info " + path("sphere.hbox") + " --verify").code, 0);
}

// Finding 2: any coordinate >= 1e19 aborted the bake inside Embree (SIGABRT).
TEST_F(CliTest, BakeOfAMeshBeyondTheCoordinateRangeFailsWithAMessage) {
  const std::string far = write("far.off", "OFF\n4 4 0\n0 0 0\n1e19 0 0\n0 1 0\n0 0 1\n3 0 2 1\n3 0 1 3\n3 0 3 2\n3 1 2 3\n");
  const Result r = run("bake " + far + " -o " + path("far.hbox") + " -m 2 -n 2");
  EXPECT_EQ(r.code, 1);
  EXPECT_NE(r.err.find("beyond the supported range"), std::string::npos) << r.err;
  // The model loader refuses models beyond 10 km (a wrong unit) before the core's 1e15 range;
  // a large but plausible model (1 km in mm) still bakes.
  const std::string near = write("near.off", "OFF\n4 4 0\n0 0 0\n1e6 0 0\n0 1e6 0\n0 0 1e6\n3 0 2 1\n3 0 1 3\n3 0 3 2\n3 1 2 3\n");
  EXPECT_EQ(run("bake " + near + " -o " + path("near.hbox") + " -m 2 -n 2").code, 0);
}

// Finding 5: a replay trusted its log's header (a negative stiffness reversed every force; a
// rate of 0.05 Hz never returned).
TEST_F(CliTest, ReplayOfALogWithAnImpossibleHeaderIsRefused) {
  const std::string log = path("plane.hblog");
  ASSERT_EQ(run("servo plane --no-realtime --seconds 0.05 --record " + log).code, 0);
  std::string bytes;
  {
    std::ifstream in(log, std::ios::binary);
    bytes.assign(std::istreambuf_iterator<char>(in), {});
  }
  ASSERT_GT(bytes.size(), 64u);
  const auto patched = [&](const std::string& name, std::size_t at, const void* value, std::size_t n) {
    std::string b = bytes;
    b.replace(at, n, static_cast<const char*>(value), n);
    std::ofstream(path(name), std::ios::binary) << b;
    return path(name);
  };
  const float stiffness = -3000.f;
  const Result negative = run("servo plane --no-realtime --seconds 1 --device replay:" +
                              patched("negative.hblog", 16 + 8 + 12, &stiffness, 4));
  EXPECT_EQ(negative.code, 1);
  EXPECT_NE(negative.err.find("maximum stiffness"), std::string::npos) << negative.err;
  const double rate = 0.05;
  const Result slow = run("servo plane --no-realtime --seconds 1 --device replay:" + patched("slow.hblog", 16, &rate, 8));
  EXPECT_EQ(slow.code, 1);
  EXPECT_NE(slow.err.find("servo log rate"), std::string::npos) << slow.err;
  EXPECT_EQ(run("servo plane --no-realtime --seconds 1 --device replay:" + log).code, 0);
}

// `servo BOX --exact MESH`: the exact answer in the same loop, one drives and the other runs
// in shadow; the summary compares them and the log and CSV carry both per tick.
TEST_F(CliTest, ServoWithExactComparesBoxAndExactOnOneTrajectoryAndLogsBoth) {
  bake_once();
  const std::string log = path("shadow.hblog"), csv = path("shadow.csv");
  const Result r = run("servo " + path("sphere.hbox") + " --exact " + path("sphere.off") +
                       " --no-realtime --seconds 0.3 --workspace metres-per-unit=0.0025 --record " + log + " --csv " + csv + " --json");
  ASSERT_EQ(r.code, 0) << r.err;
  const auto j = nlohmann::json::parse(r.out);
  ASSERT_TRUE(j.contains("box_vs_exact")) << r.out;
  const auto& c = j["box_vs_exact"];
  EXPECT_EQ(c["rendered"], "box");
  EXPECT_EQ(c["contact_both"].get<std::uint64_t>() + c["contact_box_only"].get<std::uint64_t>() +
                c["contact_exact_only"].get<std::uint64_t>() + c["contact_neither"].get<std::uint64_t>(),
            j["ticks"].get<std::uint64_t>());
  EXPECT_GT(c["contact_both"].get<std::uint64_t>(), 0u) << r.out;  // 400 units/m: the circle runs inside the sphere, the handle in and out
  EXPECT_GT(c["exact_query_p50_us"].get<double>(), 0.0);
  EXPECT_GE(c["force_diff_p99_n"].get<double>(), c["force_diff_p50_n"].get<double>());
  std::ifstream in(csv);
  std::string header;
  std::getline(in, header);
  EXPECT_NE(header.find("box_fx_n"), std::string::npos) << header;
  EXPECT_NE(header.find("exact_fx_n"), std::string::npos) << header;
  // The exact answer can drive instead; the text summary names both.
  const Result exact = run("servo " + path("sphere.hbox") + " --exact " + path("sphere.off") +
                           " --render exact --no-realtime --seconds 0.2 --workspace metres-per-unit=0.0025");
  ASSERT_EQ(exact.code, 0) << exact.err;
  EXPECT_NE(exact.out.find("exact drives the device, box in shadow"), std::string::npos) << exact.out;
  EXPECT_NE(exact.out.find("|F_box - F_exact|"), std::string::npos) << exact.out;
  // What makes no sense is refused with a message.
  const Result no_mesh = run("servo " + path("sphere.hbox") + " --render exact --no-realtime --seconds 0.1");
  EXPECT_EQ(no_mesh.code, 2);
  EXPECT_NE(no_mesh.err.find("--render exact needs --exact"), std::string::npos) << no_mesh.err;
  const Result plane = run("servo plane --exact " + path("sphere.off") + " --no-realtime --seconds 0.1");
  EXPECT_EQ(plane.code, 2);
  EXPECT_NE(plane.err.find("not the plane scene"), std::string::npos) << plane.err;
  EXPECT_EQ(run("servo plane --csv " + csv + " --no-realtime --seconds 0.1").code, 2);  // --csv needs --record
  EXPECT_EQ(run("servo " + path("sphere.hbox") + " --exact " + path("nope.off") + " --no-realtime --seconds 0.1").code, 1);
}

// `servo --law penalty|proxy`: the contact law of the loop, named in the summary and the JSON;
// with --exact both answers are rendered by it (each its own proxy).
TEST_F(CliTest, ServoLawIsChosenNamedAndABadOneRefusedNamingTheValue) {
  const Result penalty = run("servo plane --no-realtime --seconds 0.1 --json");
  ASSERT_EQ(penalty.code, 0) << penalty.err;
  EXPECT_EQ(nlohmann::json::parse(penalty.out)["contact_law"], "penalty");
  const Result text = run("servo plane --no-realtime --seconds 0.1 --law proxy");
  ASSERT_EQ(text.code, 0) << text.err;
  EXPECT_NE(text.out.find("contact law: proxy"), std::string::npos) << text.out;
  bake_once();
  const Result both = run("servo " + path("sphere.hbox") + " --exact " + path("sphere.off") +
                          " --law proxy --no-realtime --seconds 0.3 --workspace metres-per-unit=0.0025 --json");
  ASSERT_EQ(both.code, 0) << both.err;
  const auto j = nlohmann::json::parse(both.out);
  EXPECT_EQ(j["contact_law"], "proxy");
  EXPECT_EQ(j["box_vs_exact"]["contact_law"], "proxy");
  ASSERT_TRUE(j.contains("proxy") && j.contains("shadow_proxy")) << both.out;
  EXPECT_GT(j["proxy"]["contact_ticks"].get<std::uint64_t>(), 0u) << both.out;  // the circle runs inside the sphere
  EXPECT_EQ(j["proxy"]["contact_ticks"], j["box_vs_exact"]["contact_both"].get<std::uint64_t>() +
                                             j["box_vs_exact"]["contact_box_only"].get<std::uint64_t>());
  EXPECT_GT(j["shadow_proxy"]["contact_ticks"].get<std::uint64_t>(), 0u);
  const Result bad = run("servo plane --no-realtime --seconds 0.1 --law spring");
  EXPECT_EQ(bad.code, 2);
  EXPECT_NE(bad.err.find("'spring'"), std::string::npos) << bad.err;
  EXPECT_NE(bad.err.find("penalty or proxy"), std::string::npos) << bad.err;
}

} // namespace

TEST_F(CliTest, UnknownCommandIsNamedAndTheCommandsListed) {
  const Result r = run("bakee " + path("sphere.off"));
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.err.find("unknown command 'bakee'"), std::string::npos) << r.err;
  for (const char* command : {"bake", "eval", "query", "info"}) EXPECT_NE(r.err.find(command), std::string::npos) << r.err;
  EXPECT_EQ(r.err.find("A subcommand is required"), std::string::npos) << r.err;
  // Main's own options still come first.
  EXPECT_EQ(run("--threads 1 info " + path("sphere.off")).code, 0);
}

TEST_F(CliTest, ShortSegmentSaysSixNumbersAndWhatItGot) {
  bake_once();
  Result r = run("query " + path("sphere.hbox") + " --segment 1 2 3");
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.err.find("six numbers"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("got 3: 1 2 3"), std::string::npos) << r.err;
  // Before the box file, a short segment swallows its name: the message says so.
  r = run("query --segment 1 2 3 " + path("sphere.hbox"));
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.err.find("got 4"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("no BOX"), std::string::npos) << r.err;
  EXPECT_EQ(run("query --segment 0 0 30 0 0 9 " + path("sphere.hbox")).code, 0);
}

TEST_F(CliTest, EvalAgainstAnotherMeshFailsUnlessForced) {
  bake_once();
  hb::write_mesh(hb::make_sphere(12.f, 4), path("other.off"));
  const Result r = run("eval " + path("sphere.hbox") + " " + path("other.off") + " --samples 200");
  EXPECT_EQ(r.code, 1);
  EXPECT_NE(r.err.find("different mesh"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("--force"), std::string::npos) << r.err;
  EXPECT_TRUE(r.out.empty()) << r.out;
  const Result forced = run("eval " + path("sphere.hbox") + " " + path("other.off") + " --samples 200 --force");
  EXPECT_EQ(forced.code, 0) << forced.err;
  EXPECT_NE(forced.err.find("warning"), std::string::npos) << forced.err;
  EXPECT_EQ(run("eval " + path("sphere.hbox") + " " + path("sphere.off") + " --samples 200").code, 0);
}

TEST_F(CliTest, FiguresPrintWithSignificantDigits) {
  const Result bake = run("bake " + path("sphere.off") + " -o " + path("fig.hbox") + " -m 8 -n 6");
  ASSERT_EQ(bake.code, 0) << bake.err;
  // 6 x 64 x 12 x 36 = 165,888 rays: "166 k rays", not the raw count; bytes in MB or kB.
  EXPECT_NE(bake.out.find("166 k rays"), std::string::npos) << bake.out;
  EXPECT_EQ(bake.out.find("165888"), std::string::npos) << bake.out;
  EXPECT_TRUE(bake.out.find(" MB") != std::string::npos || bake.out.find(" kB") != std::string::npos) << bake.out;
  const Result eval = run("eval " + path("fig.hbox") + " " + path("sphere.off") + " --samples 500");
  ASSERT_EQ(eval.code, 0) << eval.err;
  EXPECT_EQ(eval.out.find(".0000 %"), std::string::npos) << eval.out;  // no raw fixed precision
}

TEST_F(CliTest, RatioTargetNotReachedIsSaidAndFailsOnlyWhenStrict) {
  const Result r = run("bake " + path("sphere.off") + " -o " + path("ratio.hbox") +
                       " -m 8 -n 6 --codec haar,ratio=100000 --json");
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.err.find("target not reached"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("10 %"), std::string::npos) << r.err;  // the bound at its maximum
  const auto j = nlohmann::json::parse(r.out);
  EXPECT_EQ(j["ratio_reached"], false);
  EXPECT_EQ(j["ratio_target"].get<double>(), 100000.0);
  const Result strict = run("bake " + path("sphere.off") + " -o " + path("ratio2.hbox") +
                            " -m 8 -n 6 --codec haar,ratio=100000,strict");
  EXPECT_EQ(strict.code, 1);
  EXPECT_NE(strict.err.find("target not reached"), std::string::npos) << strict.err;
  // A reachable target is met silently.
  const Result easy = run("bake " + path("sphere.off") + " -o " + path("ratio3.hbox") +
                          " -m 8 -n 6 --codec haar,ratio=1.5,strict --json");
  ASSERT_EQ(easy.code, 0) << easy.err;
  EXPECT_EQ(nlohmann::json::parse(easy.out)["ratio_reached"], true);
}

namespace {

// The columns of a CSV header line, by name.
std::map<std::string, std::size_t> csv_columns(const std::string& header) {
  std::map<std::string, std::size_t> cols;
  std::istringstream in(header);
  std::string name;
  for (std::size_t i = 0; std::getline(in, name, ','); ++i) cols[name] = i;
  return cols;
}

std::vector<double> csv_numbers(const std::string& line) {
  std::vector<double> v;
  std::istringstream in(line);
  std::string cell;
  while (std::getline(in, cell, ',')) v.push_back(std::strtod(cell.c_str(), nullptr));
  return v;
}

} // namespace

// One workspace for every command. The sphere (20 mm across, diagonal 34.6 mm) is
// fitted to the device's 80 mm, at 1500 N/m: a force per unit of depth (along the normal) of
// 1500 x 0.08 / 34.64 N per model unit, the same in `query`, `servo --exact` and `eval`, which
// all state the workspace; `--workspace real-size` shows the model at 1 unit = 1 mm instead.
TEST_F(CliTest, EveryCommandComputesForcesAtTheOneWorkspaceScaleAndStatesIt) {
  bake_once();
  const double diagonal = hb::make_sphere(10.f, 4).bounds().diagonal();
  const double newtons_per_unit = 1500.0 * 0.08 / diagonal;
  // query: the exact answer's force over its depth along the normal (the normal depth law:
  // |F| = k d mpu cos, the stylus along -z here).
  const std::string in = write("ws.csv", "sx,sy,sz,ex,ey,ez\n0,0.1,30,0,0.1,9\n");
  const Result q = run("query " + path("sphere.hbox") + " --segments " + in + " --exact " + path("sphere.off"));
  ASSERT_EQ(q.code, 0) << q.err;
  std::istringstream lines(q.out);
  std::string header, row;
  std::getline(lines, header);
  std::getline(lines, row);
  auto cols = csv_columns(header);
  ASSERT_TRUE(cols.count("perceptible")) << header;
  std::vector<double> v = csv_numbers(row);
  const double f = std::hypot(v[cols["exact_fx"]], v[cols["exact_fy"]], v[cols["exact_fz"]]);
  const double query_ratio = f / (v[cols["exact_depth"]] * v[cols["exact_nz"]]);
  EXPECT_NEAR(query_ratio, newtons_per_unit, 1e-3 * newtons_per_unit);
  // servo --exact: every tick in contact, the same ratio.
  const std::string log = path("ws.hblog"), csv = path("ws_servo.csv");
  const Result s = run("servo " + path("sphere.hbox") + " --exact " + path("sphere.off") +
                       " --no-realtime --seconds 0.3 --record " + log + " --csv " + csv + " --json");
  ASSERT_EQ(s.code, 0) << s.err;
  const auto sj = nlohmann::json::parse(s.out);
  EXPECT_EQ(sj["workspace"]["fit"], "device");
  EXPECT_NEAR(sj["workspace"]["diagonal_mm"].get<double>(), 80.0, 1e-3);
  // The shadow comparison judges every contact tick as a hand would.
  EXPECT_GT(sj["box_vs_exact"]["contact_ticks"].get<std::uint64_t>(), 0u) << s.out;
  EXPECT_LE(sj["box_vs_exact"]["perceptible_ticks"].get<std::uint64_t>(),
            sj["box_vs_exact"]["contact_ticks"].get<std::uint64_t>());
  std::ifstream servo_csv(csv);
  std::getline(servo_csv, header);
  cols = csv_columns(header);
  std::size_t checked = 0;
  while (std::getline(servo_csv, row)) {
    v = csv_numbers(row);
    if (v[cols["exact_contact"]] == 0 || v[cols["exact_depth"]] <= 0 || v[cols["exact_nz"]] < 0.2) continue;
    const double fs = std::hypot(v[cols["exact_fx_n"]], v[cols["exact_fy_n"]], v[cols["exact_fz_n"]]);
    EXPECT_NEAR(fs / (v[cols["exact_depth"]] * v[cols["exact_nz"]]), newtons_per_unit, 1e-3 * newtons_per_unit) << row;
    ++checked;
  }
  EXPECT_GT(checked, 10u) << "the virtual device's circle should touch the sphere";
  // eval states the same workspace and the perceptual headline.
  const Result e = run("eval " + path("sphere.hbox") + " " + path("sphere.off") + " --samples 2000 --json");
  ASSERT_EQ(e.code, 0) << e.err;
  const auto ej = nlohmann::json::parse(e.out);
  EXPECT_NEAR(ej["workspace"]["metres_per_unit"].get<double>(), 0.08 / diagonal, 1e-9);
  ASSERT_TRUE(ej.contains("perceptible")) << e.out;
  EXPECT_LE(ej["perceptible"]["probes"].get<std::uint64_t>(), 2000u);
  EXPECT_EQ(ej["perceptible"]["thresholds"], "w=10,f0=0.04,theta=25,fmin=0.2");
  const Result text = run("eval " + path("sphere.hbox") + " " + path("sphere.off") + " --samples 2000");
  EXPECT_NE(text.out.find("perceptibly different"), std::string::npos) << text.out;
  EXPECT_NE(text.out.find("diagonal 80 mm"), std::string::npos) << text.out;
  // --workspace real-size: 1 unit = 1 mm, a diagonal of 34.6 mm; the strict preset feels at least as much.
  const Result real = run("eval " + path("sphere.hbox") + " " + path("sphere.off") +
                          " --samples 2000 --json --workspace real-size --perceptual strict");
  ASSERT_EQ(real.code, 0) << real.err;
  const auto rj = nlohmann::json::parse(real.out);
  EXPECT_EQ(rj["workspace"]["fit"], "real-size");
  EXPECT_NEAR(rj["workspace"]["metres_per_unit"].get<double>(), 0.001, 1e-12);
  EXPECT_EQ(rj["perceptible"]["thresholds"], "w=7,f0=0.03,theta=18,fmin=0.2");
  // Two ways of scaling at once are a usage error.
  EXPECT_EQ(run("eval " + path("sphere.hbox") + " " + path("sphere.off") + " --workspace real-size,mm=100").code, 2);
}
