// The window on a laptop's screen: it fits the available geometry it opens on (first open, a
// restored layout from a larger screen, the bottom docks shown), its docks scroll instead of
// clipping, no dock's tab bar lies over a panel, the readout's lines are whole, the stability
// table shows more than two rows; shortcuts answer while the 3D view has focus; the charts
// are cleared when another model opens. Run under xvfb-run (any screen size; the test script
// also runs it at 1366x768).
#include "ChartsView.h"
#include "ReadoutPanel.h"
#include "StabilityPanel.h"
#include "window_test_support.h"
#include <QDockWidget>
#include <QFileDialog>
#include <QHeaderView>
#include <QLabel>
#include <QScreen>
#include <QScrollArea>
#include <QScrollBar>
#include <QSettings>
#include <QStatusBar>
#include <QTabBar>
#include <QTableWidget>
#include <QTimer>
#include <QtTest/QTest>

using hbtest::openAndBake;
using hbtest::placeProbe;
using hbtest::pump;

namespace {

QRect available(const MainWindow& w) { return w.availableGeometry(); }

::testing::AssertionResult fits(const MainWindow& w) {
  const QRect frame = w.frameGeometry(), avail = available(w);
  if (avail.contains(frame)) return ::testing::AssertionSuccess();
  return ::testing::AssertionFailure() << "frame " << frame.x() << "," << frame.y() << " " << frame.width() << "x"
                                       << frame.height() << " outside the available " << avail.x() << "," << avail.y()
                                       << " " << avail.width() << "x" << avail.height();
}

QDockWidget* dock(const MainWindow& w, const char* name) { return w.findChild<QDockWidget*>(QString::fromLatin1(name)); }

}  // namespace

TEST(WindowLayoutTest, WindowFitsTheAvailableGeometryOfItsScreen) {
  MainWindow w;
  w.show();
  pump(0.5);
  EXPECT_TRUE(fits(w));
  // The first window takes most of the screen, not a sliver of it.
  EXPECT_GE(w.frameGeometry().width(), std::min(1280, available(w).width() * 8 / 10));
  // The bottom docks (charts, stability) once pushed the window past the screen.
  dock(w, "ChartsDock")->show();
  dock(w, "StabilityDock")->show();
  pump(0.5);
  EXPECT_TRUE(fits(w));
  EXPECT_TRUE(w.statusBar()->isVisible());
  EXPECT_TRUE(available(w).contains(w.statusBar()->mapToGlobal(QPoint(0, w.statusBar()->height() - 1))));
}

TEST(WindowLayoutTest, ALayoutSavedOnALargerScreenIsRestoredInsideThisOne) {
  {
    MainWindow big;
    big.show();
    pump(0.3);
    dock(big, "ChartsDock")->show();
    // As if saved on a 2560x1600 screen, further right and down than this one reaches.
    big.setGeometry(QRect(available(big).topLeft() + QPoint(400, 300), QSize(2400, 1500)));
    big.savePreferences();
    ASSERT_TRUE(QSettings().contains(QStringLiteral("window/geometry")));
  }
  MainWindow w;
  w.show();
  pump(0.6);
  EXPECT_TRUE(fits(w));
  EXPECT_TRUE(dock(w, "ChartsDock")->isVisible());
  if (const char* keep = std::getenv("HB_SCREENSHOT_DIR")) w.grab().save(QString::fromLocal8Bit(keep) + "/restored_window.png");
  // No tab bar of the tabified docks lies over a visible panel.
  for (QTabBar* bar : w.findChildren<QTabBar*>()) {
    if (!bar->isVisible() || bar->parentWidget() != &w) continue;
    const QRect tabs(bar->mapTo(&w, QPoint(0, 0)), bar->size());
    if (!w.rect().intersects(tabs)) continue;  // Qt parks unused tab bars off the window
    for (QDockWidget* d : w.findChildren<QDockWidget*>()) {
      if (!d->isVisible() || d->isFloating()) continue;
      const QRect panel(d->widget()->mapTo(&w, QPoint(0, 0)), d->widget()->size());
      if (!w.rect().intersects(panel)) continue;  // a dock behind another tab
      EXPECT_FALSE(tabs.intersects(panel)) << d->objectName().toStdString() << " under a tab bar: tabs " << tabs.y() << "+"
                                           << tabs.height() << ", panel " << panel.y() << "+" << panel.height();
    }
  }
}

TEST(WindowLayoutTest, DockPanelsScrollInsteadOfClipping) {
  MainWindow w;
  w.show();
  pump(0.5);
  for (const char* name : {"ReadoutDock", "BakeDock", "SurfaceDock", "ErrorFieldDock", "DeviceDock"}) {
    auto* area = qobject_cast<QScrollArea*>(dock(w, name)->widget());
    ASSERT_NE(area, nullptr) << name << " does not scroll";
    EXPECT_TRUE(area->widgetResizable());
    // As wide as its panel asks: a scroll area must not squeeze the panel to a sliver.
    EXPECT_GE(area->width(), area->widget()->minimumSizeHint().width()) << name;
  }
  // Squeezed below its panel's height, the Bake dock scrolls to reach its last control.
  w.resize(w.width(), 520);
  pump(0.5);
  auto* bake = qobject_cast<QScrollArea*>(dock(w, "BakeDock")->widget());
  if (bake->viewport()->height() < bake->widget()->minimumSizeHint().height()) {
    EXPECT_TRUE(bake->verticalScrollBar()->isVisible());
    EXPECT_GT(bake->verticalScrollBar()->maximum(), 0);
  }
  EXPECT_GE(bake->widget()->height(), bake->widget()->minimumSizeHint().height());
  if (const char* keep = std::getenv("HB_SCREENSHOT_DIR")) w.grab().save(QString::fromLocal8Bit(keep) + "/squeezed_window.png");
}

TEST(WindowLayoutTest, ReadoutLinesAreWholeAndTheStabilityTableShowsSeveralRows) {
  hbtest::MeshDir data;
  MainWindow w;
  w.show();
  openAndBake(w, data.mesh);
  ASSERT_TRUE(placeProbe(w));
  for (int i = 0; i < 20; ++i) {
    pump(0.02);
    w.refresh();
  }
  pump(0.3);
  for (QLabel* l : w.readoutPanel()->findChildren<QLabel*>()) {
    if (!l->isVisible() || !l->wordWrap()) continue;
    EXPECT_GE(l->height(), l->heightForWidth(l->width())) << "clipped: " << l->text().toStdString();
  }
  dock(w, "StabilityDock")->show();
  dock(w, "StabilityDock")->raise();
  pump(0.5);
  QTableWidget* table = w.stabilityPanel()->table();
  const int rows = (table->viewport()->height()) / table->verticalHeader()->defaultSectionSize();
  EXPECT_GE(rows, 4) << "viewport " << table->viewport()->height() << " px";
  EXPECT_TRUE(fits(w));
}

TEST(WindowLayoutTest, CtrlOOpensTheFileDialogWhileTheViewHasFocus) {
  MainWindow w;
  w.show();
  pump(0.5);
  w.activateWindow();
  w.probeView()->setFocus();
  pump(0.2);
  QString seen;
  // The dialog is modal: note its title and close it from a timer.
  QTimer::singleShot(800, [&seen] {
    if (QWidget* modal = QApplication::activeModalWidget()) {
      seen = modal->windowTitle();
      modal->close();
    }
  });
  QTest::keyClick(w.probeView(), Qt::Key_O, Qt::ControlModifier);
  pump(1.2);
  EXPECT_EQ(seen, QStringLiteral("Open model"));
}

TEST(WindowLayoutTest, OpeningAnotherModelClearsTheCharts) {
  hbtest::MeshDir data;
  MainWindow w;
  w.show();
  openAndBake(w, data.mesh);
  ASSERT_TRUE(w.session()->startSweep({8}, {4}, 500));
  ASSERT_TRUE(hbtest::waitFor([&] { return !w.session()->job()->isRunning(); }, 300));
  ASSERT_GT(w.chartsView()->pointCount(), 0u);
  EXPECT_NE(w.chartsView()->hintText(), ChartsView::emptyHint());
  // The default bake is on the chart beside the samplings (and exact: its legend entry).
  bool defaultRow = false;
  for (const hb::SweepRow& r : w.chartsView()->boxRows()) defaultRow = defaultRow || r.label.rfind("default bake", 0) == 0;
  EXPECT_TRUE(defaultRow);
  EXPECT_GE(w.chartsView()->legendEntries(), 2);
  ASSERT_TRUE(w.openFile(data.mesh));
  EXPECT_EQ(w.chartsView()->pointCount(), 0u);
  EXPECT_EQ(w.chartsView()->legendEntries(), 0);
  // The hint names menus that exist.
  EXPECT_EQ(w.chartsView()->hintText(), ChartsView::emptyHint());
  EXPECT_TRUE(ChartsView::emptyHint().contains(QStringLiteral("Tools > Run Sweep")));
  EXPECT_TRUE(ChartsView::emptyHint().contains(QStringLiteral("File > Export Error Report")));
}
