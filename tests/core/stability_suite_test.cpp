// The stability suite's harness and gate (label `stability`).
#include "stability/stability_suite.h"
#include "errors.h"
#include "exact/exact_query.h"
#include "scene/bake.h"
#include "evaluation/probe_sampling.h"
#include "mesh/generators.h"
#include "mesh/mesh_io.h"
#include <gtest/gtest.h>
#include <cmath>
#include <fstream>
#include <string>
#include <vector>
#include <utility>

using namespace hb;

namespace {

const StabilityMetric* find(const std::vector<StabilityMetric>& ms, const std::string& test, const std::string& part) {
  for (const auto& m : ms)
    if (m.test == test && m.metric.find(part) != std::string::npos) return &m;
  return nullptr;
}

// A prescribed normal stroke 1 mm into the analytic wall z = 0 (model in metres) at 0.1 m/s.
double wall_keff_ratio(DepthLaw depth, double tilt_degrees) {
  const AnalyticWall wall(Vec3::Zero(), Vec3(0, 0, 1));
  Workspace map;
  map.metres_per_unit = 1.0;
  ForceLaw law;
  law.stiffness_n_per_m = 1000.f;
  law.metres_per_unit = 1.f;
  law.depth = depth;
  const double a = tilt_degrees * 3.14159265358979 / 180.0;
  const Vec3d dir(std::sin(a), 0, -std::cos(a));
  std::vector<Vec3d> tips;
  for (double d = -0.0005; d < 0.001; d += 1e-4) tips.push_back(Vec3d(0, 0, -d));
  for (double d = 0.001; d > -0.0005; d -= 1e-4) tips.push_back(Vec3d(0, 0, -d));
  const auto r = play_positions(wall, law, map, tips, dir, 0.02, 1e-3);
  return passivity_equivalent_stiffness(r, 1e-3) / 1000.0;
}

// T4 alone (the generated grooves) with `law`, on a small refined sphere's scene.
StabilityReport grooves_t4(ContactLaw law) {
  const TriangleMesh mesh = make_sphere(20.f, 3);
  BakeOptions bo;
  bo.params.m = 8;
  bo.params.n = 4;
  bo.refine = true;
  const BoxScene box = bake_scene(mesh, {}, bo, SourceInfo{});
  StabilityOptions o;
  o.tests = {"T4"};
  o.contact_law = law;
  return run_stability_suite(box, mesh, o);
}

} // namespace

TEST(StabilityTrajectoryTest, CalibrationGateReproducesTheReferenceSimulation) {
  const auto gate = run_calibration(falcon_profile());
  ASSERT_EQ(gate.size(), 5u);
  for (const auto& m : gate) EXPECT_TRUE(m.pass) << m.metric << ": " << m.box;
  EXPECT_NEAR(gate[0].box, 1.148, 0.01);  // b = 0
  EXPECT_NEAR(gate[1].box, 0.990, 0.01);  // b = 1.5 N s/m
}

TEST(StabilityTrajectoryTest, DepthAlongTheSegmentStiffensATiltedWallAndTheNormalLawDoesNot) {
  EXPECT_NEAR(wall_keff_ratio(DepthLaw::along_segment, 60), 2.0 * wall_keff_ratio(DepthLaw::normal, 0), 0.03);
  EXPECT_NEAR(wall_keff_ratio(DepthLaw::normal, 60), wall_keff_ratio(DepthLaw::normal, 0), 0.02);
  EXPECT_NEAR(wall_keff_ratio(DepthLaw::normal, 75), wall_keff_ratio(DepthLaw::normal, 0), 0.02);
  EXPECT_LE(wall_keff_ratio(DepthLaw::normal, 75), 1.05);
}

TEST(StabilityTrajectoryTest, StallHeldWithoutAFilterInjectsEnergy) {
  // A plain device holds its last force through a stall: a bounce at the passivity bound
  // comes back faster than it went in.
  const AnalyticWall wall(Vec3::Zero(), Vec3(0, 0, 1));
  Workspace map;
  map.metres_per_unit = 1.0;
  ForceLaw law;
  law.stiffness_n_per_m = 3000.f;
  law.metres_per_unit = 1.f;
  ClosedLoopRun run;
  run.device = falcon_profile();
  run.device.damping_n_s_per_m = 1.5;
  run.start_m = Vec3d(0, 0, 1e-9);
  run.start_velocity = Vec3d(0, 0, -0.1);
  run.seconds = 0.2;
  run.stylus_m = 0.05;
  run.stop_after_contact_ticks = 1;
  const auto plain = run_closed_loop(wall, law, map, run);
  run.stalls = {Stall{10, 5}};  // on the way out: the held force exceeds the spring's
  const auto stalled = run_closed_loop(wall, law, map, run);
  EXPECT_LE(plain.back().v.z() / 0.1, 1.0);
  EXPECT_GT(stalled.back().v.z() / 0.1, plain.back().v.z() / 0.1 + 0.02);
}

TEST(StabilityTrajectoryTest, GeneratedGroovesAndPlatesAreClosedAndOutward) {
  for (const TriangleMesh& m : {make_v_groove(90.f, false), make_v_groove(60.f, true), make_plate(0.25f)}) {
    const ExactQuery exact(m);
    ForceLaw law;
    // From high above the centre straight down: the top surface (or the crease) answers.
    const Contact c = exact.query(Segment{Vec3(0.2f, 0.1f, 30.f), Vec3(0.2f, 0.1f, -0.01f)}, law);
    ASSERT_TRUE(c.contact);
    EXPECT_GT(c.normal.z(), 0.4f);
  }
}

TEST(StabilitySuiteTest, RefinedSphereHasNoGhostsAndPassesTheGeometryTests) {
  // A small refined sphere as "the model": T2 (slides), T5 (tilt), T7 (release).
  const TriangleMesh mesh = make_sphere(20.f, 4);
  BakeOptions bo;
  bo.params.m = 16;
  bo.params.n = 8;
  bo.refine = true;
  const BoxScene box = bake_scene(mesh, {}, bo, SourceInfo{});
  StabilityOptions o;
  o.tests = {"T2", "T5", "T7"};
  o.sites = 4;
  o.generated = false;
  const StabilityReport r = run_stability_suite(box, mesh, o);
  EXPECT_TRUE(r.calibration_pass);
  ASSERT_FALSE(r.metrics.empty());
  const auto* ghost = find(r.metrics, "T2", "ghost");
  ASSERT_NE(ghost, nullptr);
  EXPECT_EQ(ghost->box, 0.0);
  const auto* tilt = find(r.metrics, "T5", "30 deg");
  ASSERT_NE(tilt, nullptr);
  EXPECT_TRUE(tilt->pass) << tilt->box;
  EXPECT_TRUE(tilt->exact_pass) << tilt->exact;
  const auto* hover = find(r.metrics, "T7", "hovering");
  ASSERT_NE(hover, nullptr);
  EXPECT_TRUE(hover->pass);
  StabilityOptions bad;
  bad.tests = {"T9"};
  EXPECT_THROW(run_stability_suite(box, mesh, bad), InvalidInput);
}

// T4 on the generated grooves: the welded grooves' refined boxes keep the contact and are as
// calm as exact (their walls have vertices of their own, joined at the crease by position:
// before, the refinement could not cross the crease and the box lost the corner, reported as
// 99). The crisp grooves chatter for exact too (the force law's limit).
TEST(StabilitySuiteTest, RefinedBoxesOfWeldedGroovesHoldTheCornerAsCalmlyAsExact) {
  const StabilityReport r = grooves_t4(ContactLaw::penalty);
  std::size_t welded = 0;
  for (const StabilityMetric& m : r.metrics) {
    ASSERT_EQ(m.test, "T4");
    EXPECT_LT(m.box, 99.0) << m.scene << ": " << m.metric;  // the contact is held
    if (m.scene.find("welded") == std::string::npos) continue;
    ++welded;
    EXPECT_TRUE(m.exact_pass) << m.scene << ": " << m.metric << " exact " << m.exact;
    EXPECT_TRUE(m.pass) << m.scene << ": " << m.metric << " box " << m.box;
  }
  EXPECT_EQ(welded, 6u);
}

TEST(StabilitySuiteTest, RawBoxesOfCrispGroovesHoldTheCornerWhereExactChatters) {
  // T4's grooves as the suite bakes them for a raw model box (m16 n8, no triangle test).
  // Near a crisp crease some of a line's samples see the other wall; a quadric fitted to the
  // rest would carry one wall past the crease (step 6b refuses such a fit; with it the 60
  // degree groove's ripple was 0.52 and 27 wall switches a second): the box's blend holds the
  // corner (ripple 0.02), where exact chatters under the penalty law.
  const TriangleMesh mesh = make_sphere(20.f, 3);
  BakeOptions bo;
  bo.params.m = 16;
  bo.params.n = 8;
  const BoxScene box = bake_scene(mesh, {}, bo, SourceInfo{});
  StabilityOptions o;
  o.tests = {"T4"};
  o.generated_refine = false;
  const StabilityReport r = run_stability_suite(box, mesh, o);
  std::size_t crisp = 0;
  for (const StabilityMetric& m : r.metrics) {
    if (m.scene != "60 deg groove, crisp") continue;
    ++crisp;
    EXPECT_TRUE(m.pass) << m.metric << ": box " << m.box << ", exact " << m.exact;
  }
  EXPECT_EQ(crisp, 2u);
}

// ---- the proxy (god-object) over a segment-query answerer --------------------------------

namespace {

// The light grip of T4 pushing down the bisector of a groove, 0.5 mm off it, for 2 s;
// returns the lateral ripple (rms F_x / mean |F|) and the wall switches a second after 1 s.
std::pair<double, double> groove_push(const ContactQuery& q, ContactLaw law_kind) {
  Workspace map;  // the groove in mm
  ForceLaw law;
  law.stiffness_n_per_m = 1500.f;
  law.metres_per_unit = 0.001f;
  ClosedLoopRun run;
  run.device = falcon_profile();
  run.hand = light_grip();
  run.start_m = Vec3d(0.0005, 0.0013, 0.002);
  run.set_point = [](double) { return Vec3d(0, 0.0013, -0.02); };
  run.seconds = 2.0;
  run.stylus_m = 0.008;
  run.contact_law = law_kind;
  const auto ticks = run_closed_loop(q, law, map, run);
  double lat2 = 0, fsum = 0;
  int n = 0, sw = 0, last = 0;
  for (const auto& r : ticks) {
    if (r.t < 1.0) continue;
    lat2 += r.force.x() * r.force.x(), fsum += r.force.norm(), ++n;
    const int wall = r.normal.x() > 0.05 ? 1 : (r.normal.x() < -0.05 ? -1 : 0);
    if (wall != 0 && last != 0 && wall != last) ++sw;
    if (wall != 0) last = wall;
  }
  if (n == 0 || fsum / n < 0.1) return {99.0, 99.0};
  return {std::sqrt(lat2 / n) / (fsum / n), sw / (ticks.back().t - 1.0)};
}

} // namespace

TEST(StabilityProxyTest, CrispGrooveChattersUnderThePenaltyLawAndIsCalmWithTheProxy) {
  for (float deg : {60.f, 90.f, 120.f}) {
    const TriangleMesh groove = make_v_groove(deg, false);
    const ExactQuery exact(groove);
    const auto penalty = groove_push(exact, ContactLaw::penalty);
    const auto proxy = groove_push(exact, ContactLaw::proxy);
    EXPECT_GT(penalty.first, 0.3) << deg << " deg";   // 50-87 % measured
    EXPECT_GT(penalty.second, 10.0) << deg << " deg"; // about 40 a second
    EXPECT_LE(proxy.first, 0.07) << deg << " deg";
    EXPECT_LE(proxy.second, 2.0) << deg << " deg";
  }
}

TEST(StabilityProxyTest, ProxyComesToRestOnTheCreaseLineHeldByTwoPlanes) {
  const TriangleMesh groove = make_v_groove(90.f, false);
  const ExactQuery exact(groove);
  GodObject proxy(exact);
  ForceLaw law;
  law.stiffness_n_per_m = 1000.f;
  law.metres_per_unit = 0.001f;
  // The tip 1 mm below the crease (y = 0, z = 0), 0.3 mm to one side; the stylus vertical.
  const Vec3 tip(0.3f, 1.1f, -1.f);
  Contact c;
  for (int k = 0; k < 5; ++k) c = proxy.step(Segment{tip + Vec3(0, 0, 8.f), tip}, law);
  ASSERT_TRUE(c.contact);
  EXPECT_EQ(proxy.active_planes(), 2);
  EXPECT_NEAR(proxy.proxy().x(), 0.f, 1e-3f);
  EXPECT_NEAR(proxy.proxy().z(), 0.f, 1e-3f);
  EXPECT_NEAR(proxy.proxy().y(), tip.y(), 1e-3f);
  // k (proxy - tip): toward the crease, 1000 N/m over about 1.04 mm.
  EXPECT_NEAR(c.force.x(), -0.3f, 0.01f);
  EXPECT_NEAR(c.force.z(), 1.0f, 0.01f);
  EXPECT_EQ(proxy.stats().fallbacks, 0u);
}

TEST(StabilityProxyTest, FlatWallFeelsAsUnderTheNormalLawAtAnyTiltAndReleasesWithTheStylus) {
  const AnalyticWall wall(Vec3::Zero(), Vec3(0, 0, 1));
  Workspace map;
  map.metres_per_unit = 1.0;
  ForceLaw law;
  law.stiffness_n_per_m = 3000.f;
  law.metres_per_unit = 1.f;
  for (double tilt : {0.0, 45.0, 75.0}) {
    const double a = tilt * 3.14159265358979 / 180.0;
    const Vec3d dir(std::sin(a), 0, -std::cos(a));
    std::vector<Vec3d> tips;
    for (double d = -0.0005; d < 0.001; d += 1e-4) tips.push_back(Vec3d(0, 0, -d));
    for (double d = 0.001; d > -0.0005; d -= 1e-4) tips.push_back(Vec3d(0, 0, -d));
    const auto pen = play_positions(wall, law, map, tips, dir, 0.02, 1e-3, ContactLaw::penalty);
    const auto prx = play_positions(wall, law, map, tips, dir, 0.02, 1e-3, ContactLaw::proxy);
    ASSERT_EQ(pen.size(), prx.size());
    for (std::size_t k = 0; k < pen.size(); ++k) {
      EXPECT_EQ(pen[k].contact, prx[k].contact) << tilt << " deg, tick " << k;
      // The same force, but for the 0.5 um clearance (1.5 mN at 3,000 N/m).
      EXPECT_NEAR((pen[k].force - prx[k].force).norm(), 0.0, 2e-3) << tilt << " deg, tick " << k;
    }
    EXPECT_EQ(prx.back().force.norm(), 0.0);  // out of contact: no force
  }
}

TEST(StabilityProxyTest, BouncesOffAWallWithThePenaltyLawsRestitution) {
  const AnalyticWall wall(Vec3::Zero(), Vec3(0, 0, 1));
  Workspace map;
  map.metres_per_unit = 1.0;
  ForceLaw law;
  law.stiffness_n_per_m = 3000.f;
  law.metres_per_unit = 1.f;
  double restitution[2];
  for (int which = 0; which < 2; ++which) {
    ClosedLoopRun run;
    run.device = falcon_profile();
    run.start_m = Vec3d(0, 0, 1e-9);
    run.start_velocity = Vec3d(0, 0, -0.1);
    run.seconds = 0.2;
    run.stylus_m = 0.05;
    run.stop_after_contact_ticks = 1;
    run.contact_law = which ? ContactLaw::proxy : ContactLaw::penalty;
    restitution[which] = run_closed_loop(wall, law, map, run).back().v.z() / 0.1;
  }
  EXPECT_NEAR(restitution[0], 1.148, 0.01);
  EXPECT_NEAR(restitution[1], restitution[0], 0.01);
  EXPECT_EQ(contact_law("proxy"), ContactLaw::proxy);
  EXPECT_THROW(contact_law("spring"), InvalidInput);
}

TEST(StabilitySuiteTest, RefinedBoxesOfCrispGroovesHoldTheCornerCalmlyWithTheProxyAsExactDoes) {
  const StabilityReport r = grooves_t4(ContactLaw::proxy);
  EXPECT_EQ(r.contact_law, "proxy");
  std::size_t crisp = 0;
  for (const StabilityMetric& m : r.metrics) {
    ASSERT_EQ(m.test, "T4");
    // Welded grooves: calm (ripple) with the proxy too; their shaded planes let the rest
    // normal wander past 0.05 a few times a second (measured: exact 3 a second at 60 deg).
    if (m.scene.find("crisp") == std::string::npos && m.metric.find("ripple") == std::string::npos) continue;
    if (m.scene.find("crisp") != std::string::npos) ++crisp;
    EXPECT_TRUE(m.exact_pass) << m.scene << ": " << m.metric << " exact " << m.exact;
    EXPECT_TRUE(m.pass) << m.scene << ": " << m.metric << " box " << m.box;
  }
  EXPECT_EQ(crisp, 6u);
}

namespace {

// The armadillo (datasets/data/meshes), fitted into the device space as the suite fits it (its
// diagonal at 80 mm), with the suite's second T1 site (seed 1, sites by area): a point under
// an overhang.
struct ArmadilloSite {
  TriangleMesh mesh;
  Workspace map;
  ForceLaw law;  // k = K_max / 2, T1's hold
  Vec3d surface{Vec3d::Zero()}, inward{Vec3d::Zero()};
};

bool armadillo_site(ArmadilloSite& a) {
  const std::string file = std::string(HB_DATASETS_DIR) + "/meshes/armadillo.off";
  if (!std::ifstream(file)) return false;
  a.mesh = read_mesh(file);
  const ExactQuery exact(a.mesh);
  a.map = make_workspace(a.mesh.bounds());  // the suite: the bounding-box diagonal at 80 mm
  a.law.stiffness_n_per_m = float(0.5 * falcon_profile().max_stiffness_n_per_m);
  a.law.metres_per_unit = float(a.map.metres_per_unit);
  ProbeOptions po;
  po.cone_degrees = 0.f;
  po.max_depth_fraction = 0.f;
  po.length_fraction = 0.05f;
  po.seed = 1;
  int kept = 0;
  for (const Segment& s : sample_probes(a.mesh, 12 * 8, po)) {
    const Vec3d surface = a.map.to_device(s.end), inward = (s.end - s.start).cast<double>().normalized();
    bool ok = true;
    for (double depth : {0.001, 0.002}) {
      const Rendered r = render(exact, a.law, a.map, surface + depth * inward, inward, 0.008);
      ok = ok && r.contact && std::fabs(r.depth_m - depth) < 0.2e-3;
    }
    if (ok && ++kept == 2) {
      a.surface = surface, a.inward = inward;
      return true;
    }
  }
  return false;
}

// T1's hold there: a light grip from 2 mm outside pulling 30 mm in (reached in 0.5 s), the
// stylus (8 mm) along the inward normal, through a proxy over `q`, for 2.5 s.
std::vector<TickRecord> armadillo_hold(const ContactQuery& q, const ArmadilloSite& a) {
  ClosedLoopRun run;
  run.device = falcon_profile();
  run.hand = light_grip();
  run.contact_law = ContactLaw::proxy;
  run.start_m = a.surface - 0.002 * a.inward;
  const Vec3d from = run.start_m, to = a.surface + 0.03 * a.inward;
  run.set_point = [from, to](double t) { return t < 0.5 ? from + (to - from) * (t / 0.5) : to; };
  run.seconds = 2.5;
  run.stylus_dir = a.inward;
  run.stylus_m = 0.008;
  return run_closed_loop(q, a.law, a.map, run);
}

} // namespace

TEST(StabilityProxyTest, LightGripHoldUnderTheArmadillosOverhangDecays) {
  // With the planes on the shaded normals the proxy crept along the crossings of the planes
  // its grazing paths made, the hand kept moving, and the rms speed of 1.75-2.5 s was 0.48
  // of that of 1-1.75 s on exact (0.85 for the box's proxy, parting from exact's); settled,
  // the grip's own damping gives 0.096, as on the flat wall.
  ArmadilloSite a;
  if (!armadillo_site(a)) GTEST_SKIP() << HB_DATASETS_DIR << "/meshes/armadillo.off is absent: run datasets/fetch.sh";
  const ExactQuery exact(a.mesh);
  const auto ticks = armadillo_hold(exact, a);
  double early = 0, late = 0;
  int ne = 0, nl = 0;
  for (const auto& r : ticks) {
    if (r.t >= 1.0 && r.t < 1.75) early += r.v.squaredNorm(), ++ne;
    if (r.t >= 1.75) late += r.v.squaredNorm(), ++nl;
  }
  ASSERT_GT(ne, 0);
  ASSERT_GT(nl, 0);
  EXPECT_LT(std::sqrt(late / nl) / std::sqrt(early / ne), 0.2);
}

TEST(StabilityProxyTest, BoxAndExactProxiesHoldTogetherUnderTheArmadillosOverhang) {
  // The box's answers are exact's up to float rounding and its normals' 32-bit code (about
  // 1e-5). The proxy that crept amplified that: at this site the two parted by 0.01 mm
  // within 0.25 s. A refined box of the mesh's triangles within 12 mm of the site (baked as
  // the suite bakes its generated objects) against exact on the whole mesh.
  ArmadilloSite a;
  if (!armadillo_site(a)) GTEST_SKIP() << HB_DATASETS_DIR << "/meshes/armadillo.off is absent: run datasets/fetch.sh";
  const ExactQuery exact(a.mesh);
  std::vector<std::uint32_t> near;
  for (std::uint32_t t = 0; t < a.mesh.triangles.size(); ++t)
    if ((a.map.to_device(a.mesh.positions[a.mesh.triangles[t][0]]) - a.surface).norm() < 0.012) near.push_back(t);
  BakeOptions bo;
  bo.params.m = 16;
  bo.params.n = 8;
  bo.refine = true;
  const BoxScene box = bake_scene_from_lists(a.mesh, {near}, bo, SourceInfo{});
  const auto tb = armadillo_hold(box, a), te = armadillo_hold(exact, a);
  ASSERT_EQ(tb.size(), te.size());
  double worst = 0;
  for (std::size_t k = 0; k < tb.size(); ++k) {
    EXPECT_EQ(tb[k].contact, te[k].contact) << "tick " << k;
    worst = std::max(worst, (tb[k].x - te[k].x).norm());
  }
  EXPECT_LT(worst, 1e-6);  // metres: the device's paths within 1 um
}
