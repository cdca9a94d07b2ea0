// The exact reference agrees with a brute-force triangle test.
#include "errors.h"
#include "exact/exact_query.h"
#include "mesh/generators.h"
#include <gtest/gtest.h>
#include <algorithm>
#include <random>

namespace hb {
namespace {

// Möller-Trumbore first hit over all triangles, and whether it is a back face.
bool brute_force_first_hit(const TriangleMesh& m, const Vec3& o, const Vec3& d, float t_max, float& t_hit, bool& back) {
  bool found = false;
  t_hit = t_max;
  for (const Triangle& tri : m.triangles) {
    const Vec3 &a = m.positions[tri[0]], &b = m.positions[tri[1]], &c = m.positions[tri[2]];
    const Vec3 e1 = b - a, e2 = c - a, p = d.cross(e2);
    const float det = e1.dot(p);
    if (std::fabs(det) < 1e-12f) continue;
    const float inv = 1.f / det;
    const Vec3 s = o - a;
    const float u = s.dot(p) * inv;
    if (u < 0.f || u > 1.f) continue;
    const Vec3 q = s.cross(e1);
    const float v = d.dot(q) * inv;
    if (v < 0.f || u + v > 1.f) continue;
    const float t = e2.dot(q) * inv;
    if (t >= 0.f && t <= t_hit) {
      t_hit = t;
      back = e1.cross(e2).dot(d) > 0.f;
      found = true;
    }
  }
  return found;
}

void check_against_brute_force(const TriangleMesh& mesh, unsigned seed) {
  const ExactQuery exact(mesh);
  const ForceLaw law{100.f, 1.f};
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> u(-2.f, 2.f);
  int contacts = 0;
  for (int i = 0; i < 300; ++i) {
    const Segment s{Vec3(u(rng), u(rng), u(rng)), Vec3(u(rng), u(rng), u(rng))};
    const float len = (s.end - s.start).norm();
    const Vec3 dir = (s.end - s.start) / len;
    float t = 0.f;
    bool back = false;
    const bool hit = brute_force_first_hit(mesh, s.start, dir, len, t, back);
    const Contact c = exact.query(s, law);
    ASSERT_EQ(c.contact, hit && !back) << "probe " << i;
    if (c.contact) {
      ++contacts;
      EXPECT_NEAR(c.depth, len - t, 1e-4f);
      EXPECT_NEAR(c.force.norm(), law.stiffness_n_per_m * c.depth * std::max(0.f, -dir.dot(c.normal)), 1e-3f);
    }
  }
  EXPECT_GT(contacts, 10);
}

TEST(ExactQueryTest, AgreesWithBruteForceOnSphere) { check_against_brute_force(make_sphere(1.f, 3), 3); }
TEST(ExactQueryTest, AgreesWithBruteForceOnTorus) { check_against_brute_force(make_torus(1.f, 0.4f, 32, 16), 5); }
TEST(ExactQueryTest, AgreesWithBruteForceOnCube) { check_against_brute_force(make_cube(Vec3(1.f, 0.7f, 0.5f), 3), 9); }

TEST(ExactQueryTest, HandleInsideTheObjectHasNoContact) {
  const TriangleMesh sphere = make_sphere(1.f, 3);
  const ExactQuery exact(sphere);
  EXPECT_FALSE(exact.query({Vec3(0.f, 0.f, 0.f), Vec3(0.f, 0.f, 2.f)}, {}).contact);
}

} // namespace
} // namespace hb

// A scene of some of the mesh's triangles holds only their vertices: each ray hits what the
// whole mesh's scene hits among those triangles (same triangle, same t, same normal), and a
// triangle id beyond the mesh is an error naming it.
TEST(ExactQueryTest, ASceneOfSomeTrianglesHitsAsTheWholeMeshDoesOnThem) {
  const hb::TriangleMesh mesh = hb::make_sphere(1.f, 3);
  std::vector<std::uint32_t> half;
  for (std::uint32_t t = 0; t < mesh.triangle_count(); ++t)
    if (mesh.positions[mesh.triangles[t][0]].x() > 0.f) half.push_back(t);
  ASSERT_GT(half.size(), 10u);
  const hb::EmbreeScene all(mesh), some(mesh, half);
  std::mt19937 rng(3);
  std::uniform_real_distribution<float> u(-1.f, 1.f);
  std::size_t hits = 0;
  for (int i = 0; i < 2000; ++i) {
    const hb::Vec3 dir = hb::Vec3(u(rng), u(rng), u(rng)).normalized();
    const hb::RayHit a = all.intersect(-3.f * dir, dir, 0.f, 10.f), b = some.intersect(-3.f * dir, dir, 0.f, 10.f);
    // From outside towards the centre the first hit of the whole sphere is on the near side:
    // where that is the +x half, the half scene hits the same triangle.
    if (!a.hit || !std::binary_search(half.begin(), half.end(), a.triangle)) continue;
    ASSERT_TRUE(b.hit) << i;
    EXPECT_EQ(a.triangle, b.triangle);
    EXPECT_EQ(a.t, b.t);
    EXPECT_EQ(a.normal, b.normal);
    ++hits;
  }
  EXPECT_GT(hits, 300u);
  EXPECT_THROW(hb::EmbreeScene(mesh, {std::uint32_t(mesh.triangle_count())}), hb::InvalidInput);
}

// The quick tree (the budgeted bake's own reference) answers as the best one: the same
// contacts, depths and forces on random segments.
TEST(ExactQueryTest, TheQuickTreeAnswersAsTheBestOne) {
  const hb::TriangleMesh mesh = hb::make_torus(1.f, 0.4f, 48, 24);
  const hb::ExactQuery best(mesh), quick(mesh, hb::BvhBuild::quick);
  std::mt19937 rng(11);
  std::uniform_real_distribution<float> u(-1.6f, 1.6f);
  const hb::ForceLaw law{100.f, 1.f};
  std::size_t contacts = 0;
  for (int i = 0; i < 5000; ++i) {
    const hb::Segment s{hb::Vec3(u(rng), u(rng), u(rng)), hb::Vec3(u(rng), u(rng), u(rng))};
    const hb::Contact a = best.query(s, law), b = quick.query(s, law);
    ASSERT_EQ(a.contact, b.contact) << i;
    if (!a.contact) continue;
    ++contacts;
    EXPECT_EQ(a.depth, b.depth);
    EXPECT_EQ(a.force, b.force);
  }
  EXPECT_GT(contacts, 500u);
}
