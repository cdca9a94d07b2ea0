// Tools with volume: point shells, their spec, and the resolution of their point contacts into
// one force and torque, on analytic cases against exact Embree.
#include "errors.h"
#include "exact/exact_query.h"
#include "mesh/generators.h"
#include "two_spheres.h"
#include "tool/tool_contact.h"
#include "tool/tool_coupling.h"
#include "tool/tool_spec.h"
#include "evaluation/tool_poses_csv.h"
#include <gtest/gtest.h>
#include <cmath>
#include <random>

using namespace hb;

namespace {

constexpr float kStiffness = 1500.f;
// Models in millimetres: a tool's metres become model units at 1 mm a unit.
constexpr double kMetresPerUnit = 1e-3;

ForceLaw law() { return ForceLaw{kStiffness, float(kMetresPerUnit), DepthLaw::normal}; }
// Models in millimetres at the device (the coupling's scale).
Workspace mm_workspace() {
  Workspace w;
  w.metres_per_unit = kMetresPerUnit;
  return w;
}

// A slab whose top face is the plane z = 0 (50 mm each way), finely split.
TriangleMesh plane_slab() {
  TriangleMesh slab = make_cube(Vec3(50.f, 50.f, 10.f), 8);
  for (Vec3& p : slab.positions) p.z() -= 10.f;
  slab.compute_vertex_normals();
  return slab;
}

// A round channel of radius `r` through material: a torus of huge major radius turned inside
// out (its tube is empty space, the rest is solid), so that near (R, 0, 0) the channel runs
// along y.
TriangleMesh round_channel(float r) {
  TriangleMesh tube = make_torus(2000.f, r, 2048, 64);
  for (Triangle& t : tube.triangles) std::swap(t[1], t[2]);
  tube.compute_vertex_normals();
  return tube;
}

ToolAnswer sphere_at(const ContactQuery& q, double radius_mm, std::size_t points, const Vec3& centre) {
  ToolProbe probe(make_sphere_tool(radius_mm * 1e-3, points), kMetresPerUnit);
  ToolPose pose;
  pose.position = centre;
  return probe.answer(q, pose, law());
}

} // namespace

TEST(ToolShapeTest, SpherePointsAreEvenlySpreadOnTheSurface) {
  const ToolShape s = make_sphere_tool(0.002, 1000);
  ASSERT_EQ(s.size(), 1000u);
  Vec3 mean = Vec3::Zero();
  for (std::size_t i = 0; i < s.size(); ++i) {
    EXPECT_NEAR(s.points[i].norm(), 0.002f, 1e-7f);
    EXPECT_NEAR(s.normals[i].dot(s.points[i].normalized()), 1.f, 1e-5f);
    EXPECT_EQ(s.handles[i], Vec3::Zero());
    mean += s.points[i];
  }
  EXPECT_LT((mean / 1000.f).norm(), 1e-5f);
  // Nearest-neighbour spacing within a factor two of the even spacing sqrt(4 pi R^2 / N).
  const float even = std::sqrt(4.f * 3.14159f * 0.002f * 0.002f / 1000.f);
  for (std::size_t i = 0; i < s.size(); i += 37) {
    float nearest = 1.f;
    for (std::size_t j = 0; j < s.size(); ++j)
      if (j != i) nearest = std::min(nearest, (s.points[i] - s.points[j]).norm());
    EXPECT_GT(nearest, 0.5f * even);
    EXPECT_LT(nearest, 1.5f * even);
  }
}

TEST(ToolShapeTest, CapsuleHandlesLieOnItsAxisARadiusFromTheirPoints) {
  const ToolShape c = make_capsule_tool(0.001, 0.010, 2000);
  ASSERT_EQ(c.size(), 2000u);
  EXPECT_DOUBLE_EQ(c.radius_m, 0.005);
  for (std::size_t i = 0; i < c.size(); ++i) {
    EXPECT_NEAR(c.handles[i].x(), 0.f, 1e-9f);
    EXPECT_NEAR(c.handles[i].y(), 0.f, 1e-9f);
    EXPECT_LE(std::fabs(c.handles[i].z()), 0.004f + 1e-7f);
    EXPECT_NEAR((c.points[i] - c.handles[i]).norm(), 0.001f, 1e-6f);
    EXPECT_NEAR((c.points[i] - c.handles[i]).normalized().dot(c.normals[i]), 1.f, 1e-4f);
  }
}

TEST(ToolShapeTest, MeshToolHandlesStayInsideTheTool) {
  // A 4 mm cube as a peg: every handle inside, at most half the cube's thickness in.
  const ToolShape t = make_mesh_tool(make_cube(Vec3(2.f, 2.f, 2.f), 4), 3000);
  ASSERT_EQ(t.size(), 3000u);
  for (std::size_t i = 0; i < t.size(); ++i) {
    EXPECT_LE(t.handles[i].cwiseAbs().maxCoeff(), 0.002f);
    EXPECT_NEAR(t.points[i].cwiseAbs().maxCoeff(), 0.002f, 1e-6f);
    EXPECT_GT((t.points[i] - t.handles[i]).norm(), 0.0f);
  }
}

TEST(ToolSpecTest, ReadsEachToolAndNamesWhatIsWrong) {
  const ToolSpec s = parse_tool_spec("sphere,radius-mm=2,points=1000");
  EXPECT_EQ(s.kind, ToolKind::sphere);
  EXPECT_DOUBLE_EQ(s.radius_mm, 2.0);
  EXPECT_EQ(s.points, 1000u);
  EXPECT_EQ(parse_tool_spec(s.text()).text(), s.text());
  const ToolSpec c = parse_tool_spec("capsule,radius-mm=1,length-mm=20,points=500");
  EXPECT_EQ(c.kind, ToolKind::capsule);
  EXPECT_DOUBLE_EQ(c.length_mm, 20.0);
  const ToolSpec m = parse_tool_spec("mesh=peg.off,points=5000");
  EXPECT_EQ(m.kind, ToolKind::mesh);
  EXPECT_EQ(m.mesh_path, "peg.off");
  EXPECT_EQ(parse_tool_spec("point").kind, ToolKind::point);
  const auto message = [](const std::string& spec) {
    try {
      parse_tool_spec(spec);
    } catch (const InvalidInput& e) {
      return std::string(e.what());
    }
    return std::string("accepted");
  };
  EXPECT_NE(message("sphere,radius-mm=-1").find("radius-mm"), std::string::npos);
  EXPECT_NE(message("sphere,points=2.5").find("points"), std::string::npos);
  EXPECT_NE(message("sphere,points=0").find("points"), std::string::npos);
  EXPECT_NE(message("cube,points=10").find("unknown tool 'cube'"), std::string::npos);
  EXPECT_NE(message("sphere,radius=2").find("unknown key 'radius'"), std::string::npos);
  EXPECT_NE(message("capsule,radius-mm=3,length-mm=4").find("shorter than the diameter"), std::string::npos);
  EXPECT_NE(message("").find("name the tool"), std::string::npos);
}

TEST(ToolContactTest, ASpherePressedIntoAPlaneFeelsTheOneStiffnessTimesItsDepth) {
  const TriangleMesh slab = plane_slab();
  const ExactQuery exact(slab);
  for (const double d_mm : {0.05, 0.2, 0.5, 1.0}) {
    for (const std::size_t n : {1000, 4000, 16000}) {
      const ToolAnswer a = sphere_at(exact, 2.0, n, Vec3(0.3f, -0.2f, float(2.0 - d_mm)));
      const double expected = kStiffness * d_mm * 1e-3;
      EXPECT_NEAR(a.force.z(), expected, 0.02 * expected + 1e-3) << d_mm << " mm, " << n << " points";
      EXPECT_NEAR(a.force.x(), 0.0, 1e-4);
      EXPECT_NEAR(a.force.y(), 0.0, 1e-4);
      EXPECT_LT(a.torque.norm(), 1e-6f);
      EXPECT_GT(a.contacts, 1u);
      EXPECT_FALSE(a.pinched);
    }
  }
}

TEST(ToolContactTest, TheForceDoesNotDependOnThePointCountFromAThousandUp) {
  const TriangleMesh slab = plane_slab();
  const ExactQuery exact(slab);
  // Tilted pose: a capsule resting at 20 degrees with its lower end 0.4 mm in.
  for (const std::size_t n : {1000, 4000, 16000, 64000}) {
    ToolProbe probe(make_capsule_tool(0.001, 0.010, n), kMetresPerUnit);
    ToolPose pose;
    pose.orientation = Eigen::AngleAxisf(float(20.0 * 3.14159265 / 180.0), Vec3::UnitX());
    const float lowest = 1.f + 4.f * std::sin(float(70.0 * 3.14159265 / 180.0));
    pose.position = Vec3(0.f, 0.f, lowest - 0.4f);
    const ToolAnswer a = probe.answer(exact, pose, law());
    EXPECT_NEAR(a.force.z(), kStiffness * 0.4e-3, 0.02 * kStiffness * 0.4e-3) << n;
    // The contact is at the lower end: the torque turns the capsule towards lying flat.
    EXPECT_GT(std::fabs(a.torque.x()), 1e-4f) << n;
  }
}

TEST(ToolContactTest, ACentredSphereInARoundChannelFeelsNoLateralForce) {
  const float r = 2.f;
  const TriangleMesh channel = round_channel(r);
  const ExactQuery exact(channel);
  // Pressed into the wall all round: 2.1 mm sphere in a 2 mm channel.
  const ToolAnswer a = sphere_at(exact, 2.1, 4000, Vec3(2000.f, 0.f, 0.f));
  EXPECT_GT(a.contacts, 1000u);
  EXPECT_TRUE(a.pinched);
  EXPECT_LT(a.force.norm(), 0.04f);  // below what a hand feels
  // Off centre by 0.3 mm towards +z: pushed back towards the centre.
  const ToolAnswer b = sphere_at(exact, 1.9, 4000, Vec3(2000.f, 0.f, 0.3f));
  EXPECT_LT(b.force.z(), -0.1f);
  EXPECT_LT(std::fabs(b.force.x()) + std::fabs(b.force.y()), 0.02f * std::fabs(b.force.z()) + 0.01f);
}

TEST(ToolContactTest, TheOnePointToolAnswersAsTheProbeSegment) {
  const TriangleMesh sphere = make_sphere(10.f, 4);
  const ExactQuery exact(sphere);
  ToolProbe probe(make_point_tool(0.008), kMetresPerUnit);
  std::mt19937 rng(5);
  std::uniform_real_distribution<float> u(-1.f, 1.f);
  for (int i = 0; i < 200; ++i) {
    ToolPose pose;
    pose.position = Vec3(u(rng), u(rng), u(rng)).normalized() * (10.f + 2.f * u(rng));
    pose.orientation = Eigen::Quaternionf(u(rng), u(rng), u(rng), u(rng)).normalized();
    const ToolAnswer a = probe.answer(exact, pose, law());
    const Segment s{pose.position + pose.orientation * Vec3(0.f, 0.f, 8.f), pose.position};
    const Contact c = exact.query(s, law());
    EXPECT_EQ(a.contacts, c.contact ? 1u : 0u);
    EXPECT_LT((a.force - c.force).norm(), 1e-5f * std::max(1.f, c.force.norm()));
  }
}

TEST(ToolContactTest, AToolOutOfReachAsksNoPointAndOneWithinReachAsksThemAll) {
  const TriangleMesh slab = plane_slab();
  const ExactQuery exact(slab);
  ToolProbe probe(make_sphere_tool(0.002, 500), kMetresPerUnit);
  ToolPose far;
  far.position = Vec3(0.f, 0.f, 2.5f);
  const ToolAnswer a = probe.answer(exact, far, law());
  EXPECT_FALSE(a.reached);
  EXPECT_FALSE(probe.last_asked());
  ToolPose near = far;
  near.position.z() = 1.9f;
  const ToolAnswer b = probe.answer(exact, near, law());
  EXPECT_TRUE(b.reached);
  EXPECT_GT(b.contacts, 0u);
}

TEST(ExactQueryTest, ABatchOfRaysAnswersAsEachRayAlone) {
  const TriangleMesh torus = make_torus(10.f, 3.f, 96, 48);
  const ExactQuery exact(torus);
  std::mt19937 rng(11);
  std::uniform_real_distribution<float> u(-15.f, 15.f);
  std::vector<Segment> segments(1000);
  for (Segment& s : segments) s = {Vec3(u(rng), u(rng), u(rng)), Vec3(u(rng), u(rng), u(rng))};
  segments[3].end = segments[3].start;  // empty segment: no contact
  std::vector<Contact> many(segments.size());
  exact.query_many(segments.data(), segments.size(), law(), many.data());
  std::size_t contacts = 0;
  for (std::size_t i = 0; i < segments.size(); ++i) {
    const Contact one = exact.query(segments[i], law());
    ASSERT_EQ(one.contact, many[i].contact) << i;
    EXPECT_EQ(one.depth, many[i].depth) << i;
    EXPECT_EQ(one.force, many[i].force) << i;
    contacts += one.contact;
  }
  EXPECT_GT(contacts, 50u);
}

TEST(ToolCouplingTest, ASpherePushedThroughAThinPlateAtHalfAMetreASecondNeverPopsThrough) {
  // A 1 mm plate; the device goes from 5 mm above it to 10 mm below at 0.5 m/s (0.5 mm a tick).
  TriangleMesh plate = make_cube(Vec3(50.f, 50.f, 0.5f), 8);
  plate.compute_vertex_normals();
  const ExactQuery exact(plate);
  ToolCoupling coupling(exact, make_sphere_tool(0.002, 1000), mm_workspace());
  ToolPose device;
  float last_force = 0.f;
  for (int tick = 0; tick <= 34; ++tick) {
    device.position = Vec3(0.f, 0.f, 7.5f - 0.5f * float(tick));
    const ToolCouplingStep& s = coupling.step(device, law());
    // The simulated tool stays on the plate's top side, never more than a sub-step in.
    EXPECT_GE(s.tool.position.z(), 0.5f + 2.f - 1.01f) << tick;
    const float depth = std::max(0.f, 2.5f - device.position.z());
    EXPECT_NEAR(s.force.z(), kStiffness * depth * 1e-3f, 0.02f * kStiffness * depth * 1e-3f + 1e-3f) << tick;
    EXPECT_GE(s.force.z(), last_force - 1e-4f) << tick;  // pushing harder never lets go
    last_force = s.force.z();
  }
  EXPECT_GT(last_force, 14.f);  // 10 mm past the plate's underside: the spring says so
}

TEST(ToolCouplingTest, Resting10SecondsOnASurfaceHoldsOneSteadyForce) {
  const TriangleMesh slab = plane_slab();
  const ExactQuery exact(slab);
  ToolCoupling coupling(exact, make_sphere_tool(0.002, 1000), mm_workspace());
  ToolPose device;
  device.position = Vec3(1.f, 2.f, 1.5f);  // 0.5 mm in
  float lo = 1e9f, hi = -1e9f;
  for (int tick = 0; tick < 10000; ++tick) {
    const ToolCouplingStep& s = coupling.step(device, law());
    if (tick < 5) continue;
    lo = std::min(lo, s.force.z());
    hi = std::max(hi, s.force.z());
    EXPECT_LT(std::hypot(s.force.x(), s.force.y()), 1e-4f);
  }
  EXPECT_NEAR(lo, 0.75f, 0.015f);
  EXPECT_LT(hi - lo, 1e-4f);  // no buzz, no drift
}

TEST(ToolCouplingTest, AToolAwayFromTheSurfaceFeelsNoForce) {
  const TriangleMesh slab = plane_slab();
  const ExactQuery exact(slab);
  ToolCoupling coupling(exact, make_capsule_tool(0.001, 0.01, 1000), mm_workspace());
  ToolPose device;
  for (int tick = 0; tick < 100; ++tick) {
    device.position = Vec3(0.1f * float(tick), 0.f, 8.f);
    const ToolCouplingStep& s = coupling.step(device, law());
    EXPECT_EQ(s.force, Vec3::Zero());
    EXPECT_FALSE(s.touching);
  }
}

TEST(ToolContactTest, TheScenesStarQueryAnswersEverySegmentAsQueryDoes) {
  // The two spheres (radius 1) on the cells route; a sphere tool of radius 0.3 placed all over
  // their surfaces, from clear of them to a third of its radius in, and in the gap between.
  const test::TwoSpheres two = test::two_spheres(2.2f);
  const BoxScene scene(without_triangle_ids(test::refined_two_spheres(two)));
  ASSERT_EQ(scene.route(), SceneRoute::cells);
  const ToolShape tool = make_sphere_tool(0.3, 500);  // 1 unit a metre: radius 0.3 units
  std::mt19937 rng(3);
  std::uniform_real_distribution<float> u(-1.f, 1.f);
  std::vector<Vec3> tips(tool.size());
  std::vector<Contact> star(tool.size());
  StarScratch scratch;
  std::size_t contacts = 0;
  for (int k = 0; k < 400; ++k) {
    const Vec3 dir = Vec3(u(rng), u(rng), u(rng)).normalized();
    const Vec3 centre = (k % 2 ? Vec3(2.2f, 0.f, 0.f) : Vec3::Zero()) + dir * (1.2f + 0.15f * u(rng));
    for (std::size_t i = 0; i < tool.size(); ++i) tips[i] = centre + tool.points[i];
    scene.query_star(centre, tips.data(), tips.size(), law(), star.data(), scratch);
    for (std::size_t i = 0; i < tool.size(); ++i) {
      const Contact one = scene.query(Segment{centre, tips[i]}, law());
      ASSERT_EQ(one.contact, star[i].contact) << k << " " << i;
      EXPECT_LT((one.force - star[i].force).norm(), 1e-6f) << k << " " << i;
      contacts += one.contact;
    }
  }
  EXPECT_GT(contacts, 1000u);
}

TEST(ToolPosesCsvTest, ReadsPositionsAndOrientationsAndNamesTheLineOfABadValue) {
  const auto poses = parse_tool_poses_csv("\xEF\xBB\xBFqw, x,y,z,qx,qy,qz\r\n2,1,2,3,0,0,0\n\n0,4,5,6,0,0,3\n", "p.csv");
  ASSERT_EQ(poses.size(), 2u);
  EXPECT_EQ(poses[0].position, Vec3(1.f, 2.f, 3.f));
  EXPECT_NEAR(poses[0].orientation.w(), 1.f, 1e-6f);      // normalised
  EXPECT_NEAR(poses[1].orientation.z(), 1.f, 1e-6f);
  EXPECT_EQ(parse_tool_poses_csv("x,y,z\n1,2,3\n", "p.csv")[0].orientation.w(), 1.f);  // no orientation: identity
  const auto message = [](const std::string& text) {
    try {
      parse_tool_poses_csv(text, "p.csv");
    } catch (const InvalidInput& e) {
      return std::string(e.what());
    }
    return std::string("accepted");
  };
  EXPECT_NE(message("x,y,z\n1,2\n").find("p.csv:2: expected 3 values"), std::string::npos);
  EXPECT_NE(message("x,y,z\n1,0x10,3\n").find("p.csv:2: y is not a finite number"), std::string::npos);
  EXPECT_NE(message("x,y,z,qw\n1,2,3,1\n").find("all four columns"), std::string::npos);
  EXPECT_NE(message("x,y,z,qw,qx,qy,qz\n1,2,3,0,0,0,0\n").find("no length"), std::string::npos);
  EXPECT_NE(message("x,y,w\n").find("unknown column 'w'"), std::string::npos);
  EXPECT_NE(message("").find("empty poses file"), std::string::npos);
}
