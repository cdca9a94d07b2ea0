// The exact reference agrees with a brute-force triangle test.
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
