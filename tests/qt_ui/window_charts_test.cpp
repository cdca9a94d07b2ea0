// The first chart a user meets in the window: right after the default bake, with no
// sweep, the speed chart shows what a hand feels against query time for the default bake, exact
// and the raw samplings the bake tried, each labelled on the chart and explained in its tooltip;
// a box file loaded back shows the same points (the times are in the file); a sweep replaces
// them.
#include "ChartsView.h"
#include "store/box_file.h"
#include "window_test_support.h"
#include <QDockWidget>
#include <QFileInfo>
#include <algorithm>
#include <cstdlib>
#include <string>
#include <vector>

using hbtest::pump;
using hbtest::waitFor;

namespace {

bool has(const std::vector<std::string>& v, const std::string& prefix) {
  return std::any_of(v.begin(), v.end(), [&](const std::string& s) { return s.rfind(prefix, 0) == 0; });
}

// Shows the Charts dock at 2/5 of the window's height and keeps the chart and the window as
// PNGs in HB_SCREENSHOT_DIR, for a person to look at.
void keepCharts(MainWindow& w, const QString& name) {
  if (auto* d = w.findChild<QDockWidget*>(QStringLiteral("ChartsDock"))) {
    d->show();
    d->raise();
    w.resizeDocks({d}, {w.height() * 2 / 5}, Qt::Vertical);
  }
  pump(1.0);
  if (const char* keep = std::getenv("HB_SCREENSHOT_DIR")) {
    w.chartsView()->grab().save(QString::fromLocal8Bit(keep) + "/" + name + "_chart.png");
    w.grab().save(QString::fromLocal8Bit(keep) + "/" + name + "_window.png");
  }
}

}  // namespace

TEST(WindowChartsTest, RightAfterTheDefaultBakeTheSpeedChartShowsItExactAndTheRawSamplingsItTried) {
  hbtest::MeshDir data;
  MainWindow w;
  w.resize(1400, 900);
  w.show();
  w.setBakeOnOpen(false);
  ASSERT_TRUE(w.openFile(data.mesh));
  EXPECT_EQ(w.chartsView()->pointCount(), 0u);
  BakeSettings settings = w.session()->bakeSettings();
  settings.advanced = false;  // the default recipe: the budgeted bake, raw boxes tried first
  w.session()->setBakeSettings(settings);
  QString error;
  ASSERT_TRUE(w.session()->startBake(&error)) << error.toStdString();
  ASSERT_TRUE(waitFor([&] { return w.session()->hasBoxes() && !w.session()->job()->isRunning(); }, 600));
  const hb::BudgetReport& rep = w.session()->boxes()->parts().budget;
  ASSERT_TRUE(rep.present);
  ASSERT_FALSE(rep.raw_tried.empty()) << rep.summary();
  ASSERT_GT(rep.answer_ns, 0.0);

  // No sweep ran: the chart holds the bake's own points.
  ChartsView* charts = w.chartsView();
  EXPECT_TRUE(charts->showsBake());
  const std::vector<hb::SweepRow>& rows = charts->boxRows();
  ASSERT_EQ(rows.size(), 1 + rep.raw_tried.size());  // the default bake, then every raw sampling (each timed)
  EXPECT_EQ(rows[0].label.rfind("default bake: ", 0), 0u) << rows[0].label;
  EXPECT_DOUBLE_EQ(rows[0].query_ns, rep.answer_ns);
  EXPECT_DOUBLE_EQ(rows[0].perceptible_share, rep.perceptible);
  for (std::size_t i = 0; i < rep.raw_tried.size(); ++i) {
    const hb::SweepRow& raw = rows[1 + i];
    EXPECT_TRUE(raw.tried_by_the_bake) << raw.label;
    EXPECT_EQ(raw.label, "raw m" + std::to_string(rep.raw_tried[i].m) + " n" + std::to_string(rep.raw_tried[i].n) +
                             " (tried by the bake)");
    EXPECT_GT(raw.query_ns, 0.0);
    EXPECT_DOUBLE_EQ(raw.perceptible_share, rep.raw_tried[i].probes_felt);
    const std::string tip = charts->speedTooltip(1 + i);
    EXPECT_NE(tip.find("tuning probes"), std::string::npos) << tip;
    EXPECT_NE(tip.find("against exact's"), std::string::npos) << tip;
  }
  const std::string bakeTip = charts->speedTooltip(0);
  EXPECT_NE(bakeTip.find("fresh probes"), std::string::npos) << bakeTip;
  // Labelled on the chart: exact, the default bake, each raw sampling; the budget line too.
  const std::vector<std::string> labels = charts->speedPointLabels();
  EXPECT_TRUE(has(labels, "exact Embree"));
  EXPECT_TRUE(has(labels, "default bake: "));
  EXPECT_TRUE(has(labels, "raw m16 n8 (tried by the bake)"));
  EXPECT_NE(charts->budgetLineLabel().find("0.1 %"), std::string::npos) << charts->budgetLineLabel();
  EXPECT_EQ(charts->legendEntries(), 3);  // haptic box, raw box tried by the bake, exact
  for (const std::string& t : charts->speedAxisLabels()) EXPECT_NE(t.find("s"), std::string::npos) << t;  // times
  EXPECT_NE(charts->hintText(), ChartsView::emptyHint());
  keepCharts(w, "bake");

  // Loaded back from its file, the box shows the same points: the times are in the file.
  const QString box = data.dir.filePath(QStringLiteral("default.hbox"));
  ASSERT_TRUE(w.session()->saveBoxFile(box));
  const double answerNs = rows[0].query_ns;
  const std::size_t points = charts->pointCount();
  charts->setRows({}, {});
  ASSERT_TRUE(w.session()->openBoxFile(box, &error)) << error.toStdString();
  ASSERT_TRUE(waitFor([&] { return charts->pointCount() > 0; }, 60));
  EXPECT_TRUE(charts->showsBake());
  EXPECT_EQ(charts->pointCount(), points);
  EXPECT_DOUBLE_EQ(charts->boxRows()[0].query_ns, answerNs);
  // As is the window's cache entry of that bake, which opening the model again loads.
  ASSERT_TRUE(w.openFile(data.mesh));
  ASSERT_TRUE(waitFor([&] { return w.session()->hasBoxes() && !w.session()->job()->isRunning(); }, 120));
  EXPECT_TRUE(charts->showsBake());
  EXPECT_EQ(charts->pointCount(), points);
  EXPECT_DOUBLE_EQ(charts->boxRows()[0].query_ns, answerNs);

  // A file baked before bakes timed what they tried: nothing to chart, and the hint says to
  // bake again.
  const QString untimed = data.dir.filePath(QStringLiteral("untimed.hbox"));
  {
    hb::BoxScene old = *w.session()->boxes();
    old = hb::with_budget(old, old.parts().budget.without_times());
    hb::save_box_file(old, untimed.toStdString());
  }
  ASSERT_TRUE(w.session()->openBoxFile(untimed, &error)) << error.toStdString();
  ASSERT_TRUE(waitFor([&] { return charts->hintText() == ChartsView::untimedBakeHint(); }, 60)) << charts->hintText().toStdString();
  EXPECT_EQ(charts->pointCount(), 0u);
  ASSERT_TRUE(w.session()->openBoxFile(box, &error)) << error.toStdString();
  ASSERT_TRUE(waitFor([&] { return charts->showsBake(); }, 60));

  // A sweep replaces them with its rows (the default bake among them).
  ASSERT_TRUE(w.session()->startSweep({8}, {4}, 500, &error)) << error.toStdString();
  ASSERT_TRUE(waitFor([&] { return !w.session()->job()->isRunning(); }, 600));
  EXPECT_FALSE(charts->showsBake());
  EXPECT_TRUE(charts->showsSweep());
  EXPECT_EQ(charts->pointCount(), 2u);  // m8 n4 and the default bake
}
