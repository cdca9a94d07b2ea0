// The window's figures tell one story with the tool's: both query times measured the same way
// (and said how), the exported error-field image in the metric its caption names, the bake's
// whole time.
#include "ErrorFieldPanel.h"
#include "ReadoutPanel.h"
#include "vtkHapticBoxBakeFilter.h"
#include "SessionPipeline.h"
#include "window_test_support.h"
#include <QDir>
#include <QFileInfo>
#include <QImage>
#include <QListWidget>
#include <QPushButton>
#include <cmath>
#include <chrono>

using hbtest::openAndBake;
using hbtest::placeProbe;
using hbtest::pump;
using hbtest::waitFor;

TEST(WindowFiguresTest, ReadoutTimesBothAnswersTheSameWayAndSaysHow) {
  hbtest::MeshDir data;
  MainWindow w;
  w.show();
  openAndBake(w, data.mesh);
  ASSERT_TRUE(placeProbe(w));
  ASSERT_TRUE(waitFor([&] { return w.session()->reading().exactQueryNs > 0.0; }, 20));
  const ProbeReading r = w.session()->reading();
  EXPECT_GT(r.exactQueryNs, 0.0);
  EXPECT_GT(r.approxQueryNs, 0.0);
  for (int i = 0; i < 12; ++i) {
    pump(0.02);
    w.refresh();
  }
  const QString query = w.readoutPanel()->rowText(QStringLiteral("query"));
  EXPECT_TRUE(query.contains(QStringLiteral("median of %1 warm queries each").arg(ProbeReading::kTimingRepeats)))
      << query.toStdString();
  EXPECT_TRUE(query.contains(QStringLiteral("GUI thread")));
  EXPECT_FALSE(query.contains(QStringLiteral("cold")));
  // The servo thread's own per-tick figure is stated apart, as its own.
  if (r.deviceRunning) {
    EXPECT_TRUE(w.readoutPanel()->rowText(QStringLiteral("device")).contains(QStringLiteral("box query")));
  }
}

TEST(WindowFiguresTest, ExportedErrorFieldImageShowsTheMetricItsCaptionNames) {
  hbtest::MeshDir data;
  MainWindow w;
  w.show();
  openAndBake(w, data.mesh);
  w.errorFieldPanel()->computeButton()->click();
  ASSERT_TRUE(waitFor([&] { return w.session()->hasErrorField() && !w.session()->job()->isRunning(); }));
  // The relative force error as the window shows it: what the report's caption names.
  w.errorFieldPanel()->setMetric(ErrorMetric::RelativeForce);
  pump(0.2);
  const QString force = data.dir.filePath(QStringLiteral("force.png")), direction = data.dir.filePath(QStringLiteral("direction.png"));
  ASSERT_TRUE(w.exportScreenshot(force));
  w.errorFieldPanel()->setMetric(ErrorMetric::Direction);
  pump(0.2);
  ASSERT_TRUE(w.exportScreenshot(direction));
  const QString dir = data.dir.filePath(QStringLiteral("report"));
  ASSERT_TRUE(w.exportReport(dir, 1000));
  ASSERT_TRUE(waitFor([&] { return !w.session()->job()->isRunning(); }, 300));
  const QImage exported(dir + QStringLiteral("/error_field.png"));
  ASSERT_FALSE(exported.isNull());
  EXPECT_EQ(exported.convertToFormat(QImage::Format_RGB32), QImage(force).convertToFormat(QImage::Format_RGB32));
  EXPECT_NE(exported.convertToFormat(QImage::Format_RGB32), QImage(direction).convertToFormat(QImage::Format_RGB32));
  QFile html(dir + QStringLiteral("/report.html"));
  ASSERT_TRUE(html.open(QIODevice::ReadOnly));
  EXPECT_TRUE(html.readAll().contains("Metric shown: relative force error"));
  // The window still shows the metric the user chose.
  EXPECT_EQ(w.errorFieldPanel()->metric(), ErrorMetric::Direction);
}

TEST(WindowFiguresTest, BakeTimeIsTheWholeBakeNotOneStage) {
  hbtest::MeshDir data;
  MainWindow w;
  w.show();
  w.setBakeOnOpen(false);
  ASSERT_TRUE(w.openFile(data.mesh));
  BakeSettings b = w.session()->bakeSettings();
  b.useCache = false;  // a real bake (the default recipe: decomposition, budget search, tables, checks)
  w.session()->setBakeSettings(b);
  w.bakePanel()->showSettings();
  const auto start = std::chrono::steady_clock::now();
  w.bakePanel()->bakeButton()->click();
  ASSERT_TRUE(waitFor([&] { return w.session()->hasBoxes() && !w.session()->job()->isRunning(); }, 300));
  const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  const double stage = w.session()->model()->pipeline()->bake()->GetBakeSeconds();
  const double total = w.session()->bakeSeconds();
  std::printf("bake: %.3f s in all (one stage %.3f s), %.3f s seen by the test\n", total, stage, wall);
  EXPECT_GE(total, stage);
  EXPECT_LE(total, wall);
  EXPECT_GE(total, 0.7 * wall - 0.2);  // the test's wait adds event-loop polling only
  EXPECT_FALSE(w.session()->boxesFromCache());
}

TEST(WindowFiguresTest, AWorstVertexPutsTheProbeOnTheFieldsProbeThereAndTheCameraFollows) {
  hbtest::MeshDir data;
  MainWindow w;
  w.show();
  openAndBake(w, data.mesh);  // a small raw box (m 8, n 4): errors of several percent
  w.errorFieldPanel()->computeButton()->click();
  ASSERT_TRUE(waitFor([&] { return w.session()->hasErrorField() && !w.session()->job()->isRunning(); }));
  w.errorFieldPanel()->setMetric(ErrorMetric::RelativeForce);
  QListWidget* worst = w.errorFieldPanel()->worstList();
  ASSERT_GT(worst->count(), 0);
  const QVariantList v = worst->item(0)->data(Qt::UserRole).toList();
  ASSERT_EQ(v.size(), 7);
  const std::size_t vertex = std::size_t(v[6].toULongLong());
  const float fieldError = w.session()->errorField()->force_error[vertex];
  ASSERT_GT(fieldError, 0.f);
  emit worst->itemClicked(worst->item(0));
  // The readout shows the error the field measured there (the same segment; the window's
  // probe handle may be longer, which does not move the first hit).
  auto readoutError = [&] {
    const ProbeReading r = w.session()->reading();
    return r.exact.contact && r.approx.contact ? r.relativeError : -1.0;
  };
  EXPECT_TRUE(waitFor([&] { return std::abs(readoutError() - fieldError) <= 0.25 * fieldError; }, 10))
      << "readout " << readoutError() << ", field " << fieldError;
  // The camera is centred on the vertex.
  const hb::Vec3 p(v[0].toFloat(), v[1].toFloat(), v[2].toFloat());
  EXPECT_LT((w.probeView()->focalPoint() - p).norm(), 1e-3f * w.session()->diagonal());
}

TEST(WindowFiguresTest, TheReportDialogStartsWhereReportsGoNotInTheDatasetFolder) {
  hbtest::MeshDir data;
  MainWindow w;
  w.show();
  openAndBake(w, data.mesh);
  EXPECT_EQ(w.lastFolder(), QFileInfo(data.mesh).absolutePath());
  EXPECT_EQ(w.reportStartFolder(), QDir::homePath());
  QDir(data.dir.path()).mkdir(QStringLiteral("reports"));
  const QString dir = data.dir.filePath(QStringLiteral("reports/bumpy"));
  ASSERT_TRUE(w.exportReport(dir, 500));
  ASSERT_TRUE(waitFor([&] { return !w.session()->job()->isRunning(); }, 300));
  EXPECT_EQ(w.reportStartFolder(), data.dir.filePath(QStringLiteral("reports")));
}
