// One workspace scale and the perceptual judgement (contact/workspace.h, perception/perceptible.h),
// and the perceptible figures compare_queries reports with them.
#include "perception/perceptible.h"
#include "contact/workspace.h"
#include "errors.h"
#include "evaluation/comparison.h"
#include "evaluation/probe_sampling.h"
#include "exact/exact_query.h"
#include "mesh/generators.h"
#include <gtest/gtest.h>
#include <cmath>
#include <string>

namespace {

hb::Contact contact_with_force(const hb::Vec3& force) {
  hb::Contact c;
  c.contact = true;
  c.force = force;
  c.normal = force.normalized();
  c.depth = 1.f;
  return c;
}

} // namespace

TEST(WorkspaceTest, TheModelIsFittedToTheDevicesEightyMillimetresWhateverItsUnits) {
  const hb::Workspace small = hb::make_workspace(1.33);    // the chess piece, 1.33 mm
  const hb::Workspace large = hb::make_workspace(229.0);   // the armadillo, 229 mm
  EXPECT_NEAR(small.diagonal_m(), 0.08, 1e-9);
  EXPECT_NEAR(large.diagonal_m(), 0.08, 1e-9);
  EXPECT_DOUBLE_EQ(small.stiffness_n_per_m, 1500.0);
  // The same relative penetration gives the same newtons on both models.
  const hb::ForceLaw a = small.law(), b = large.law();
  EXPECT_NEAR(a.stiffness_n_per_m * a.metres_per_unit * 0.01 * 1.33, b.stiffness_n_per_m * b.metres_per_unit * 0.01 * 229.0,
              1e-6);
  EXPECT_NE(small.describe().find("80 mm"), std::string::npos) << small.describe();
}

TEST(WorkspaceTest, RealSizeAndAnExplicitScaleKeepTheirUnitsAndBadValuesAreNamed) {
  hb::WorkspaceOptions o;
  o.fit = hb::WorkspaceFit::real_size;
  EXPECT_DOUBLE_EQ(hb::make_workspace(229.0, o).metres_per_unit, 0.001);
  EXPECT_NEAR(hb::make_workspace(229.0, o).diagonal_m(), 0.229, 1e-12);
  o.fit = hb::WorkspaceFit::scale;
  o.metres_per_unit = 2e-4;
  EXPECT_DOUBLE_EQ(hb::make_workspace(229.0, o).metres_per_unit, 2e-4);
  o.stiffness_n_per_m = -1;
  try {
    hb::make_workspace(229.0, o);
    FAIL() << "a negative stiffness was accepted";
  } catch (const hb::InvalidInput& e) {
    EXPECT_NE(std::string(e.what()).find("stiffness"), std::string::npos) << e.what();
  }
  EXPECT_THROW(hb::make_workspace(0.0), hb::InvalidInput);  // nothing to fit
  EXPECT_THROW(hb::make_workspace(std::nan("")), hb::InvalidInput);
}

TEST(WorkspaceTest, TheFrontEndsSpecSetsTheFitTheSpringAndTheLimit) {
  hb::WorkspaceOptions o;
  hb::parse_workspace_spec("mm=120,stiffness=3000,max-force=5", o);
  EXPECT_EQ(o.fit, hb::WorkspaceFit::device);
  EXPECT_DOUBLE_EQ(o.diagonal_m, 0.12);
  EXPECT_DOUBLE_EQ(o.stiffness_n_per_m, 3000.0);
  EXPECT_DOUBLE_EQ(o.max_force_n, 5.0);
  hb::WorkspaceOptions r;
  hb::parse_workspace_spec("real-size", r);
  EXPECT_EQ(r.fit, hb::WorkspaceFit::real_size);
  hb::WorkspaceOptions s;
  hb::parse_workspace_spec("metres-per-unit=0.002", s);
  EXPECT_EQ(s.fit, hb::WorkspaceFit::scale);
  EXPECT_DOUBLE_EQ(hb::make_workspace(229.0, s).metres_per_unit, 0.002);
  hb::WorkspaceOptions d;
  hb::parse_workspace_spec("", d);
  EXPECT_EQ(d.fit, hb::WorkspaceFit::device);
  EXPECT_DOUBLE_EQ(d.diagonal_m, hb::WorkspaceOptions::kDefaultDiagonalM);
  const auto refusal = [](const std::string& spec) {
    hb::WorkspaceOptions w;
    try {
      hb::parse_workspace_spec(spec, w);
    } catch (const hb::InvalidInput& e) {
      return std::string(e.what());
    }
    return std::string();
  };
  EXPECT_NE(refusal("stiffness=-5").find("--workspace stiffness"), std::string::npos);
  EXPECT_NE(refusal("mm=80,real-size").find("exclude each other"), std::string::npos);
  EXPECT_NE(refusal("depth=3").find("unknown key 'depth'"), std::string::npos);
  EXPECT_NE(refusal("mm=nan").find("--workspace mm"), std::string::npos);
}

TEST(PerceptionTest, MagnitudeDifferencesCountOnlyBeyondTheJndOrTheAbsoluteThreshold) {
  const hb::PerceptualThresholds t;
  // 0.01 N on 0.05 N is "20 %" but below the 0.04 N threshold: not felt.
  EXPECT_FALSE(hb::perceive(contact_with_force({0, 0, 0.05f}), contact_with_force({0, 0, 0.06f}), t).perceptible());
  // 8 % of 2 N (0.16 N) is below the 10 % JND: not felt; 15 % is.
  EXPECT_FALSE(hb::perceive(contact_with_force({0, 0, 2.f}), contact_with_force({0, 0, 2.16f}), t).perceptible());
  const hb::PerceivedDifference felt = hb::perceive(contact_with_force({0, 0, 2.f}), contact_with_force({0, 0, 2.3f}), t);
  EXPECT_EQ(felt.by, hb::kPerceivedMagnitude);
  EXPECT_NEAR(felt.ratio, 1.5, 1e-5);
  // The strict preset feels the 8 %.
  EXPECT_TRUE(hb::perceive(contact_with_force({0, 0, 2.f}), contact_with_force({0, 0, 2.16f}),
                           hb::PerceptualThresholds::strict())
                  .perceptible());
  // Beyond the device's force limit both feel the same.
  EXPECT_FALSE(hb::perceive(contact_with_force({0, 0, 9.f}), contact_with_force({0, 0, 12.f}), t, 8.0).perceptible());
}

TEST(PerceptionTest, DirectionsCountBeyondTwentyFiveDegreesWhenBothForcesAreFirm) {
  const hb::PerceptualThresholds t;
  const float c30 = std::cos(30.f * 3.14159265f / 180.f), s30 = std::sin(30.f * 3.14159265f / 180.f);
  const hb::PerceivedDifference firm =
      hb::perceive(contact_with_force({0, 0, 1.f}), contact_with_force({s30, 0, c30}), t);
  EXPECT_EQ(firm.by, hb::kPerceivedDirection);
  EXPECT_NEAR(firm.angle_deg, 30.0, 1e-3);
  // The same angle on forces below F_min (0.2 N) is not judged.
  EXPECT_FALSE(hb::perceive(contact_with_force({0, 0, 0.1f}), contact_with_force({0.1f * s30, 0, 0.1f * c30}), t)
                   .perceptible());
  // 20 degrees: not felt.
  const float c20 = std::cos(20.f * 3.14159265f / 180.f), s20 = std::sin(20.f * 3.14159265f / 180.f);
  EXPECT_FALSE(hb::perceive(contact_with_force({0, 0, 1.f}), contact_with_force({s20, 0, c20}), t).perceptible());
}

TEST(PerceptionTest, AContactOnOneSideIsFeltOnlyAboveTheAbsoluteThreshold) {
  const hb::PerceptualThresholds t;
  const hb::Contact none;
  EXPECT_FALSE(hb::perceive(none, contact_with_force({0, 0, 0.0007f}), t).perceptible());
  EXPECT_EQ(hb::perceive(contact_with_force({0, 0, 3.f}), none, t).by, hb::kPerceivedContact);
  EXPECT_EQ(hb::perceived_by_name(hb::kPerceivedMagnitude | hb::kPerceivedContact), "magnitude+contact");
}

TEST(PerceptionTest, ThresholdSpecsRoundTripAndBadKeysAreNamed) {
  const hb::PerceptualThresholds t = hb::parse_thresholds("w=7,f0=0.03,theta=18");
  EXPECT_DOUBLE_EQ(t.weber, 0.07);
  EXPECT_DOUBLE_EQ(t.floor_n, 0.03);
  EXPECT_DOUBLE_EQ(t.angle_deg, 18.0);
  EXPECT_DOUBLE_EQ(t.angle_min_force_n, 0.2);
  const hb::PerceptualThresholds back = hb::parse_thresholds(hb::thresholds_spec(t));
  EXPECT_DOUBLE_EQ(back.weber, t.weber);
  EXPECT_DOUBLE_EQ(hb::parse_thresholds("strict").angle_deg, 18.0);
  try {
    hb::parse_thresholds("w=10,jnd=3");
    FAIL();
  } catch (const hb::InvalidInput& e) {
    EXPECT_NE(std::string(e.what()).find("jnd"), std::string::npos) << e.what();
  }
  EXPECT_THROW(hb::parse_thresholds("theta=nan"), hb::InvalidInput);
}

TEST(PerceptionTest, ExactAgainstItselfIsNeverFeltAndAShiftedSurfaceIsFeltWhereTheDifferenceExceedsTheThreshold) {
  const hb::TriangleMesh sphere = hb::make_sphere(10.f, 4);
  hb::TriangleMesh bigger = sphere;
  for (hb::Vec3& v : bigger.positions) v *= 1.02f;  // 0.2 mm on a 20 mm-wide sphere: 0.4 mm at 80 mm
  const hb::ExactQuery exact(sphere), shifted(bigger);
  const auto probes = hb::sample_probes(sphere, 4000, {});
  const float diag = sphere.bounds().diagonal();
  const hb::ForceLaw law = hb::make_workspace(diag).law();
  const hb::ComparisonStats same = hb::compare_queries(exact, exact, probes, law, diag);
  EXPECT_EQ(same.perceptible, 0u);
  EXPECT_EQ(same.force_difference_max_n, 0.0);
  const hb::ComparisonStats off = hb::compare_queries(shifted, exact, probes, law, diag);
  // 0.4 mm at 1500 N/m is 0.6 N: felt on most contacts, whatever the relative error says.
  EXPECT_GT(off.perceptible_share, 0.3);
  EXPECT_GT(off.force_difference_median_n, 0.3);
  EXPECT_EQ(off.perceptible, off.perceptible_magnitude + off.perceptible_contact)
      << "a 2 % larger sphere changes magnitudes and contacts, not directions";
  // Stricter thresholds never feel less.
  hb::PerceptualJudge strict;
  strict.thresholds = hb::PerceptualThresholds::strict();
  EXPECT_GE(hb::compare_queries(shifted, exact, probes, law, diag, nullptr, nullptr, nullptr, strict).perceptible,
            off.perceptible);
}
