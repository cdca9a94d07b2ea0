// The probe distributions shared by eval, bench, sweep and reports.
#include "errors.h"
#include "evaluation/probe_sampling.h"
#include "mesh/generators.h"
#include <gtest/gtest.h>
#include <algorithm>
#include <cmath>

namespace hb {
namespace {

TEST(ProbeSamplingTest, SameSeedSameProbesAndTipsNearTheSurface) {
  const TriangleMesh sphere = make_sphere(1.f, 4);
  const auto a = sample_probes(sphere, 500), b = sample_probes(sphere, 500);
  ASSERT_EQ(a.size(), 500u);
  const float diagonal = sphere.bounds().diagonal();
  for (std::size_t i = 0; i < a.size(); ++i) {
    EXPECT_EQ(a[i].start, b[i].start);
    EXPECT_EQ(a[i].end, b[i].end);
    EXPECT_NEAR((a[i].end - a[i].start).norm(), 0.10f * diagonal, 1e-4f);
    // The tip lies at most 3% of the diagonal inside the (nearly unit) sphere.
    EXPECT_LE(a[i].end.norm(), 1.0005f);
    EXPECT_GE(a[i].end.norm(), 1.f - 0.031f * diagonal);
  }
}

TEST(ProbeSamplingTest, CoherentOrderIsAPermutation) {
  auto probes = sample_probes(make_sphere(1.f, 3), 300);
  auto sorted = probes;
  sort_probes_coherently(sorted);
  const auto key = [](const Segment& s) { return std::make_tuple(s.end.x(), s.end.y(), s.end.z(), s.start.x()); };
  std::vector<std::tuple<float, float, float, float>> x, y;
  for (const Segment& s : probes) x.push_back(key(s));
  for (const Segment& s : sorted) y.push_back(key(s));
  std::sort(x.begin(), x.end());
  std::sort(y.begin(), y.end());
  EXPECT_EQ(x, y);
}

TEST(ProbeSamplingTest, StrokesCircleEachAnchorInSmallSteps) {
  const TriangleMesh sphere = make_sphere(1.f, 4);
  const float diagonal = sphere.bounds().diagonal();
  const std::size_t steps = 200;
  const auto strokes = sample_strokes(sphere, 3, steps, 0.02f);
  ASSERT_EQ(strokes.size(), 3 * steps);
  const float step_length = float(2.0 * M_PI) * 0.02f * diagonal / float(steps);
  for (std::size_t i = 1; i < strokes.size(); ++i) {
    if (i % steps == 0) continue;  // a new stroke
    const Vec3 l0 = (strokes[i - 1].end - strokes[i - 1].start).normalized();
    const Vec3 l1 = (strokes[i].end - strokes[i].start).normalized();
    EXPECT_GT(l0.dot(l1), 0.99999f);  // same direction along a stroke
    EXPECT_NEAR((strokes[i].end - strokes[i - 1].end).norm(), step_length, 0.01f * step_length);
  }
  EXPECT_THROW(sample_strokes(sphere, 1, 0, 0.02f), InvalidInput);
}

} // namespace
} // namespace hb
