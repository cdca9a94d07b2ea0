// The window end to end under a display: open, bake, probe with both arrows, error field,
// report, screenshot (checked pixel by pixel), cache, cancel, sessions, bad input.
#include "BackgroundJob.h"
#include "BakePanel.h"
#include "ChartsView.h"
#include "ErrorFieldPanel.h"
#include "HapticSession.h"
#include "MainWindow.h"
#include "ProbeView.h"
#include "ReadoutPanel.h"
#include "window_test_support.h"
#include <QDateTime>
#include <QDir>
#include <QDirIterator>
#include <QFile>
#include <functional>
#include <QTimer>
#include <QMessageBox>
#include <QFileInfo>
#include <QImage>
#include <QLabel>
#include <QListWidget>
#include <QPushButton>
#include <QDropEvent>
#include <QStatusBar>
#include <QMimeData>
#include <QUrl>
#include "vtkHapticBoxUtilities.h"
#include <vtkCommand.h>
#include <vtkXMLPolyDataWriter.h>
#include <vtkRenderWindow.h>
#include <vtkRenderWindowInteractor.h>
#include <gtest/gtest.h>

using hbtest::pump;
using hbtest::waitFor;
using hbtest::openAndBake;
using hbtest::placeProbe;
using hbtest::setSmallBake;

namespace {

/// Runs the window's sweep over m 8 and 12 (n 4, 1000 probes) and waits for its box points:
/// the two samplings and the default bake (as `hapticbox sweep`).
void runSmallSweep(MainWindow& w) {
  QString error;
  ASSERT_TRUE(w.session()->startSweep({8, 12}, {4}, 1000, &error)) << error.toStdString();
  ASSERT_TRUE(waitFor([&] { return !w.session()->job()->isRunning(); }, 300));
  ASSERT_EQ(w.chartsView()->pointCount(), 3u);
  EXPECT_EQ(w.chartsView()->boxRows().back().label.rfind("default bake", 0), 0u);
}

struct PixelCounts {
  int model = 0, exactArrow = 0, approxArrow = 0, total = 0;
};

/// Counts the model's beige pixels and the arrows' red (exact) and blue (box) ones.
PixelCounts countPixels(const QString& png) {
  PixelCounts c;
  QImage img(png);
  if (img.isNull()) return c;
  img = img.convertToFormat(QImage::Format_RGB32);
  for (int y = 0; y < img.height(); ++y)
    for (int x = 0; x < img.width(); ++x) {
      const QColor q(img.pixel(x, y));
      const int r = q.red(), g = q.green(), b = q.blue();
      ++c.total;
      if (r > 90 && r >= g && g >= b && r - b > 25 && !(g < 0.75 * r && b < 80)) ++c.model;
      // The series colours (series_colours.h): exact red, box blue, shaded.
      if (r > 120 && g < 0.45 * r && b < 0.45 * r) ++c.exactArrow;
      if (b > 100 && b > r + 60 && b > g + 30) ++c.approxArrow;
    }
  return c;
}

}  // namespace

TEST(MainWindowTest, OpensBakesAndShowsBothArrowsAtContact) {
  hbtest::MeshDir data;
  MainWindow w;
  w.show();
  openAndBake(w, data.mesh);
  EXPECT_TRUE(w.session()->servoRunning());
  ASSERT_TRUE(placeProbe(w));
  ASSERT_TRUE(waitFor([&] {
    const ProbeReading r = w.session()->reading();
    return r.exact.contact && r.approx.contact;
  }, 10.0));
  pump(0.7);
  w.refresh();
  EXPECT_TRUE(w.probeView()->exactArrowShown());
  EXPECT_TRUE(w.probeView()->approxArrowShown());
  const ProbeReading r = w.session()->reading();
  EXPECT_GT(r.exact.force.norm(), 0.f);
  EXPECT_LT(r.relativeError, 0.5);
  EXPECT_GT(r.rateHz, 500.0);  // the device thread runs at ~1 kHz
  for (int i = 0; i < 6; ++i) w.refresh();
  EXPECT_TRUE(w.readoutPanel()->rowText("exact").endsWith(" N"));
  EXPECT_TRUE(w.readoutPanel()->rowText("approx").endsWith(" N"));
  EXPECT_TRUE(w.readoutPanel()->rowText("device").contains("Hz"));
  // Whether a hand would feel the difference, against its threshold in newtons.
  const QString felt = w.readoutPanel()->rowText("felt");
  EXPECT_TRUE(felt.startsWith("no: ") || felt.startsWith("yes (")) << felt.toStdString();
  EXPECT_TRUE(felt.contains(" N against ")) << felt.toStdString();

  // Deeper means more force.
  const float before = r.exact.force.norm();
  w.session()->setDepthFraction(w.session()->depthFraction() + 0.01);
  pump(0.1);
  EXPECT_GT(w.session()->reading().exact.force.norm(), before);
}

TEST(MainWindowTest, ScreenshotShowsTheModelAndBothArrows) {
  hbtest::MeshDir data;
  MainWindow w;
  w.show();
  openAndBake(w, data.mesh);
  ASSERT_TRUE(placeProbe(w));
  w.session()->setDepthFraction(0.03);
  pump(1.0);
  w.refresh();
  const QString png = data.dir.filePath(QStringLiteral("shot.png"));
  ASSERT_TRUE(w.exportScreenshot(png));
  const PixelCounts c = countPixels(png);
  ASSERT_GT(c.total, 10000);
  EXPECT_GT(c.model, c.total / 50) << "the model covers too few pixels: blank screenshot?";
  EXPECT_GT(c.exactArrow, 20) << "no red (exact) arrow pixels";
  EXPECT_GT(c.approxArrow, 20) << "no blue (haptic box) arrow pixels";
}

TEST(MainWindowTest, ComputesTheErrorFieldAndExportsAReport) {
  hbtest::MeshDir data;
  MainWindow w;
  w.show();
  openAndBake(w, data.mesh);
  w.errorFieldPanel()->computeButton()->click();
  ASSERT_TRUE(waitFor([&] { return w.session()->hasErrorField() && !w.session()->job()->isRunning(); }));
  EXPECT_EQ(w.session()->errorField()->size(), w.session()->mesh().vertex_count());
  EXPECT_EQ(w.probeView()->colorMode(), ProbeView::ColorMode::ErrorField);
  EXPECT_TRUE(w.probeView()->scalarBarShown());
  w.errorFieldPanel()->setMetric(ErrorMetric::Direction);
  EXPECT_TRUE(w.probeView()->scalarBarShown());

  const QString dir = data.dir.filePath(QStringLiteral("report"));
  ASSERT_TRUE(w.exportReport(dir, 2000));
  ASSERT_TRUE(waitFor([&] { return !w.session()->job()->isRunning(); }, 300));
  for (const char* f : {"report.html", "summary.json", "samples.csv", "error_field.png"})
    EXPECT_TRUE(QFileInfo::exists(dir + "/" + f)) << f;
  QFile html(dir + "/report.html");
  ASSERT_TRUE(html.open(QIODevice::ReadOnly));
  EXPECT_TRUE(html.readAll().contains("data:image/png;base64"));
  EXPECT_GT(w.session()->sweepRows().size(), 1u);
}

TEST(MainWindowTest, ReopeningUsesTheCachedBake) {
  hbtest::MeshDir data;
  {
    MainWindow w;
    openAndBake(w, data.mesh);
  }
  // The first window's bake is the cache's one entry; reopening must load it as it is
  // (the same file, not rewritten) with no bake job, even with Bake on Open off.
  const QDir cache(data.dir.filePath(QStringLiteral("xdg-cache")));
  const auto entries = [&] {
    QStringList files;
    QDirIterator it(cache.path(), {QStringLiteral("*.hbox")}, QDir::Files, QDirIterator::Subdirectories);
    while (it.hasNext()) files << it.next();
    return files;
  };
  const QStringList before = entries();
  ASSERT_EQ(before.size(), 1);
  const QDateTime written = QFileInfo(before.front()).lastModified();
  const qint64 bytes = QFileInfo(before.front()).size();
  MainWindow w;
  w.setBakeOnOpen(false);
  setSmallBake(*w.session());
  bool jobStarted = false;
  QObject::connect(w.session()->job(), &BackgroundJob::started, [&] { jobStarted = true; });
  ASSERT_TRUE(w.openFile(data.mesh));
  pump(0.2);
  EXPECT_TRUE(w.session()->hasBoxes());
  EXPECT_TRUE(w.session()->boxesFromCache());
  EXPECT_FALSE(jobStarted) << "reopening ran a job: the cached bake was not used";
  EXPECT_EQ(entries(), before);
  EXPECT_EQ(QFileInfo(before.front()).lastModified(), written) << "the cache entry was rewritten";
  EXPECT_EQ(QFileInfo(before.front()).size(), bytes);
  bool saysFromCache = false;  // the panel's summary: "N box(es), m .., n .., .., from the cache"
  for (const QLabel* l : w.bakePanel()->findChildren<QLabel*>())
    saysFromCache |= l->text().endsWith(QStringLiteral("from the cache"));
  EXPECT_TRUE(saysFromCache);
  // The cache is the shared one (XDG), shown and clearable in the bake panel; nothing is
  // written next to the model.
  EXPECT_FALSE(QFileInfo::exists(data.dir.filePath(QStringLiteral(".hapticbox-cache"))));
  EXPECT_TRUE(w.session()->cacheDir().startsWith(data.dir.filePath(QStringLiteral("xdg-cache"))));
  EXPECT_EQ(w.session()->cacheUsage().files, 1u);
  EXPECT_TRUE(w.bakePanel()->cacheLabel()->text().startsWith(QStringLiteral("1 box file")));
  ASSERT_TRUE(w.bakePanel()->clearCacheButton()->isEnabled());
  w.bakePanel()->clearCacheButton()->click();
  EXPECT_EQ(w.session()->cacheUsage().files, 0u);
  EXPECT_TRUE(w.session()->hasBoxes());  // the boxes in use stay
  EXPECT_TRUE(w.bakePanel()->cacheLabel()->text().startsWith(QStringLiteral("0 box file")));
}

TEST(MainWindowTest, CancellingABakeLeavesNoBoxes) {
  hbtest::MeshDir data;
  MainWindow w;
  w.setBakeOnOpen(false);
  ASSERT_TRUE(w.openFile(data.mesh));
  BakeSettings b = w.session()->bakeSettings();
  b.advanced = true;
  b.m = 32;  // 150 MB of tables: long enough to cancel, small enough for a shared machine
  b.n = 16;
  b.useCache = false;
  w.session()->setBakeSettings(b);
  w.bakePanel()->showSettings();
  w.bakePanel()->bakeButton()->click();
  ASSERT_TRUE(w.session()->job()->isRunning());
  pump(0.2);
  w.bakePanel()->cancelButton()->click();
  ASSERT_TRUE(waitFor([&] { return !w.session()->job()->isRunning(); }, 60));
  EXPECT_FALSE(w.session()->hasBoxes());
  EXPECT_TRUE(w.bakePanel()->bakeButton()->isEnabled());
}

TEST(MainWindowTest, BadFilesAreReportedNotFatal) {
  hbtest::MeshDir data;
  MainWindow w;
  const QString garbage = data.dir.filePath(QStringLiteral("garbage.off"));
  QFile f(garbage);
  ASSERT_TRUE(f.open(QIODevice::WriteOnly));
  f.write("OFF\n3 1 0\n0 0 0\nnan 1 0\n");
  f.close();
  EXPECT_FALSE(w.openFile(garbage));
  EXPECT_FALSE(w.openFile(data.dir.filePath(QStringLiteral("missing.off"))));
  EXPECT_FALSE(w.openFile(data.dir.filePath(QStringLiteral("model.xyz"))));
  EXPECT_FALSE(w.session()->hasMesh());
  // A good file still opens afterwards.
  w.setBakeOnOpen(false);
  EXPECT_TRUE(w.openFile(data.mesh));
}

TEST(MainWindowTest, AFileItCannotOpenInteractivelyGetsADialogNamingTheFileAndTheCause) {
  hbtest::MeshDir data;
  MainWindow w;
  w.show();
  // What the dialog says, read (and closed) by a timer while it waits for the user.
  const auto dialogText = [&](const std::function<bool()>& open) {
    QString text;
    QTimer closer;
    closer.setInterval(50);
    QObject::connect(&closer, &QTimer::timeout, [&] {
      if (auto* box = qobject_cast<QMessageBox*>(QApplication::activeModalWidget())) {
        text = box->text();
        box->accept();
      }
    });
    closer.start();
    EXPECT_FALSE(open());
    closer.stop();
    return text;
  };
  const QString missing = data.dir.filePath(QStringLiteral("missing.off"));
  QString text = dialogText([&] { return w.openFile(missing, true); });
  EXPECT_TRUE(text.contains(missing)) << text.toStdString();
  EXPECT_TRUE(text.contains(QStringLiteral("no such file"))) << text.toStdString();
  EXPECT_EQ(w.lastError(), text);
  // A session whose model is gone: the dialog names the model, lastError the session too.
  const QString session = data.dir.filePath(QStringLiteral("lost.hbsession"));
  QFile f(session);
  ASSERT_TRUE(f.open(QIODevice::WriteOnly));
  f.write(R"({"format":"hapticbox-session","version":1,"mesh":"gone.off","bake":{"recipe":"default"}})");
  f.close();
  text = dialogText([&] { return w.openFile(session, true); });
  EXPECT_TRUE(text.contains(QStringLiteral("gone.off"))) << text.toStdString();
  EXPECT_TRUE(w.lastError().contains(QStringLiteral("lost.hbsession"))) << w.lastError().toStdString();
}

TEST(MainWindowTest, SessionFileReopensModelBoxesAndCamera) {
  hbtest::MeshDir data;
  const QString path = data.dir.filePath(QStringLiteral("s.hbsession"));
  CameraState camera;
  {
    MainWindow w;
    w.show();
    openAndBake(w, data.mesh);
    w.session()->setDepthFraction(0.02);
    camera = w.probeView()->cameraState();
    ASSERT_TRUE(w.saveSession(path));
  }
  MainWindow w;
  w.show();
  ASSERT_TRUE(w.openFile(path));
  EXPECT_EQ(w.session()->meshPath(), QFileInfo(data.mesh).absoluteFilePath());
  EXPECT_TRUE(w.session()->hasBoxes());  // from the cache
  EXPECT_EQ(w.session()->bakeSettings().m, 8);
  EXPECT_NEAR(w.session()->depthFraction(), 0.02, 1e-9);
  const CameraState c = w.probeView()->cameraState();
  for (int i = 0; i < 3; ++i) EXPECT_NEAR(c.position[i], camera.position[i], 1e-6);
}

TEST(MainWindowTest, WithoutAFalconTheVirtualDeviceIsUsed) {
  MainWindow w;
  QString note;
  EXPECT_FALSE(w.session()->setDevice(DeviceKind::Falcon, {}, &note));
  EXPECT_EQ(w.session()->deviceKind(), DeviceKind::Virtual);
  EXPECT_FALSE(note.isEmpty());
}

TEST(MainWindowTest, DraggingOnTheModelMovesTheProbe) {
  hbtest::MeshDir data;
  MainWindow w;
  w.show();
  openAndBake(w, data.mesh);
  pump(0.3);
  vtkRenderWindowInteractor* rwi = w.probeView()->interactor();
  const int* size = w.probeView()->renderWindow()->GetSize();
  const int x = size[0] / 2, y = size[1] / 2;
  rwi->SetEventInformation(x, y);
  rwi->InvokeEvent(vtkCommand::LeftButtonPressEvent);
  ASSERT_TRUE(w.session()->surfacePoint().has_value()) << "a press on the model places the probe";
  const hb::Vec3 first = *w.session()->surfacePoint();
  rwi->SetEventInformation(x + 15, y + 10);
  rwi->InvokeEvent(vtkCommand::MouseMoveEvent);
  rwi->InvokeEvent(vtkCommand::LeftButtonReleaseEvent);
  EXPECT_GT((*w.session()->surfacePoint() - first).norm(), 0.f) << "the drag moves the tip";
  ASSERT_TRUE(waitFor([&] { return w.session()->reading().approx.contact; }, 5.0));
  // Ctrl+wheel pushes deeper.
  const double depth = w.session()->depthFraction();
  rwi->SetControlKey(1);
  rwi->InvokeEvent(vtkCommand::MouseWheelForwardEvent);
  rwi->SetControlKey(0);
  EXPECT_GT(w.session()->depthFraction(), depth);
  // A press off the model rotates the camera instead.
  const hb::Vec3 placed = *w.session()->surfacePoint();
  rwi->SetEventInformation(2, 2);
  rwi->InvokeEvent(vtkCommand::LeftButtonPressEvent);
  rwi->InvokeEvent(vtkCommand::LeftButtonReleaseEvent);
  EXPECT_EQ(*w.session()->surfacePoint(), placed);
}

TEST(MainWindowTest, DroppingAFileOpensIt) {
  hbtest::MeshDir data;
  MainWindow w;
  w.setBakeOnOpen(false);
  EXPECT_FALSE(w.openDroppedUrls({QUrl(QStringLiteral("https://example.org/a.off"))}));
  EXPECT_FALSE(w.session()->hasMesh());
  EXPECT_TRUE(w.openDroppedUrls({QUrl::fromLocalFile(data.mesh)}));
  EXPECT_TRUE(w.session()->hasMesh());
}

TEST(MainWindowTest, AMissingReplayLogFallsBackToTheVirtualDevice) {
  MainWindow w;
  QString note;
  EXPECT_FALSE(w.session()->setDevice(DeviceKind::Replay, QStringLiteral("/nonexistent/run.hblog"), &note));
  EXPECT_EQ(w.session()->deviceKind(), DeviceKind::Virtual);
  EXPECT_TRUE(note.contains("virtual"));
}

TEST(MainWindowTest, SweepFillsTheChartAndAPointLoadsItsConfiguration) {
  hbtest::MeshDir data;
  MainWindow w;
  w.show();
  openAndBake(w, data.mesh);
  ASSERT_NO_FATAL_FAILURE(runSmallSweep(w));
  w.chartsView()->choose(1);  // what a click on the m 12 point does
  EXPECT_EQ(w.session()->bakeSettings().m, 12);
  ASSERT_TRUE(waitFor([&] { return !w.session()->job()->isRunning(); }, 120));
  ASSERT_TRUE(w.session()->hasBoxes());
  EXPECT_EQ(w.session()->boxes()->parts().boxes.front().params().m, 12);
}

TEST(MainWindowTest, APieceFileBakesOneBoxPerPieceAndABadOneIsReported) {
  hbtest::MeshDir data;
  MainWindow w;
  w.setBakeOnOpen(false);
  ASSERT_TRUE(w.openFile(data.mesh));
  const hb::TriangleMesh& mesh = w.session()->mesh();
  const QString good = data.dir.filePath(QStringLiteral("halves.pieces"));
  {
    QFile f(good);
    ASSERT_TRUE(f.open(QIODevice::WriteOnly));
    for (const auto& t : mesh.triangles) f.write(mesh.positions[t[0]].z() > 0.f ? "7\n" : "3\n");
  }
  BakeSettings b = w.session()->bakeSettings();
  b.advanced = true;
  b.m = 8;
  b.n = 4;
  b.pieces = BakeSettings::Pieces::File;
  b.piecesFile = good;
  w.session()->setBakeSettings(b);
  w.bakePanel()->showSettings();
  w.bakePanel()->bakeButton()->click();
  ASSERT_TRUE(waitFor([&] { return !w.session()->job()->isRunning(); }));
  ASSERT_TRUE(w.session()->hasBoxes());
  EXPECT_EQ(w.session()->boxes()->parts().boxes.size(), 2u);
  EXPECT_EQ(w.session()->outlines()->GetNumberOfLines(), 24);

  const QString bad = data.dir.filePath(QStringLiteral("short.pieces"));
  {
    QFile f(bad);
    ASSERT_TRUE(f.open(QIODevice::WriteOnly));
    f.write("0\n1\n");
  }
  b.piecesFile = bad;
  w.session()->setBakeSettings(b);
  w.bakePanel()->showSettings();
  QString message;
  QObject::connect(w.session(), &HapticSession::jobFinished,
                   [&](const QString&, bool ok, const QString& m) { message = ok ? QString() : m; });
  w.bakePanel()->bakeButton()->click();
  ASSERT_TRUE(waitFor([&] { return !w.session()->job()->isRunning(); }));
  EXPECT_TRUE(message.contains("piece ids")) << message.toStdString();
  EXPECT_EQ(w.session()->boxes()->parts().boxes.size(), 2u) << "the previous boxes stay";
}

TEST(MainWindowTest, OpensVtkPolyDataFiles) {
  hbtest::MeshDir data;
  const hb::TriangleMesh mesh = hb::read_mesh(QFile::encodeName(data.mesh).toStdString());
  const QString vtp = data.dir.filePath(QStringLiteral("bumpy.vtp"));
  auto writer = vtkSmartPointer<vtkXMLPolyDataWriter>::New();
  writer->SetInputData(vtkHapticBoxUtilities::ToPolyData(mesh));
  writer->SetFileName(QFile::encodeName(vtp).constData());
  ASSERT_EQ(writer->Write(), 1);
  MainWindow w;
  w.setBakeOnOpen(false);
  ASSERT_TRUE(w.openFile(vtp));
  EXPECT_EQ(w.session()->mesh().triangle_count(), mesh.triangle_count());
}

TEST(MainWindowTest, AutomaticPiecesAndTheBlockCodecBakeACompressedSceneOfSeveralBoxes) {
  // A torus has pockets along its own lines: the automatic decomposition splits it.
  QTemporaryDir dir;
  const QString mesh = dir.filePath(QStringLiteral("torus.off"));
  hb::write_mesh(hb::make_torus(40.f, 12.f, 96, 32), QFile::encodeName(mesh).toStdString());
  MainWindow w;
  w.setBakeOnOpen(false);
  ASSERT_TRUE(w.openFile(mesh));
  BakeSettings b = w.session()->bakeSettings();
  b.advanced = true;
  b.m = 8;
  b.n = 4;
  b.pieces = BakeSettings::Pieces::Automatic;
  b.codec = QStringLiteral("block");
  b.refine = true;
  b.useCache = false;
  w.session()->setBakeSettings(b);
  w.bakePanel()->showSettings();
  w.bakePanel()->bakeButton()->click();
  ASSERT_TRUE(waitFor([&] { return !w.session()->job()->isRunning(); }));
  ASSERT_TRUE(w.session()->hasBoxes());
  EXPECT_GT(w.session()->boxes()->parts().boxes.size(), 1u);
  for (const hb::HapticBox& box : w.session()->boxes()->parts().boxes) {
    EXPECT_EQ(box.codec(), hb::CodecId::block);
    EXPECT_TRUE(box.refines());  // the panel's "Refine exactly" reached the bake
  }
}

TEST(MainWindowTest, ErrorFieldUsesViridisNamesTheMetricAndListsWorstVerticesThatMoveTheProbe) {
  hbtest::MeshDir data;
  MainWindow w;
  w.show();
  openAndBake(w, data.mesh);
  w.errorFieldPanel()->computeButton()->click();
  ASSERT_TRUE(waitFor([&] { return w.session()->hasErrorField() && !w.session()->job()->isRunning(); }));
  // The summary names the metric shown, in its unit, and the vertices without data.
  auto* info = w.errorFieldPanel()->findChildren<QLabel*>().first();
  QString text;
  for (QLabel* l : w.errorFieldPanel()->findChildren<QLabel*>())
    if (l->text().contains("points,")) text = l->text();
  // The default metric: where a hand would feel the difference.
  EXPECT_EQ(w.errorFieldPanel()->metric(), ErrorMetric::Perceptible);
  EXPECT_TRUE(text.contains("a hand would feel the difference at")) << text.toStdString();
  EXPECT_TRUE(text.contains("no data")) << text.toStdString();
  (void)info;
  w.errorFieldPanel()->setMetric(ErrorMetric::RelativeForce);
  for (QLabel* l : w.errorFieldPanel()->findChildren<QLabel*>())
    if (l->text().contains("points,")) text = l->text();
  EXPECT_TRUE(text.contains("median relative force error")) << text.toStdString();
  w.errorFieldPanel()->setMetric(ErrorMetric::Direction);
  for (QLabel* l : w.errorFieldPanel()->findChildren<QLabel*>())
    if (l->text().contains("points,")) text = l->text();
  EXPECT_TRUE(text.contains("median direction error")) << text.toStdString();
  EXPECT_FALSE(text.contains("force error")) << text.toStdString();
  w.errorFieldPanel()->setMetric(ErrorMetric::ContactDisagreement);
  for (QLabel* l : w.errorFieldPanel()->findChildren<QLabel*>())
    if (l->text().contains("points,")) text = l->text();
  EXPECT_TRUE(text.contains("contacts disagree at")) << text.toStdString();
  // Worst vertices for the metric shown; a click moves the probe onto that vertex.
  w.errorFieldPanel()->setMetric(ErrorMetric::RelativeForce);
  QListWidget* worst = w.errorFieldPanel()->worstList();
  ASSERT_GT(worst->count(), 0);
  ASSERT_TRUE(worst->item(0)->text().contains("%")) << worst->item(0)->text().toStdString();
  const QVariantList v = worst->item(0)->data(Qt::UserRole).toList();
  ASSERT_EQ(v.size(), 7);  // position, normal, vertex index
  emit worst->itemClicked(worst->item(0));
  const hb::Vec3 vertex(v[0].toFloat(), v[1].toFloat(), v[2].toFloat());
  // The probe line comes to pass through the vertex (the virtual device follows its target;
  // the tip is pushed past the vertex along the inward normal).
  auto offLine = [&] {
    const ProbeReading r = w.session()->reading();
    if (!r.placed) return 1e30f;
    const hb::Vec3 d = (r.segment.end - r.segment.start).normalized();
    return ((vertex - r.segment.start) - d * d.dot(vertex - r.segment.start)).norm();
  };
  EXPECT_TRUE(waitFor([&] { return offLine() < 2e-3f * w.session()->diagonal(); }, 10)) << offLine();
  // The screenshot of the field uses viridis (no pure red of the old rainbow map).
  const QString png = data.dir.filePath(QStringLiteral("field.png"));
  w.probeView()->saveScreenshot(png);
  QImage img(png);
  ASSERT_FALSE(img.isNull());
  int rainbowRed = 0, viridisish = 0;
  for (int y = 0; y < img.height(); y += 2)
    for (int x = 0; x < img.width(); x += 2) {
      if (x < 0.15 * img.width() && y > 0.78 * img.height()) continue;  // the orientation axes (red X)
      const QColor q(img.pixel(x, y));
      // Pure red (the rainbow's top; the exact arrow's red, 214 39 40, stays below 235).
      if (q.red() > 235 && q.green() < 60 && q.blue() < 60) ++rainbowRed;
      if (q.green() > q.red() && q.blue() > q.red() + 20 && q.red() < 90) ++viridisish;  // teal-blue band
    }
  EXPECT_EQ(rainbowRed, 0);
  EXPECT_GT(viridisish, 50);
  // For a person to look at: HB_SCREENSHOT_DIR keeps the view and the whole window.
  if (const char* keep = std::getenv("HB_SCREENSHOT_DIR")) {
    QFile::copy(png, QString::fromLocal8Bit(keep) + "/error_field_view.png");
    w.grab().save(QString::fromLocal8Bit(keep) + "/error_field_window.png");
    w.errorFieldPanel()->setMetric(ErrorMetric::ContactDisagreement);
    pump(0.3);
    w.probeView()->saveScreenshot(QString::fromLocal8Bit(keep) + "/contact_disagreement_view.png");
  }
}

TEST(MainWindowTest, ChartsLabelRealTimesNameConfigurationsAndAReportKeepsTheSweep) {
  hbtest::MeshDir data;
  MainWindow w;
  w.show();
  openAndBake(w, data.mesh);
  ASSERT_NO_FATAL_FAILURE(runSmallSweep(w));
  const std::size_t sweepRows = w.session()->sweepRows().size();
  // Tick labels are times ("1 us", "200 ns"), not log10 numbers.
  const std::vector<std::string> ticks = w.chartsView()->speedAxisLabels();
  ASSERT_FALSE(ticks.empty());
  for (const std::string& t : ticks) EXPECT_TRUE(t.find("s") != std::string::npos) << t;
  // The tooltip says which configuration a point is.
  const std::string tip = w.chartsView()->speedTooltip(0);
  EXPECT_NE(tip.find("m 8, n 4"), std::string::npos) << tip;
  EXPECT_NE(tip.find("a query"), std::string::npos) << tip;
  EXPECT_EQ(w.chartsView()->legendEntries(), 3);  // box, exact, VTK: the series present
  EXPECT_FALSE(w.chartsView()->tooltipVisible());
  // Exporting a report measures fewer rows; it does not replace the sweep's chart.
  ASSERT_TRUE(w.exportReport(data.dir.filePath(QStringLiteral("rep")), 500));
  ASSERT_TRUE(waitFor([&] { return !w.session()->job()->isRunning(); }, 300));
  EXPECT_EQ(w.session()->sweepRows().size(), sweepRows);
  EXPECT_EQ(w.chartsView()->pointCount(), 3u);
}

TEST(MainWindowTest, ReadoutWithoutAModelSaysHowToOpenOne) {
  MainWindow w;
  w.show();
  ASSERT_TRUE(waitFor([&] { return w.readoutPanel()->rowText("depth").contains("File > Open"); }, 10));
  EXPECT_FALSE(w.readoutPanel()->rowText("depth").contains("drag on the model"));
}
