// The logic without widgets: session files, the background job, the servo rate monitor.
#include "BackgroundJob.h"
#include "HapticSession.h"
#include "SessionFile.h"
#include "errors.h"
#include "ui_test_support.h"
#include <QFile>
#include <QProcess>
#include <nlohmann/json.hpp>
#include <gtest/gtest.h>
#include <thread>

TEST(SessionFileTest, RoundTripsEveryField) {
  QTemporaryDir dir;
  SessionState s;
  s.meshPath = dir.filePath("model.off");
  s.bake.m = 24;
  s.bake.n = 6;
  s.bake.padding = 0.02f;
  s.bake.refine = true;
  s.baked = true;
  s.depthFraction = 0.03;
  s.tiltDegrees = 30;
  s.outlines = true;
  s.metric = ErrorMetric::Direction;
  s.hasCamera = true;
  s.camera.position = {1, 2, 3};
  s.hasProbe = true;
  s.probePoint = {0.5f, -1.25f, 7.f};
  saveSessionFile(s, dir.filePath("a.hbsession"));
  const SessionState t = loadSessionFile(dir.filePath("a.hbsession"));
  EXPECT_EQ(t.meshPath, s.meshPath);
  EXPECT_EQ(t.bake.m, 24);
  EXPECT_EQ(t.bake.n, 6);
  EXPECT_FLOAT_EQ(t.bake.padding, 0.02f);
  EXPECT_TRUE(t.bake.refine);
  EXPECT_TRUE(t.baked);
  EXPECT_DOUBLE_EQ(t.tiltDegrees, 30);
  EXPECT_TRUE(t.outlines);
  EXPECT_EQ(t.metric, ErrorMetric::Direction);
  EXPECT_EQ(t.camera.position[2], 3);
  EXPECT_TRUE(t.hasProbe);
  EXPECT_FLOAT_EQ(t.probePoint[1], -1.25f);
  s.hasProbe = false;  // a probe never placed stays unplaced
  saveSessionFile(s, dir.filePath("b.hbsession"));
  EXPECT_FALSE(loadSessionFile(dir.filePath("b.hbsession")).hasProbe);
}

TEST(SessionFileTest, GarbageIsInvalidInput) {
  QTemporaryDir dir;
  QFile f(dir.filePath("b.hbsession"));
  ASSERT_TRUE(f.open(QIODevice::WriteOnly));
  f.write("{ not json");
  f.close();
  EXPECT_THROW(loadSessionFile(dir.filePath("b.hbsession")), hb::InvalidInput);
  EXPECT_THROW(loadSessionFile(dir.filePath("missing.hbsession")), hb::IoError);
}

TEST(BackgroundJobTest, CancelStopsTheWorkAndReportsCancelled) {
  BackgroundJob job;
  bool finished = false, cancelled = false;
  QObject::connect(&job, &BackgroundJob::finished, [&](bool, bool c, const QString&) {
    finished = true;
    cancelled = c;
  });
  ASSERT_TRUE(job.start("spin", [](const auto& progress) {
    for (int i = 0;; ++i) {
      if (!progress(0.0)) throw hb::Cancelled("spin cancelled");
      std::this_thread::sleep_for(std::chrono::milliseconds(1));
    }
  }));
  EXPECT_FALSE(job.start("second", [](const auto&) {}));
  job.cancel();
  ASSERT_TRUE(hbtest::waitFor([&] { return finished; }, 10));
  EXPECT_TRUE(cancelled);
  EXPECT_FALSE(job.isRunning());
}


namespace {

// summary.json without what differs between two runs of the same report: timings (and what
// is derived from them: the Pareto front, speed verdicts), cache hits, the image and its note.
nlohmann::json withoutTimings(const nlohmann::json& j) {
  if (j.is_array()) {
    nlohmann::json out = nlohmann::json::array();
    for (const auto& x : j) out.push_back(withoutTimings(x));
    return out;
  }
  if (!j.is_object()) return j;
  nlohmann::json out = nlohmann::json::object();
  for (auto it = j.begin(); it != j.end(); ++it) {
    const std::string& k = it.key();
    bool timing = false;
    for (const char* w : {"_ns", "seconds", "timing", "pareto", "from_cache", "image", "note", "faster", "slower",
                          "speedup", "loaded_from_file", "stamp", "command_line", "date", "machine", "host", "verdict", "generated",
                          "summary_text"})
      timing |= k.find(w) != std::string::npos;
    if (!timing) out[k] = withoutTimings(*it);
  }
  return out;
}

nlohmann::json readJson(const QString& path) {
  QFile f(path);
  if (!f.open(QIODevice::ReadOnly)) return {};
  return nlohmann::json::parse(f.readAll().toStdString());
}

}  // namespace

// The window's Export Error Report and `hapticbox report BOX MESH` build one ReportRequest
// (report/report_request.h): the same box and mesh give the same summary.json, timings aside,
// with the references' real memory and build times.
TEST(SessionReportTest, WindowAndCommandLineGiveTheSameReport) {
  hbtest::MeshDir data;
  HapticSession s;
  ASSERT_TRUE(s.openMesh(data.mesh));
  BakeSettings b = s.bakeSettings();
  b.m = 8;
  b.n = 4;
  s.setBakeSettings(b);
  ASSERT_TRUE(s.startBake());
  ASSERT_TRUE(hbtest::waitFor([&] { return !s.job()->isRunning(); }, 300));
  ASSERT_TRUE(s.hasBoxes());
  const QString box = data.dir.filePath(QStringLiteral("bumpy.hbox"));
  ASSERT_TRUE(s.saveBoxFile(box));
  ASSERT_TRUE(s.openBoxFile(box));

  const QString windowDir = data.dir.filePath(QStringLiteral("window-report"));
  QString error;
  ASSERT_TRUE(s.startReport(windowDir, QString(), 1000, &error)) << error.toStdString();
  ASSERT_TRUE(hbtest::waitFor([&] { return !s.job()->isRunning(); }, 300));

  const QString cliDir = data.dir.filePath(QStringLiteral("cli-report"));
  QProcess cli;
  cli.start(QStringLiteral(HB_CLI_PATH), {QStringLiteral("report"), box, s.meshPath(), QStringLiteral("-o"), cliDir,
                                          QStringLiteral("--samples"), QStringLiteral("1000"), QStringLiteral("--no-image")});
  ASSERT_TRUE(cli.waitForFinished(300000));
  ASSERT_EQ(cli.exitCode(), 0) << cli.readAllStandardError().toStdString();

  const nlohmann::json window = readJson(windowDir + "/summary.json"), line = readJson(cliDir + "/summary.json");
  ASSERT_FALSE(window.is_null());
  ASSERT_FALSE(line.is_null());
  EXPECT_EQ(withoutTimings(window).dump(1), withoutTimings(line).dump(1));
  // Both measured the same references, with their real costs.
  for (const nlohmann::json* j : {&window, &line}) {
    bool exact = false, vtk = false;
    for (const auto& row : (*j)["sweep"]) {
      if (row["method"] == "exact_embree") exact = row["memory_bytes"].get<double>() > 0;
      if (row["method"] == "vtk_static_cell_locator") vtk = row["memory_bytes"].get<double>() > 0;
    }
    EXPECT_TRUE(exact);
    EXPECT_TRUE(vtk);
  }
  EXPECT_GT(window["sweep"].size(), 2u);  // the default sweep ran in the window too
}
