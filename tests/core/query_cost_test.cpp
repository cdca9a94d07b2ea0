// The cheaper routed query: the candidates' plane crossings four at a time, the
// walk memo that stops the refinement's walks where an earlier walk of the same line went,
// and the grid's brick summaries. Each must give the answers of the plain code.
#include "surface/scene_grid.h"
#include "surface/surface_triangles.h"
#include "mesh/generators.h"
#include "two_spheres.h"
#include <gtest/gtest.h>
#include <algorithm>
#include <limits>
#include <random>
#include <set>
#include <tuple>

namespace hb {
namespace {

const TriangleMesh& bumpy() {
  static const TriangleMesh mesh = make_bumpy_sphere({1.f, 0.06f, 6, 4});
  return mesh;
}

// Random lines from outside the sphere towards it, and random triangles, some out of range.
struct Line {
  float o[3], d[3];
};
// The triangle the line crosses first (brute force), and the rings of its neighbours.
std::vector<std::uint32_t> around_crossing(const SurfaceTriangles& surface, const Line& line, int count) {
  std::uint32_t first = kNoTriangle;
  float best = std::numeric_limits<float>::infinity();
  for (std::uint32_t t = 0; t < surface.size(); ++t) {
    float s = 0.f;
    Vec3 n;
    bool front = false;
    if (surface.intersect(t, line.o, line.d, 0.f, s, n, front) && s < best) best = s, first = t;
  }
  std::vector<std::uint32_t> out;
  if (first == kNoTriangle) return out;
  out.push_back(first);
  for (std::size_t k = 0; out.size() < std::size_t(count) && k < out.size(); ++k)
    for (std::uint32_t nb : surface.records()[out[k]].neighbour)
      if (nb != kNoTriangle && out.size() < std::size_t(count) && std::find(out.begin(), out.end(), nb) == out.end())
        out.push_back(nb);
  return out;
}
Line random_line(std::mt19937& rng) {
  std::uniform_real_distribution<float> u(-1.f, 1.f);
  Vec3 from(u(rng), u(rng), u(rng)), to(0.3f * u(rng), 0.3f * u(rng), 0.3f * u(rng));
  from = 1.6f * from.normalized();
  const Vec3 d = (to - from).normalized();
  return {{from.x(), from.y(), from.z()}, {d.x(), d.y(), d.z()}};
}

TEST(QueryCostTest, PlaneHitsFourAtATimeGiveIntersectsAnswersBitForBit) {
  const SurfaceTriangles surface(bumpy());
  std::mt19937 rng(3);
  std::uniform_int_distribution<std::uint32_t> pick(0, std::uint32_t(surface.size()) + 20);
  std::size_t crossed = 0, compared = 0;
  for (int trial = 0; trial < 2000; ++trial) {
    const Line line = random_line(rng);
    const int count = 1 + trial % 16;
    std::uint32_t ids[16];
    const std::vector<std::uint32_t> near = trial % 2 ? around_crossing(surface, line, count) : std::vector<std::uint32_t>{};
    for (int k = 0; k < count; ++k)
      ids[k] = std::size_t(k) < near.size() ? near[std::size_t(k)] : trial % 5 == 0 && k == 0 ? kNoTriangle : pick(rng);
    if (trial % 7 == 0) std::swap(ids[0], ids[count - 1]);
    float u[16], v[16], s[16];
    const unsigned ok = surface.plane_hits(ids, count, line.o, line.d, u, v, s);
    for (int k = 0; k < count; ++k) {
      float s_ref = 0.f, outside = 0.f;
      Vec3 n_ref;
      bool front_ref = false;
      const bool hit = surface.intersect(ids[k], line.o, line.d, 0.f, s_ref, n_ref, front_ref, &outside);
      ++compared;
      if (!((ok >> k) & 1u)) {
        EXPECT_FALSE(hit) << trial << " " << k;
        EXPECT_EQ(outside, std::numeric_limits<float>::infinity()) << trial << " " << k;
        continue;
      }
      const float w = std::min(std::min(u[k], v[k]), 1.f - u[k] - v[k]);
      if (w < 0.f) {
        EXPECT_FALSE(hit);
        EXPECT_EQ(outside, -w) << trial << " " << k;
        continue;
      }
      EXPECT_EQ(outside, 0.f);
      float s_out = 0.f;
      Vec3 n;
      bool front = false;
      const bool shaded = surface.shade(ids[k], line.d, u[k], v[k], s[k], 0.f, s_out, n, front);
      ASSERT_EQ(shaded, hit) << trial << " " << k;
      if (!hit) continue;
      ++crossed;
      EXPECT_EQ(s_out, s_ref);
      EXPECT_EQ(n, n_ref);
      EXPECT_EQ(front, front_ref);
    }
  }
  EXPECT_GT(crossed, 100u);
  EXPECT_GT(compared, 10000u);
}

TEST(QueryCostTest, WalksWithAMemoFindEveryCrossingTheWalksWithoutOneFind) {
  const SurfaceTriangles surface(bumpy());
  std::mt19937 rng(5);
  std::uniform_int_distribution<std::uint32_t> pick(0, std::uint32_t(surface.size()) - 1);
  std::size_t recorded_lines = 0, found = 0;
  for (int trial = 0; trial < 300; ++trial) {
    const Line line = random_line(rng);
    // Starts near each other (a walk's neighbours, as a refinement's candidates are) and
    // some anywhere.
    std::vector<std::uint32_t> starts = around_crossing(surface, line, 40);
    if (starts.size() > 12) starts.erase(starts.begin(), starts.begin() + 12);  // a ring or two away
    starts.push_back(pick(rng));
    std::shuffle(starts.begin(), starts.end(), rng);
    if (starts.size() > 12) starts.resize(12);
    const int steps = 2 + trial % 8;
    std::set<std::tuple<std::uint32_t, float, bool>> plain, memoed;
    SurfaceTriangles::WalkMemo memo;
    for (std::uint32_t start : starts) {
      float s = 0.f;
      Vec3 n;
      bool front = false;
      std::uint32_t id = kNoTriangle;
      if (surface.walk(start, line.o, line.d, 0.f, steps, s, n, front, &id)) plain.insert({id, s, front});
      std::uint32_t id_m = kNoTriangle;
      float s_m = 0.f;
      Vec3 n_m;
      bool front_m = false;
      if (surface.walk(start, line.o, line.d, 0.f, steps, s_m, n_m, front_m, &id_m, &memo)) {
        memoed.insert({id_m, s_m, front_m});
        EXPECT_EQ(id_m, id);
        EXPECT_EQ(s_m, s);
        EXPECT_EQ(n_m, n);
      }
    }
    EXPECT_EQ(plain, memoed) << trial;
    found += plain.size();
    recorded_lines += memo.used > 0 ? 1 : 0;
  }
  EXPECT_GT(found, 100u);
  EXPECT_GT(recorded_lines, 150u);
}

TEST(QueryCostTest, BrickSummariesHoldTheStateOfEveryCellOfAnEmptyBrick) {
  const test::TwoSpheres two = test::two_spheres(3.f);
  std::vector<std::vector<std::uint32_t>> lists(2);
  for (std::uint32_t t = 0; t < two.piece.size(); ++t) lists[two.piece[t]].push_back(t);
  const SceneGrid grid = build_scene_grid(two.mesh, lists, SceneGridOptions{1.f / 90.f});
  const auto& d = grid.dims();
  const int bx = (d[0] + 3) / 4, by = (d[1] + 3) / 4, bz = (d[2] + 3) / 4;
  ASSERT_EQ(grid.bricks().size(), std::size_t(bx) * std::size_t(by) * std::size_t(bz));
  std::size_t index = 0, empty_inside = 0, empty_outside = 0, far = 0;
  for (int z = 0; z < d[2]; ++z)
    for (int y = 0; y < d[1]; ++y)
      for (int x = 0; x < d[0]; ++x, ++index) {
        const std::uint8_t b = grid.bricks()[(std::size_t(z / 4) * std::size_t(by) + std::size_t(y / 4)) * std::size_t(bx) +
                                             std::size_t(x / 4)];
        const std::uint16_t code = grid.codes()[index];
        if ((b & SceneGrid::kBrickSurface) == SceneGrid::kBrickSurface) continue;
        ASSERT_LT(code, SceneGrid::kFirstSurface) << x << " " << y << " " << z;
        ASSERT_EQ(code, b & SceneGrid::kBrickSurface) << x << " " << y << " " << z;
        empty_inside += code == SceneGrid::kInside ? 1 : 0;
        empty_outside += code == SceneGrid::kOutside ? 1 : 0;
        far += (b >> 2) >= 2 ? 1 : 0;
      }
  EXPECT_GT(empty_inside, 0u);
  EXPECT_GT(empty_outside, 0u);
  EXPECT_GT(far, 0u);
  // The brick distance: no surface brick within (distance - 1) bricks.
  for (int z = 0; z < bz; ++z)
    for (int y = 0; y < by; ++y)
      for (int x = 0; x < bx; ++x) {
        const int dist = grid.bricks()[(std::size_t(z) * std::size_t(by) + std::size_t(y)) * std::size_t(bx) + std::size_t(x)] >> 2;
        for (int Z = std::max(0, z - dist + 1); Z <= std::min(bz - 1, z + dist - 1); ++Z)
          for (int Y = std::max(0, y - dist + 1); Y <= std::min(by - 1, y + dist - 1); ++Y)
            for (int X = std::max(0, x - dist + 1); X <= std::min(bx - 1, x + dist - 1); ++X) {
              const std::uint8_t o = grid.bricks()[(std::size_t(Z) * std::size_t(by) + std::size_t(Y)) * std::size_t(bx) + std::size_t(X)];
              ASSERT_NE(o & SceneGrid::kBrickSurface, SceneGrid::kBrickSurface) << x << " " << y << " " << z;
            }
      }
}

} // namespace
} // namespace hb
