// The logic without widgets: session files, the background job, the servo rate monitor.
#include "BackgroundJob.h"
#include "SessionFile.h"
#include "errors.h"
#include "ui_test_support.h"
#include <QFile>
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

