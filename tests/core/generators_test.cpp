#include "mesh/generators.h"

#include "errors.h"
#include "mesh_checks.h"

#include <gtest/gtest.h>

#include <cmath>

namespace hb {
namespace {

constexpr double kPi = 3.14159265358979323846;

TEST(GeneratorsTest, SphereIsClosedOutwardWithStatedCount) {
  const TriangleMesh m = make_sphere(2.f, 4);
  EXPECT_EQ(m.triangle_count(), 20u * 256u);
  EXPECT_EQ(m.vertex_count(), 10u * 256u + 2u);
  EXPECT_TRUE(test::is_watertight(m));
  EXPECT_TRUE(test::normals_are_unit(m));
  const double v = test::signed_volume(m);
  EXPECT_GT(v, 0.0);
  EXPECT_NEAR(v, 4.0 / 3.0 * kPi * 8.0, 0.01 * 4.0 / 3.0 * kPi * 8.0);
  for (const Vec3& p : m.positions) EXPECT_NEAR(p.norm(), 2.f, 1e-5f);
}

TEST(GeneratorsTest, IcosahedronIsOutward) {
  const TriangleMesh m = make_sphere(1.f, 0);
  EXPECT_EQ(m.triangle_count(), 20u);
  EXPECT_TRUE(test::is_watertight(m));
  for (const Triangle& t : m.triangles) {
    const Vec3 n = (m.positions[t[1]] - m.positions[t[0]]).cross(m.positions[t[2]] - m.positions[t[0]]);
    EXPECT_GT(n.dot(m.positions[t[0]]), 0.f);  // every face, not just the sum
  }
}

TEST(GeneratorsTest, CubeIsClosedOutwardWithStatedCount) {
  const TriangleMesh m = make_cube(Vec3(1.f, 2.f, 3.f), 3);
  EXPECT_EQ(m.triangle_count(), 6u * 9u * 2u);
  EXPECT_EQ(m.vertex_count(), 6u * 16u - 12u * 4u + 8u);  // welded borders: 4^3 - 2^3
  EXPECT_TRUE(test::is_watertight(m));
  EXPECT_NEAR(test::signed_volume(m), 48.0, 1e-4);
  EXPECT_NEAR(m.area(), 2.0 * (8.0 + 12.0 + 24.0), 1e-4);
}

TEST(GeneratorsTest, EllipsoidIsClosedOutward) {
  const TriangleMesh m = make_ellipsoid(Vec3(1.f, 2.f, 0.5f), 4);
  EXPECT_TRUE(test::is_watertight(m));
  EXPECT_TRUE(test::normals_are_unit(m));
  EXPECT_NEAR(test::signed_volume(m), 4.0 / 3.0 * kPi, 0.02 * 4.0 / 3.0 * kPi);
}

TEST(GeneratorsTest, TorusIsClosedOutwardWithStatedCount) {
  const TriangleMesh m = make_torus(2.f, 0.5f, 64, 32);
  EXPECT_EQ(m.triangle_count(), 2u * 64u * 32u);
  EXPECT_TRUE(test::is_watertight(m));
  const double exact = 2.0 * kPi * kPi * 2.0 * 0.25;
  EXPECT_NEAR(test::signed_volume(m), exact, 0.02 * exact);
}

TEST(GeneratorsTest, BumpySphereDefaultsHaveStatedCountAndStayStarShaped) {
  const BumpySphereOptions options;
  const TriangleMesh m = make_bumpy_sphere(options);
  EXPECT_EQ(m.triangle_count(), 327680u);
  EXPECT_GE(m.triangle_count(), 200000u);
  EXPECT_TRUE(test::is_watertight(m));
  EXPECT_TRUE(test::normals_are_unit(m));
  EXPECT_GT(test::signed_volume(m), 0.0);
  float lo = 1e9f, hi = 0.f;
  for (const Vec3& p : m.positions) {
    lo = std::min(lo, p.norm());
    hi = std::max(hi, p.norm());
  }
  EXPECT_NEAR(hi, 1.f + options.bump_amplitude, 1e-3f);  // amplitude is exactly the peak
  EXPECT_GE(lo, 1.f - options.bump_amplitude - 1e-3f);
  EXPECT_LT(hi - lo, 0.2f);
  // Star-shaped about the centre: every face sees the origin from its back side.
  for (const Triangle& t : m.triangles) {
    const Vec3 n = (m.positions[t[1]] - m.positions[t[0]]).cross(m.positions[t[2]] - m.positions[t[0]]);
    ASSERT_GT(n.dot(m.positions[t[0]]), 0.f);
  }
}

TEST(GeneratorsTest, ChessPieceDefaultsAreClosedOutwardAndLarge) {
  const ChessPieceOptions options;
  const TriangleMesh m = make_chess_piece(options);
  EXPECT_EQ(m.triangle_count(), 2u * std::size_t(options.profile_samples - 1) * std::size_t(options.segments));
  EXPECT_GE(m.triangle_count(), 100000u);
  EXPECT_TRUE(test::is_watertight(m));
  EXPECT_TRUE(test::normals_are_unit(m));
  EXPECT_GT(test::signed_volume(m), 0.0);
  const Bounds b = m.bounds();
  EXPECT_NEAR(b.min.z(), 0.f, 1e-6f);
  EXPECT_NEAR(b.max.z(), options.height, 1e-5f);
}

TEST(GeneratorsTest, ChessPieceProfileHasSeveralNecks) {
  // Radius along the height, from the ring vertices: count local minima (necks).
  ChessPieceOptions options;
  options.segments = 8;
  const TriangleMesh m = make_chess_piece(options);
  std::vector<float> radius;
  for (int k = 0; k + 1 < options.profile_samples; ++k) {
    const Vec3& p = m.positions[std::size_t(k) * options.segments];
    radius.push_back(Eigen::Vector2f(p.x(), p.y()).norm());
  }
  int necks = 0;
  for (std::size_t i = 1; i + 1 < radius.size(); ++i)
    if (radius[i] < radius[i - 1] && radius[i] <= radius[i + 1]) ++necks;
  EXPECT_GE(necks, 3);
}

TEST(GeneratorsTest, BadOptionsAreInvalidInput) {
  EXPECT_THROW(make_sphere(-1.f, 2), InvalidInput);
  EXPECT_THROW(make_sphere(1.f, -1), InvalidInput);
  EXPECT_THROW(make_cube(Vec3(1, 0, 1)), InvalidInput);
  EXPECT_THROW(make_torus(1.f, 2.f, 8, 8), InvalidInput);
  BumpySphereOptions bumpy;
  bumpy.bump_amplitude = 0.5f;
  EXPECT_THROW(make_bumpy_sphere(bumpy), InvalidInput);
  ChessPieceOptions chess;
  chess.segments = 3;
  EXPECT_THROW(make_chess_piece(chess), InvalidInput);
}

} // namespace
} // namespace hb
