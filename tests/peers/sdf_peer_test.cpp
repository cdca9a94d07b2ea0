// The signed distance field peer against exact Embree on analytic shapes: the same contacts
// within a voxel's worth, the product's contact definition, the broad phase, the memory target.
#include "errors.h"
#include "exact/exact_query.h"
#include "mesh/generators.h"
#include "peers/sdf_peer.h"
#include "tool/tool_contact.h"
#include <gtest/gtest.h>
#include <algorithm>
#include <cmath>
#include <random>
#include <thread>
#include <vector>

using namespace hb;

namespace {

constexpr float kStiffness = 1500.f;
constexpr float kMetresPerUnit = 1e-3f;  // models in millimetres
constexpr double kVoxel = 0.1;

ForceLaw law() { return ForceLaw{kStiffness, kMetresPerUnit, DepthLaw::normal}; }

SdfPeerOptions at_voxel(double voxel) {
  SdfPeerOptions o;
  o.voxel = voxel;
  return o;
}

// A unit direction at most `max_tilt` radians from `axis`.
Vec3 tilted(const Vec3& axis, float max_tilt, std::mt19937& rng) {
  std::uniform_real_distribution<float> u(-1.f, 1.f);
  Vec3 side = axis.cross(Vec3(u(rng), u(rng), u(rng))).normalized();
  const float tilt = max_tilt * std::fabs(u(rng));
  return (std::cos(tilt) * axis + std::sin(tilt) * side).normalized();
}

// A probe whose tip lies `depth` below the surface point `surface` of outward normal `n`,
// its handle 3 units back along a direction up to 40 degrees from -n.
Segment probe_into(const Vec3& surface, const Vec3& n, float depth, std::mt19937& rng) {
  const Vec3 tip = surface - depth * n;
  return Segment{tip + 3.f * tilted(n, 0.7f, rng), tip};
}

// Peer and exact agree on contact, and within a voxel's worth on the normal penetration,
// the normal and the force (the peer answers by the distance at the tip, exact by where the
// segment crosses the surface: the same normal depth on a plane, near it on a curved face).
void expect_agreement(const ContactQuery& peer, const ContactQuery& exact, const Segment& s, int i) {
  const Contact a = peer.query(s, law());
  const Contact e = exact.query(s, law());
  ASSERT_TRUE(e.contact) << "probe " << i;
  ASSERT_TRUE(a.contact) << "probe " << i;
  const Vec3 l = (s.end - s.start).normalized();
  const float exact_normal_depth = e.depth * -l.dot(e.normal);
  const float peer_normal_depth = a.force.norm() / (kStiffness * kMetresPerUnit);
  EXPECT_NEAR(peer_normal_depth, exact_normal_depth, kVoxel) << "probe " << i;
  EXPECT_NEAR(a.depth * -l.dot(a.normal), peer_normal_depth, 1e-4f) << "probe " << i;
  EXPECT_GT(a.normal.dot(e.normal), std::cos(0.1f)) << "probe " << i << " at depth " << exact_normal_depth
                                                    << " tilted " << std::acos(-l.dot(e.normal)) << " rad";
  EXPECT_LT((a.force - e.force).norm(), kStiffness * kMetresPerUnit * kVoxel) << "probe " << i;
  EXPECT_NEAR(a.normal.norm(), 1.f, 1e-5f);
  EXPECT_LT((a.point - (s.end + peer_normal_depth * a.normal)).norm(), 1e-4f) << "probe " << i;
}

} // namespace

TEST(SdfPeerTest, OnASphereDepthNormalAndForceAgreeWithExact) {
  const TriangleMesh sphere = make_sphere(10.f, 5);
  const SdfPeer peer(sphere, at_voxel(kVoxel));
  const ExactQuery exact(sphere);
  std::mt19937 rng(3);
  std::uniform_real_distribution<float> u(-1.f, 1.f), depth(0.01f, 0.15f);
  for (int i = 0; i < 300; ++i) {
    const Vec3 n = Vec3(u(rng), u(rng), u(rng)).normalized();
    expect_agreement(peer, exact, probe_into(10.f * n, n, depth(rng), rng), i);
  }
}

TEST(SdfPeerTest, OnACubeFaceDepthNormalAndForceAgreeWithExact) {
  const TriangleMesh cube = make_cube(Vec3(10.f, 10.f, 10.f), 8);
  const SdfPeer peer(cube, at_voxel(kVoxel));
  const ExactQuery exact(cube);
  std::mt19937 rng(4);
  std::uniform_real_distribution<float> u(-7.f, 7.f), depth(0.01f, 0.15f);
  const Vec3 faces[] = {Vec3::UnitX(), -Vec3::UnitX(), Vec3::UnitY(), -Vec3::UnitY(), Vec3::UnitZ(), -Vec3::UnitZ()};
  for (int i = 0; i < 300; ++i) {
    const Vec3& n = faces[i % 6];
    // A point of the face away from its edges (where the nearest face may be another one).
    Vec3 surface = 10.f * n;
    for (int k = 0; k < 3; ++k)
      if (n[k] == 0.f) surface[k] = u(rng);
    expect_agreement(peer, exact, probe_into(surface, n, depth(rng), rng), i);
  }
}

TEST(SdfPeerTest, AHandleInsideOrATipOutsideIsNoContact) {
  const TriangleMesh sphere = make_sphere(10.f, 5);
  const SdfPeer peer(sphere, at_voxel(kVoxel));
  // Both ends inside, near the surface: the handle is inside.
  EXPECT_FALSE(peer.query(Segment{Vec3(9.95f, 0.f, 0.f), Vec3(9.8f, 0.f, 0.f)}, law()).contact);
  // Leaving the object: the handle inside, the tip outside.
  EXPECT_FALSE(peer.query(Segment{Vec3(9.9f, 0.f, 0.f), Vec3(10.5f, 0.f, 0.f)}, law()).contact);
  // Short of the surface.
  EXPECT_FALSE(peer.query(Segment{Vec3(13.f, 0.f, 0.f), Vec3(10.05f, 0.f, 0.f)}, law()).contact);
  // Degenerate or non-finite segments.
  EXPECT_FALSE(peer.query(Segment{Vec3(9.9f, 0.f, 0.f), Vec3(9.9f, 0.f, 0.f)}, law()).contact);
  EXPECT_FALSE(peer.query(Segment{Vec3(13.f, 0.f, 0.f), Vec3(NAN, 0.f, 0.f)}, law()).contact);
  EXPECT_FALSE(peer.query(Segment{Vec3(13.f, 0.f, 0.f), Vec3(1e30f, 0.f, 0.f)}, law()).contact);
  // The same probe with the handle outside is a contact.
  EXPECT_TRUE(peer.query(Segment{Vec3(13.f, 0.f, 0.f), Vec3(9.8f, 0.f, 0.f)}, law()).contact);
}

TEST(SdfPeerTest, ATipDeeperThanTheBandFeelsTheClampedDepth) {
  const TriangleMesh cube = make_cube(Vec3(10.f, 10.f, 10.f), 8);
  const SdfPeer peer(cube, at_voxel(kVoxel));
  const float band = float(peer.band_voxels() * kVoxel);
  EXPECT_NEAR(peer.distance(Vec3(0.f, 0.f, 0.f)), -band, 1e-5f);
  EXPECT_NEAR(peer.distance(Vec3(0.f, 0.f, 30.f)), band, 1e-5f);
  // Within the band the force grows with the depth; beyond it, no normal: no contact.
  const Contact c = peer.query(Segment{Vec3(0.f, 0.f, 13.f), Vec3(0.f, 0.f, 10.f - 0.5f * band)}, law());
  ASSERT_TRUE(c.contact);
  EXPECT_NEAR(c.force.z(), kStiffness * kMetresPerUnit * 0.5f * band, 1e-3f);
  EXPECT_FALSE(peer.query(Segment{Vec3(0.f, 0.f, 13.f), Vec3(0.f, 0.f, 10.f - 3.f * band)}, law()).contact);
}

TEST(SdfPeerTest, AnInsideDepthWidensTheBandInsideToRenderIt) {
  const TriangleMesh cube = make_cube(Vec3(10.f, 10.f, 10.f), 8);
  SdfPeerOptions o = at_voxel(kVoxel);
  o.inside_depth = 1.0;
  const SdfPeer peer(cube, o);
  EXPECT_EQ(peer.inside_voxels(), 12);
  EXPECT_NEAR(peer.distance(Vec3(0.f, 0.f, 30.f)), peer.band_voxels() * kVoxel, 1e-5f);
  EXPECT_NEAR(peer.distance(Vec3(0.f, 0.f, 0.f)), -12 * kVoxel, 1e-5f);
  const Contact c = peer.query(Segment{Vec3(0.3f, 0.f, 13.f), Vec3(0.f, 0.f, 9.f)}, law());
  ASSERT_TRUE(c.contact);
  EXPECT_NEAR(c.force.z(), kStiffness * kMetresPerUnit * 1.f, 1e-3f);
  EXPECT_LT(std::hypot(c.force.x(), c.force.y()), 1e-4f);
  EXPECT_GT(peer.memory_bytes(), SdfPeer(cube, at_voxel(kVoxel)).memory_bytes());
}

TEST(SdfPeerTest, WithinReachIsFalseOnlyWhereNoSurfaceIsWithinTheRadius) {
  const TriangleMesh sphere = make_sphere(10.f, 5);
  SdfPeerOptions o = at_voxel(kVoxel);
  o.band_voxels = 10;  // the field knows distances up to 1 unit
  const SdfPeer peer(sphere, o);
  EXPECT_FALSE(peer.within_reach(Vec3(0.f, 0.f, 30.f), 0.5f));
  EXPECT_FALSE(peer.within_reach(Vec3(0.f, 0.f, 10.7f), 0.4f));
  EXPECT_TRUE(peer.within_reach(Vec3(0.f, 0.f, 10.7f), 0.75f));
  EXPECT_TRUE(peer.within_reach(Vec3(0.f, 0.f, 30.f), 2.f));  // beyond the band: cannot tell
  EXPECT_TRUE(peer.within_reach(Vec3(0.f, 0.f, 0.f), 0.1f));  // inside
  EXPECT_TRUE(peer.within_reach(Vec3(NAN, 0.f, 0.f), 0.1f));
}

TEST(SdfPeerTest, TheGridMeetsItsMemoryTarget) {
  const TriangleMesh sphere = make_sphere(10.f, 5);
  for (const std::size_t target : {std::size_t(1) << 20, std::size_t(4) << 20}) {
    SdfPeerOptions o;
    o.memory_bytes = target;
    const SdfPeer peer(sphere, o);
    EXPECT_NEAR(double(peer.memory_bytes()) / double(target), 1.0, 0.25) << peer.describe();
    EXPECT_LE(peer.builds(), 3);
    EXPECT_GT(peer.voxel(), 0.0);
  }
  const TriangleMesh cube = make_cube(Vec3(10.f, 5.f, 2.f), 4);
  SdfPeerOptions o;
  o.memory_bytes = std::size_t(1) << 20;
  const SdfPeer peer(cube, o);
  EXPECT_NEAR(double(peer.memory_bytes()) / double(o.memory_bytes), 1.0, 0.25) << peer.describe();
  // A band widened inside costs voxels: the search finds a coarser voxel at the same memory.
  o.inside_depth = 0.5;
  const SdfPeer deep(cube, o);
  EXPECT_NEAR(double(deep.memory_bytes()) / double(o.memory_bytes), 1.0, 0.25) << deep.describe();
  EXPECT_GT(deep.voxel(), peer.voxel());
  EXPECT_GE(deep.inside_voxels() * deep.voxel(), 0.5 + 2 * deep.voxel() - 1e-9);
}

TEST(SdfPeerTest, ASphereToolOnAPlaneFeelsWhatItFeelsOnExact) {
  // A slab whose top face is the plane z = 0, wide enough for a 2 mm sphere.
  TriangleMesh slab = make_cube(Vec3(6.f, 6.f, 3.f), 4);
  for (Vec3& p : slab.positions) p.z() -= 3.f;
  slab.compute_vertex_normals();
  const SdfPeer peer(slab, at_voxel(kVoxel));
  const ExactQuery exact(slab);
  ToolProbe probe(make_sphere_tool(0.002, 2000), kMetresPerUnit);
  for (const float d : {0.05f, 0.2f}) {
    ToolPose pose;
    pose.position = Vec3(0.3f, -0.2f, 2.f - d);
    const ToolAnswer p = probe.answer(peer, pose, law());
    const ToolAnswer e = probe.answer(exact, pose, law());
    EXPECT_NEAR(p.force.z(), e.force.z(), 0.02f * e.force.z() + 1e-3f) << d;
    EXPECT_LT(std::hypot(p.force.x(), p.force.y()), 1e-3f) << d;
  }
}

TEST(SdfPeerTest, QueriesFromManyThreadsAnswerAsOneThread) {
  const TriangleMesh sphere = make_sphere(10.f, 4);
  const SdfPeer peer(sphere, at_voxel(kVoxel));
  std::mt19937 rng(9);
  std::uniform_real_distribution<float> u(-1.f, 1.f);
  std::vector<Segment> segments(2000);
  for (Segment& s : segments) {
    const Vec3 n = Vec3(u(rng), u(rng), u(rng)).normalized();
    s = Segment{n * 12.f, n * (10.f + 0.2f * u(rng))};
  }
  std::vector<Contact> serial(segments.size());
  peer.query_many(segments.data(), segments.size(), law(), serial.data());
  std::vector<std::vector<Contact>> parallel(4, std::vector<Contact>(segments.size()));
  std::vector<std::thread> threads;
  for (auto& out : parallel)
    threads.emplace_back([&] { peer.query_many(segments.data(), segments.size(), law(), out.data()); });
  for (std::thread& t : threads) t.join();
  for (const auto& out : parallel)
    for (std::size_t i = 0; i < segments.size(); ++i) {
      ASSERT_EQ(out[i].contact, serial[i].contact) << i;
      ASSERT_EQ(out[i].force, serial[i].force) << i;
    }
}

TEST(SdfPeerTest, AMeshWithNoTrianglesOrBadOptionsIsInvalidInput) {
  const auto message = [](const TriangleMesh& mesh, const SdfPeerOptions& o) -> std::string {
    try {
      SdfPeer peer(mesh, o);
    } catch (const InvalidInput& e) {
      return e.what();
    }
    return "";
  };
  TriangleMesh empty;
  empty.positions = {Vec3(0.f, 0.f, 0.f), Vec3(1.f, 0.f, 0.f)};
  EXPECT_NE(message(empty, at_voxel(0.1)).find("no triangles"), std::string::npos);
  const TriangleMesh cube = make_cube(Vec3(1.f, 1.f, 1.f));
  EXPECT_NE(message(cube, at_voxel(-1.0)).find("voxel -1"), std::string::npos);
  EXPECT_NE(message(cube, SdfPeerOptions{}).find("neither a voxel nor memory_bytes"), std::string::npos);
  SdfPeerOptions band = at_voxel(0.1);
  band.band_voxels = 0;
  EXPECT_NE(message(cube, band).find("band_voxels 0"), std::string::npos);
  SdfPeerOptions inside = at_voxel(0.1);
  inside.inside_depth = NAN;
  EXPECT_NE(message(cube, inside).find("inside_depth nan"), std::string::npos);
  EXPECT_NE(message(cube, at_voxel(1e-9)).find("too small"), std::string::npos);
  TriangleMesh nan_vertex = cube;
  nan_vertex.positions[2].y() = NAN;
  EXPECT_NE(message(nan_vertex, at_voxel(0.1)).find("vertex 2"), std::string::npos);
  TriangleMesh bad_index = cube;
  bad_index.triangles[5][1] = 99;
  EXPECT_NE(message(bad_index, at_voxel(0.1)).find("triangle 5 refers to vertex 99"), std::string::npos);
}
