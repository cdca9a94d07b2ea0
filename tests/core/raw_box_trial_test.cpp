// The budgeted bake's raw-box trial (recipe/raw_box_trial.h): the screen, its forecast along
// the slides, and the codec bound derived from the force threshold.
#include "perception/perceptible.h"
#include "contact/workspace.h"
#include "evaluation/probe_sampling.h"
#include "exact/exact_query.h"
#include "mesh/generators.h"
#include "recipe/raw_box_trial.h"
#include <gtest/gtest.h>
#include <vector>

namespace hb {
namespace {

// A bumpy sphere subdivided `subdivisions` times, its exact reference, `count` probes of
// `seed` on it and exact's answers at the workspace's law (built in place: exact holds the mesh).
struct BumpyProbes {
  BumpyProbes(int subdivisions, std::size_t count, std::uint64_t seed)
      : mesh(make_bumpy_sphere(options(subdivisions))), exact(mesh), law(make_workspace(mesh.bounds().diagonal()).law()) {
    ProbeOptions po;
    po.seed = seed;
    probes = sample_probes(mesh, count, po);
    for (const Segment& s : probes) answers.push_back(exact.query(s, law));
  }
  static BumpySphereOptions options(int subdivisions) {
    BumpySphereOptions bo;
    bo.subdivisions = subdivisions;
    return bo;
  }
  const TriangleMesh mesh;
  const ExactQuery exact;
  const ForceLaw law;
  std::vector<Segment> probes;
  std::vector<Contact> answers;
};

TEST(RawBoxTrialTest, AScreenFeltOnSlidesBeyondWhatTheFinestCouldFixForecastsNoSamplingServes) {
  const RawSampling screen{16, 8}, finest{32, 16};
  const double allowed = 0.0008;
  // 3% at m16 n8: even a 32-fold fall leaves 0.094%.
  EXPECT_TRUE(slides_hopeless(0.03, screen, finest, allowed));
  // The bumpy sphere's m16 n8 since grazing lines settle on a fitted quadric (1.57%, block-coded)
  // could fall below 0.08% at twice the sampling (measured: 0.039%): the finest is tried.
  EXPECT_FALSE(slides_hopeless(0.0157, screen, finest, allowed));
  // Not judged (no contact along the slides): no forecast.
  EXPECT_FALSE(slides_hopeless(-1.0, screen, finest, allowed));
  // The refinement is the larger of the two ratios: m16 n8 to m24 n24 is threefold (243x).
  EXPECT_TRUE(slides_hopeless(0.2, screen, {24, 24}, allowed));
  EXPECT_FALSE(slides_hopeless(0.18, screen, {24, 24}, allowed));
}

TEST(RawBoxTrialTest, CodecBoundMakesAnEighthOfTheForceThresholdAtTheWorkspaceStiffness) {
  const double diagonal = 2.0;  // model units
  const ForceLaw law = make_workspace(diagonal).law();
  const PerceptualThresholds t;
  const float bound = raw_codec_bound(law, t, diagonal);  // a fraction of the diagonal
  const double force = double(bound) * diagonal * double(law.metres_per_unit) * double(law.stiffness_n_per_m);
  EXPECT_NEAR(force, 0.125 * t.floor_n, 1e-6);
}

TEST(RawBoxTrialTest, TheScreenOfABumpySphereJudgesItsSlidesAndStopsWhenTheyCannotServe) {
  const BumpyProbes b(5, 4000, 7);  // 20,480 triangles
  RawTrialOptions o;
  o.samplings = {{16, 8}, {32, 16}};
  o.codec_bound = raw_codec_bound(b.law, o.thresholds, double(b.mesh.bounds().diagonal()));
  const RawTrial trial = try_raw_boxes(b.mesh, b.exact, b.probes, b.answers, b.law, BakeOptions{}, SourceInfo{}, o);
  ASSERT_FALSE(trial.tried.empty());
  const RawCandidate& first = trial.tried.front();
  EXPECT_EQ(first.m, 16);
  EXPECT_GT(first.probes_felt, o.allowed_share);  // a coarse box is felt on some probes
  ASSERT_GE(first.ticks_felt, 0.0);               // and its slides were judged all the same
  const bool hopeless = slides_hopeless(first.ticks_felt, o.samplings[0], o.samplings[1], o.allowed_share);
  EXPECT_EQ(trial.tried.size(), hopeless ? 1u : 2u);
  if (hopeless) {
    EXPECT_EQ(first.outcome, "felt on slides");
    EXPECT_FALSE(trial.scene.has_value());
  }
}

// Every sampling the trial tries is timed against exact, one that failed too (the speed chart
// places each, hb::bake_chart_points): a coarse box felt on most probes, which stops the trial
// at the screen, still has its query time and exact's beside it.
TEST(RawBoxTrialTest, EverySamplingTriedIsTimedAgainstExactWhateverItsOutcome) {
  const BumpyProbes b(3, 2000, 11);  // 1,280 triangles
  RawTrialOptions o;
  o.samplings = {{4, 2}, {8, 4}};
  o.slides = false;
  const RawTrial trial = try_raw_boxes(b.mesh, b.exact, b.probes, b.answers, b.law, BakeOptions{}, SourceInfo{}, o);
  ASSERT_FALSE(trial.tried.empty());
  EXPECT_EQ(trial.tried.front().outcome, "felt on probes");  // m4 n2: far too coarse to serve
  for (const RawCandidate& c : trial.tried) {
    EXPECT_GT(c.box_ns, 0.0) << c.describe();
    EXPECT_GT(c.exact_ns, 0.0) << c.describe();
    EXPECT_NE(c.describe().find(" ns against exact's "), std::string::npos) << c.describe();
  }
}

// A sampling that passes the tuning probes (near the normal) and the memory cap is judged on
// light touches at any angle too (eval's second figure), before its slides: a sampling felt
// there is not kept.
TEST(RawBoxTrialTest, ASamplingThatPassesTheProbesIsJudgedOnLightTouchesAtAnyAngle) {
  const BumpyProbes b(5, 4000, 7);  // 20,480 triangles
  RawTrialOptions o;
  o.samplings = {{32, 16}};
  o.slides = false;
  o.light_touches = 4000;
  o.codec_bound = raw_codec_bound(b.law, o.thresholds, double(b.mesh.bounds().diagonal()));
  const RawTrial trial = try_raw_boxes(b.mesh, b.exact, b.probes, b.answers, b.law, BakeOptions{}, SourceInfo{}, o);
  ASSERT_EQ(trial.tried.size(), 1u);
  const RawCandidate& c = trial.tried.front();
  ASSERT_LE(c.probes_felt, o.allowed_share) << c.describe();
  ASSERT_GE(c.light_felt, 0.0) << c.describe();
  EXPECT_NE(c.describe().find("% of light touches"), std::string::npos) << c.describe();
  EXPECT_EQ(c.outcome == "felt on light touches", c.light_felt > o.allowed_share) << c.describe();
}

} // namespace
} // namespace hb
