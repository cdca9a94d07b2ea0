// The desktop basics: preferences that persist, toolbar, orientation
// axes and view buttons, screenshots at a resolution with a transparent background, the probe
// in sessions, last folders, readable arrows, job feedback that is current and complete, docks
// that keep their width.
#include "DevicePanel.h"
#include "ReadoutPanel.h"
#include "ScreenshotDialog.h"
#include "SessionFile.h"
#include "StabilityPanel.h"
#include "stability/stability_suite.h"
#include "window_test_support.h"
#include "series_colours.h"
#include <QAction>
#include <QCheckBox>
#include <QComboBox>
#include <QDir>
#include <QDockWidget>
#include <QFile>
#include <QFileInfo>
#include <QImage>
#include <QLabel>
#include <QProgressBar>
#include <QSettings>
#include <QSpinBox>
#include <QTableWidget>
#include <QStatusBar>
#include <QToolBar>
#include <chrono>
#include <cstdlib>
#include <set>

using hbtest::openAndBake;
using hbtest::placeProbe;
using hbtest::pump;
using hbtest::waitFor;

namespace {

QAction* toolAction(MainWindow& w, const QString& text) {
  for (QAction* a : w.toolBar()->actions())
    if (a->iconText() == text || a->text() == text) return a;
  return nullptr;
}

}  // namespace

TEST(DesktopBasicsTest, PreferencesPersistInATemporarySettingsFileNotTheUsers) {
  const QString file = QSettings().fileName();
  EXPECT_FALSE(file.startsWith(QDir::homePath() + QStringLiteral("/.config"))) << file.toStdString();
  QSize size;
  {
    MainWindow w;
    w.show();
    BakeSettings b = w.session()->bakeSettings();
    b.advanced = true;
    b.m = 23;
    b.n = 6;
    b.codec = QStringLiteral("block");
    b.refine = true;
    w.session()->setBakeSettings(b);
    w.bakePanel()->showSettings();
    w.findChild<QDockWidget*>(QStringLiteral("ReadoutDock"))->hide();
    w.findChild<QDockWidget*>(QStringLiteral("ChartsDock"))->show();
    w.probeView()->setOrientationAxesVisible(false);
    for (QAction* a : w.findChildren<QAction*>())
      if (a->text() == QStringLiteral("Orientation &Axes")) a->setChecked(false);
    w.resize(1100, 780);
    pump(0.2);
    size = w.size();
    w.close();  // writes the preferences
  }
  ASSERT_TRUE(QFileInfo::exists(file));
  MainWindow w;
  w.show();
  pump(0.2);
  EXPECT_TRUE(w.session()->bakeSettings().advanced);
  EXPECT_EQ(w.session()->bakeSettings().m, 23);
  EXPECT_EQ(w.session()->bakeSettings().n, 6);
  EXPECT_EQ(w.session()->bakeSettings().codec, QStringLiteral("block"));
  EXPECT_TRUE(w.session()->bakeSettings().refine);
  EXPECT_FALSE(w.findChild<QDockWidget*>(QStringLiteral("ReadoutDock"))->isVisible());
  EXPECT_TRUE(w.findChild<QDockWidget*>(QStringLiteral("ChartsDock"))->isVisible());
  EXPECT_FALSE(w.probeView()->orientationAxesVisible());
  EXPECT_EQ(w.size(), size);
  EXPECT_EQ(w.size().width(), 1100);
}

TEST(DesktopBasicsTest, FileDialogsStartInTheLastFolderUsed) {
  hbtest::MeshDir data;
  MainWindow w;
  EXPECT_EQ(w.lastFolder(), QDir::currentPath());  // nothing remembered yet
  w.setBakeOnOpen(false);
  ASSERT_TRUE(w.openFile(data.mesh));
  EXPECT_EQ(w.lastFolder(), QFileInfo(data.mesh).absolutePath());
  QDir(data.dir.path()).mkdir(QStringLiteral("shots"));
  const QString shot = data.dir.filePath(QStringLiteral("shots/a.png"));
  w.show();
  pump(0.3);
  ASSERT_TRUE(w.exportScreenshot(shot));
  MainWindow next;  // a later run starts there too
  EXPECT_EQ(next.lastFolder(), QFileInfo(shot).absolutePath());
}

TEST(DesktopBasicsTest, ToolbarViewButtonsAndOrientationAxes) {
  hbtest::MeshDir data;
  MainWindow w;
  w.show();
  w.setBakeOnOpen(false);
  ASSERT_TRUE(w.openFile(data.mesh));
  pump(0.3);
  ASSERT_NE(w.toolBar(), nullptr);
  for (const char* t : {"Open", "Save Session", "Bake", "Cancel", "Screenshot", "Reset", "+X", "-X", "+Y", "-Y", "+Z", "-Z"})
    EXPECT_NE(toolAction(w, QString::fromLatin1(t)), nullptr) << t;
  EXPECT_TRUE(w.probeView()->orientationAxesVisible());
  EXPECT_FALSE(toolAction(w, QStringLiteral("Cancel"))->isEnabled());  // no job running
  const struct { const char* text; hb::Vec3 direction; } views[] = {
      {"+X", hb::Vec3::UnitX()}, {"-X", -hb::Vec3::UnitX()}, {"+Y", hb::Vec3::UnitY()},
      {"-Y", -hb::Vec3::UnitY()}, {"+Z", hb::Vec3::UnitZ()}, {"-Z", -hb::Vec3::UnitZ()}};
  for (const auto& v : views) {
    toolAction(w, QString::fromLatin1(v.text))->trigger();
    EXPECT_GT(w.probeView()->viewDirection().dot(v.direction), 0.9999f) << v.text;
    hb::Vec3 p;  // the model is framed: the centre of the view is on it
    const QSize size = w.probeView()->viewPixels();
    EXPECT_TRUE(w.probeView()->pickSurface(size.width() / 2, size.height() / 2, p)) << v.text;
  }
}

TEST(DesktopBasicsTest, ScreenshotAtTwiceTheViewWithATransparentBackground) {
  hbtest::MeshDir data;
  MainWindow w;
  w.show();
  w.setBakeOnOpen(false);
  ASSERT_TRUE(w.openFile(data.mesh));
  pump(0.5);
  const QSize view = w.probeView()->viewPixels();
  ScreenshotDialog dialog(view);
  dialog.setMagnification(2);
  EXPECT_EQ(dialog.imagePixels(), view * 2);
  EXPECT_TRUE(dialog.sizeLabel()->text().contains(QString::number(view.width() * 2)));

  const QString big = data.dir.filePath(QStringLiteral("big.png"));
  ASSERT_TRUE(w.exportScreenshot(big, 2, true));
  if (const char* keep = std::getenv("HB_SCREENSHOT_DIR")) QFile::copy(big, QString::fromLocal8Bit(keep) + "/transparent_2x.png");
  QImage img(big);
  ASSERT_FALSE(img.isNull());
  EXPECT_EQ(img.size(), view * 2);
  ASSERT_TRUE(img.hasAlphaChannel());
  EXPECT_EQ(qAlpha(img.pixel(3, 3)), 0) << "the background corner is not transparent";
  EXPECT_EQ(qAlpha(img.pixel(img.width() / 2, img.height() / 2)), 255) << "the model is not opaque";
  // The window's own background is back afterwards: an ordinary screenshot is opaque.
  const QString plain = data.dir.filePath(QStringLiteral("plain.png"));
  ASSERT_TRUE(w.exportScreenshot(plain));
  QImage p(plain);
  EXPECT_EQ(p.size(), view);
  EXPECT_EQ(qAlpha(p.pixel(3, 3)), 255);
  EXPECT_FALSE(w.exportScreenshot(data.dir.filePath(QStringLiteral("x.png")), 9));  // out of range: refused
}

TEST(DesktopBasicsTest, SessionsSaveAndRestoreTheProbe) {
  hbtest::MeshDir data;
  const QString path = data.dir.filePath(QStringLiteral("probe.hbsession"));
  hb::Vec3 point;
  {
    MainWindow w;
    w.show();
    openAndBake(w, data.mesh);
    ASSERT_TRUE(placeProbe(w));
    point = *w.session()->surfacePoint();
    ASSERT_TRUE(w.saveSession(path));
  }
  EXPECT_TRUE(loadSessionFile(path).hasProbe);
  MainWindow w;
  w.show();
  ASSERT_TRUE(w.openFile(path));
  ASSERT_TRUE(w.session()->surfacePoint().has_value());
  EXPECT_LT((*w.session()->surfacePoint() - point).norm(), 1e-4f);
  ASSERT_TRUE(waitFor([&] { return w.session()->reading().placed && w.session()->reading().exact.contact; }, 10));
}

TEST(DesktopBasicsTest, AgreeingArrowsBothShowAndHeadOnArrowsAreCaptioned) {
  hbtest::MeshDir data;
  MainWindow w;
  w.show();
  openAndBake(w, data.mesh);
  ASSERT_TRUE(placeProbe(w));  // aimed along the view: the force points back at the camera
  w.session()->setDepthFraction(0.03);
  ASSERT_TRUE(waitFor([&] { return w.session()->reading().approx.contact; }, 10));
  pump(0.5);
  w.refresh();
  const QString png = data.dir.filePath(QStringLiteral("headon.png"));
  ASSERT_TRUE(w.exportScreenshot(png));
  if (const char* keep = std::getenv("HB_SCREENSHOT_DIR")) {  // for a person to look at
    QFile::copy(png, QString::fromLocal8Bit(keep) + "/arrows_head_on.png");
    w.grab().save(QString::fromLocal8Bit(keep) + "/arrows_head_on_window.png");
  }
  EXPECT_EQ(w.probeView()->exactArrowCaption(), QStringLiteral("exact: toward you"));
  EXPECT_EQ(w.probeView()->approxArrowCaption(), QStringLiteral("box: toward you"));
  // Both colours on screen although the two arrows coincide.
  QImage img = QImage(png).convertToFormat(QImage::Format_RGB32);
  // In the series colours of the charts and the report: exact red, box blue.
  int red = 0, blue = 0;
  for (int y = 0; y < img.height(); ++y)
    for (int x = 0; x < img.width(); ++x) {
      const QColor q(img.pixel(x, y));
      if (q.red() > 120 && q.green() < 0.45 * q.red() && q.blue() < 0.45 * q.red()) ++red;
      if (q.blue() > 100 && q.blue() > q.red() + 60 && q.blue() > q.green() + 30) ++blue;
    }
  EXPECT_GT(red, 20);
  EXPECT_GT(blue, 20);
  // One definition of the series colours: the arrows are drawn in exactly the charts' colours.
  const std::array<double, 3> exact = w.probeView()->arrowColor(true), box = w.probeView()->arrowColor(false);
  EXPECT_NEAR(exact[0], hb::kExactSeries.rf(), 1e-9);
  EXPECT_NEAR(exact[1], hb::kExactSeries.gf(), 1e-9);
  EXPECT_NEAR(exact[2], hb::kExactSeries.bf(), 1e-9);
  EXPECT_NEAR(box[0], hb::kBoxSeries.rf(), 1e-9);
  EXPECT_NEAR(box[1], hb::kBoxSeries.gf(), 1e-9);
  EXPECT_NEAR(box[2], hb::kBoxSeries.bf(), 1e-9);
  // From the side the arrows read by their shape: no captions.
  w.probeView()->orbitCamera(80.0, 0.0);
  w.probeView()->renderWindow()->Render();
  EXPECT_TRUE(w.probeView()->exactArrowCaption().isEmpty());
  EXPECT_TRUE(w.probeView()->approxArrowCaption().isEmpty());
}

TEST(DesktopBasicsTest, JobStatusIsCurrentCompleteAndCancelAnswersQuickly) {
  hbtest::MeshDir data;
  MainWindow w;
  w.show();
  w.setBakeOnOpen(false);
  ASSERT_TRUE(w.openFile(data.mesh));
  // Automatic pieces: the decomposition's share of the bar moves (it used to sit at 0 %).
  BakeSettings b = w.session()->bakeSettings();
  b.advanced = true;
  b.pieces = BakeSettings::Pieces::Automatic;
  b.m = 32;
  b.n = 16;
  b.useCache = false;
  w.session()->setBakeSettings(b);
  w.bakePanel()->showSettings();
  double seenInDecomposition = 0.0;
  QObject::connect(w.session()->job(), &BackgroundJob::progressChanged, &w, [&](double f) {
    if (f < 1.0 / 3.0) seenInDecomposition = std::max(seenInDecomposition, f);
  });
  w.bakePanel()->bakeButton()->click();
  ASSERT_TRUE(w.session()->job()->isRunning());
  EXPECT_TRUE(w.statusBar()->currentMessage().contains(QStringLiteral("Bake of bumpy.off running")))
      << w.statusBar()->currentMessage().toStdString();
  ASSERT_TRUE(waitFor([&] { return seenInDecomposition > 0.05 || !w.session()->job()->isRunning(); }, 60));
  EXPECT_GT(seenInDecomposition, 0.05);
  ASSERT_TRUE(w.session()->job()->isRunning());
  const auto t0 = std::chrono::steady_clock::now();
  for (QPushButton* p : w.statusBar()->findChildren<QPushButton*>())
    if (p->text() == QStringLiteral("Cancel")) p->click();
  EXPECT_TRUE(w.statusBar()->currentMessage().startsWith(QStringLiteral("Cancelling Bake of bumpy.off")));
  ASSERT_TRUE(waitFor([&] { return !w.session()->job()->isRunning(); }, 60));
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  EXPECT_LT(seconds, 3.0) << "cancel took " << seconds << " s";
  EXPECT_EQ(w.statusBar()->currentMessage(), QStringLiteral("Bake of bumpy.off cancelled"));
  // The next bake's status replaces it.
  hbtest::setSmallBake(*w.session());
  b = w.session()->bakeSettings();
  b.pieces = BakeSettings::Pieces::None;
  w.session()->setBakeSettings(b);
  w.bakePanel()->showSettings();
  w.bakePanel()->bakeButton()->click();
  EXPECT_FALSE(w.statusBar()->currentMessage().contains(QStringLiteral("cancelled")));
  ASSERT_TRUE(waitFor([&] { return !w.session()->job()->isRunning(); }, 60));
  EXPECT_EQ(w.statusBar()->currentMessage(), QStringLiteral("Bake of bumpy.off done"));
  // A piece-file bake without a file says what is missing (it used to read ": cannot open piece file").
  b = w.session()->bakeSettings();
  b.pieces = BakeSettings::Pieces::File;
  b.piecesFile.clear();
  w.session()->setBakeSettings(b);
  w.bakePanel()->showSettings();
  w.bakePanel()->bakeButton()->click();
  EXPECT_FALSE(w.session()->job()->isRunning());
  EXPECT_TRUE(w.statusBar()->currentMessage().contains(QStringLiteral("no piece file is chosen")))
      << w.statusBar()->currentMessage().toStdString();
}

TEST(DesktopBasicsTest, DocksKeepTheirWidthWhenTextsGrow) {
  hbtest::MeshDir data;
  MainWindow w;
  w.show();
  openAndBake(w, data.mesh);
  pump(0.3);
  auto* dock = w.findChild<QDockWidget*>(QStringLiteral("BakeDock"));
  const int width = dock->width(), viewWidth = w.probeView()->width();
  // The largest tables the panel allows and refinement: the longest size text.
  w.bakePanel()->findChildren<QSpinBox*>().at(0)->setValue(256);
  w.bakePanel()->findChildren<QSpinBox*>().at(1)->setValue(64);
  for (QCheckBox* c : w.bakePanel()->findChildren<QCheckBox*>())
    if (c->text().startsWith(QStringLiteral("Refine"))) c->setChecked(true);
  ASSERT_TRUE(placeProbe(w));
  for (int i = 0; i < 30; ++i) {
    pump(0.02);
    w.refresh();
  }
  pump(0.3);
  if (const char* keep = std::getenv("HB_SCREENSHOT_DIR")) w.grab().save(QString::fromLocal8Bit(keep) + "/long_texts_window.png");
  EXPECT_EQ(dock->width(), width);
  EXPECT_EQ(w.probeView()->width(), viewWidth);
}

TEST(DesktopBasicsTest, StabilityTabRunsTheSuiteWithTheProxyLawWhenChosen) {
  hbtest::MeshDir data;
  MainWindow w;
  w.show();
  openAndBake(w, data.mesh);
  StabilityPanel* panel = w.stabilityPanel();
  ASSERT_EQ(panel->lawBox()->currentData().toInt(), int(hb::ContactLaw::penalty));  // the default
  panel->lawBox()->setCurrentIndex(panel->lawBox()->findData(int(hb::ContactLaw::proxy)));
  panel->sitesBox()->setValue(1);
  panel->generatedBox()->setChecked(false);
  panel->runButton()->click();
  ASSERT_TRUE(w.session()->job()->isRunning());
  ASSERT_TRUE(waitFor([&] { return !w.session()->job()->isRunning(); }, 300));
  const hb::StabilityReport* r = w.session()->stabilityReport();
  ASSERT_NE(r, nullptr);
  EXPECT_EQ(r->contact_law, "proxy");
  EXPECT_TRUE(r->calibration_pass);
  EXPECT_GT(r->metrics.size(), 8u);
  EXPECT_TRUE(panel->summaryLabel()->text().contains(QStringLiteral("proxy law"))) << panel->summaryLabel()->text().toStdString();
}

TEST(DesktopBasicsTest, DevicePanelsContactLawRestartsTheServoWithTheProxyWhichPushesBack) {
  hbtest::MeshDir data;
  MainWindow w;
  w.show();
  openAndBake(w, data.mesh);
  ASSERT_TRUE(w.session()->servoRunning());
  EXPECT_EQ(w.session()->device()->servoContactLaw(), hb::ContactLaw::penalty);
  QComboBox* law = w.devicePanel()->lawBox();
  law->setCurrentIndex(law->findData(int(hb::ContactLaw::proxy)));
  EXPECT_EQ(w.session()->contactLaw(), hb::ContactLaw::proxy);
  ASSERT_TRUE(w.session()->servoRunning());
  EXPECT_EQ(w.session()->device()->servoContactLaw(), hb::ContactLaw::proxy);
  // The proxy's force reaches the readout: the tip pushed past the surface is pushed back.
  ASSERT_TRUE(placeProbe(w));
  ASSERT_TRUE(waitFor([&] {
    const ProbeReading r = w.session()->reading();
    return r.approx.contact && r.approx.force.norm() > 0.f;
  }, 10.0));
  law->setCurrentIndex(law->findData(int(hb::ContactLaw::penalty)));
  EXPECT_EQ(w.session()->device()->servoContactLaw(), hb::ContactLaw::penalty);
}

TEST(DesktopBasicsTest, StabilityTabRunsTheSuiteOnTheOpenModelAndShowsItsTable) {
  hbtest::MeshDir data;
  MainWindow w;
  w.show();
  StabilityPanel* panel = w.stabilityPanel();
  auto* dock = w.findChild<QDockWidget*>(QStringLiteral("StabilityDock"));
  EXPECT_FALSE(dock->isVisible());
  for (QAction* a : w.findChildren<QAction*>())
    if (a->text() == QStringLiteral("S&tability Suite...")) a->trigger();
  EXPECT_TRUE(dock->isVisible());
  EXPECT_FALSE(panel->runButton()->isEnabled());  // no boxes yet
  openAndBake(w, data.mesh);
  EXPECT_TRUE(panel->runButton()->isEnabled());
  panel->sitesBox()->setValue(1);
  panel->generatedBox()->setChecked(false);  // the model alone: quick
  panel->runButton()->click();
  ASSERT_TRUE(w.session()->job()->isRunning());
  EXPECT_FALSE(panel->runButton()->isEnabled());
  ASSERT_TRUE(waitFor([&] { return !w.session()->job()->isRunning(); }, 300));
  const hb::StabilityReport* r = w.session()->stabilityReport();
  ASSERT_NE(r, nullptr);
  EXPECT_TRUE(r->calibration_pass);
  ASSERT_GT(r->metrics.size(), 8u);
  QTableWidget* t = panel->table();
  ASSERT_EQ(t->rowCount(), static_cast<int>(r->calibration.size() + r->metrics.size()));
  EXPECT_EQ(t->horizontalHeaderItem(6)->text(), QStringLiteral("Verdict"));
  std::set<QString> tests;
  for (int i = 0; i < t->rowCount(); ++i) {
    tests.insert(t->item(i, 0)->text());
    const QString verdict = t->item(i, 6)->text();
    EXPECT_TRUE(verdict == "pass" || verdict.startsWith("fail") || verdict == "info") << verdict.toStdString();
  }
  for (const char* test : {"calibration", "T1", "T2", "T5", "T8"}) EXPECT_EQ(tests.count(QString::fromLatin1(test)), 1u) << test;
  EXPECT_EQ(t->item(static_cast<int>(r->calibration.size()), 1)->text(), QStringLiteral("bumpy.off"));
  EXPECT_TRUE(panel->summaryLabel()->text().contains(QStringLiteral("calibration pass"))) << panel->summaryLabel()->text().toStdString();
  EXPECT_TRUE(panel->runButton()->isEnabled());
  if (const char* keep = std::getenv("HB_SCREENSHOT_DIR")) {
    pump(0.3);
    w.grab().save(QString::fromLocal8Bit(keep) + "/stability_tab_window.png");
  }
}
