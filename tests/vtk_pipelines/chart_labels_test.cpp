// Where the speed-against-accuracy chart puts its point labels (hb::LabelPlacer): beside their
// points, apart, inside the axes.
#include "report_charts.h"
#include <gtest/gtest.h>
#include <cmath>
#include <random>

namespace {

bool overlap(const hb::LabelPlacer::Rect& a, const hb::LabelPlacer::Rect& b) {
  return a.x0 < b.x1 && b.x0 < a.x1 && a.y0 < b.y1 && b.y0 < a.y1;
}

} // namespace

TEST(ChartLabelsTest, ACrowdOfPointsGetsLabelsNearTheirPointsThatNeitherOverlapNorLeaveTheAxes) {
  // A sweep's usual crowd: many fast configurations within a few percent of each other.
  const double x0 = 2.0, x1 = 4.0, y0 = 0.0, y1 = 100.0, line = 0.05 * (y1 - y0);
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> xs(2.05, 2.4), ys(20.0, 90.0);
  std::vector<std::pair<double, double>> points;
  for (int i = 0; i < 30; ++i) points.emplace_back(xs(rng), ys(rng));
  hb::LabelPlacer placer(x0, x1, y0, y1);
  for (const auto& [x, y] : points) placer.mark(x, y, false);
  std::vector<hb::LabelPlacer::Rect> shown;
  int left_out = 0;
  for (const auto& [x, y] : points) {
    const hb::LabelPlacer::Placement p = placer.place(x, y, 7, false, false);  // "m16 n8 "
    if (!p.shown) {
      ++left_out;
      continue;
    }
    EXPECT_LE(std::fabs(p.y - y), 1.6 * line + 1e-9) << "a label drifted from its point";
    EXPECT_LE(std::fabs((p.left ? p.box.x1 : p.box.x0) - x), 0.04 * (x1 - x0));
    EXPECT_GE(p.box.x0, x0);
    EXPECT_LE(p.box.x1, x1);
    EXPECT_GE(p.box.y0, y0);
    EXPECT_LE(p.box.y1, y1);
    for (const auto& r : shown) EXPECT_FALSE(overlap(p.box, r));
    for (const auto& [px, py] : points) {
      const hb::LabelPlacer::Rect mark{px - 0.008 * (x1 - x0), px + 0.008 * (x1 - x0), py - 0.25 * line, py + 0.25 * line};
      EXPECT_FALSE(overlap(p.box, mark)) << "a label covers a point";
    }
    shown.push_back(p.box);
  }
  EXPECT_GT(shown.size(), 10u) << "most of a crowd is labelled";
  EXPECT_GT(left_out, 0) << "this crowd cannot all be labelled";
}

TEST(ChartLabelsTest, LabelsThatMustBeDrawnStackAboveACrowdedBottomRow) {
  // The default bake, a raw sampling and exact, all at 0% felt and close in time (the bottom of
  // the top panel, no room below): each named label is drawn clear of the others and of the
  // marks, stacked up to three lines above its point.
  const double x0 = 2.0, x1 = 4.0, y0 = -0.05, y1 = 1.15, line = 0.05 * (y1 - y0);
  const double xs[] = {2.34, 2.61, 2.78, 2.45};
  hb::LabelPlacer placer(x0, x1, y0, y1);
  for (double x : xs) placer.mark(x, 0.0, x == 2.78);
  std::vector<hb::LabelPlacer::Rect> shown;
  for (double x : xs) {
    const hb::LabelPlacer::Placement p = placer.place(x, 0.0, 30, true, x == 2.78);  // "raw m32 n16 (tried by the bake)"
    ASSERT_TRUE(p.shown);
    EXPECT_LE(std::fabs(p.y), 3.2 * line + 1e-9);
    for (const auto& r : shown) EXPECT_FALSE(overlap(p.box, r)) << "labels of " << x << " overlap";
    shown.push_back(p.box);
  }
}

TEST(ChartLabelsTest, AReferenceIsAlwaysLabelledAndClearOfItsOwnMark) {
  hb::LabelPlacer placer(2.0, 4.0, 0.0, 100.0);
  placer.mark(2.5, 0.0, true);
  placer.mark(2.52, 0.0, false);  // the default bake beside exact
  const auto exact = placer.place(2.5, 0.0, 12, true, true);
  ASSERT_TRUE(exact.shown);
  EXPECT_FALSE(exact.box.x0 < 2.5 + 0.03 * 2.0 && exact.box.x1 > 2.5 - 0.03 * 2.0 && exact.box.y0 < 2.5 && exact.box.y1 > -2.5)
      << "the label covers the reference's own mark";
  // A label with no room at all is still drawn when it must be, inside the axes across.
  hb::LabelPlacer full(2.0, 4.0, 0.0, 100.0);
  full.reserve(2.0, 4.0, 0.0, 100.0);
  const auto forced = full.place(3.0, 50.0, 10, true, false);
  EXPECT_TRUE(forced.shown);
  EXPECT_GE(forced.box.x0, 2.0);
  EXPECT_LE(forced.box.x1, 4.0);
  EXPECT_FALSE(full.place(3.0, 50.0, 10, false, false).shown);
}
