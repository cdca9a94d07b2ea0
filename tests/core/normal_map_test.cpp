// A simplified surface's normal map (SurfaceTriangles::set_normal_map, hb::fit_normal_map):
// the full mesh's shading on a lattice over each simplified triangle, so a surface of 16 or
// 256 times fewer triangles answers with the full mesh's normals.
#include "errors.h"
#include "evaluation/probe_sampling.h"
#include "evaluation/surface_deviation.h"
#include "exact/embree_scene.h"
#include "exact/exact_query.h"
#include "recipe/bake_recipe.h"
#include "store/box_file.h"
#include "surface/surface_triangles.h"
#include "mesh/generators.h"
#include "mesh/subdivision.h"
#include "scratch_dir_test.h"
#include <gtest/gtest.h>
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>

namespace hb {
namespace {

// A coarse sphere and the mesh that flat-subdivides it twice, with the normals a file of it
// would get (recomputed from its own faces: faceted, not the coarse mesh's).
struct CoarseAndFine {
  TriangleMesh coarse, fine;
};
CoarseAndFine coarse_and_fine() {
  CoarseAndFine m;
  m.coarse = make_sphere(1.f, 2);
  m.fine = subdivide_midpoint(m.coarse, 2);
  m.fine.compute_vertex_normals();
  return m;
}

double angle_deg(const Vec3& a, const Vec3& b) {
  return std::acos(double(std::clamp(a.normalized().dot(b.normalized()), -1.f, 1.f))) * 180.0 / M_PI;
}

// The first crossing of o + s d among all of `surface`'s triangles (front or back), shaded.
bool first_hit(const SurfaceTriangles& surface, const Vec3& o, const Vec3& d, float& s, Vec3& normal) {
  const float of[3] = {o.x(), o.y(), o.z()}, df[3] = {d.x(), d.y(), d.z()};
  bool found = false;
  for (std::uint32_t id = 0; id < surface.size(); ++id) {
    float t = 0.f;
    Vec3 n;
    bool front = false;
    if (surface.intersect(id, of, df, 0.f, t, n, front) && (!found || t < s)) {
      s = t;
      normal = n;
      found = true;
    }
  }
  return found;
}

TEST(NormalMapTest, ACoarseSurfaceWithItsMapShadesAsTheMeshThatSubdividesIt) {
  const CoarseAndFine m = coarse_and_fine();
  const int side = 4;  // two midpoint levels: the lattice points are the fine mesh's vertices
  ShadingFitStats stats;
  const std::vector<std::uint32_t> by_triangle =
      fit_normal_map(m.fine, m.coarse, side, 0.01 * double(m.fine.bounds().diagonal()), nullptr, &stats);
  EXPECT_EQ(stats.fitted, stats.triangles);  // every lattice point met the fine mesh
  const std::size_t per = SurfaceTriangles::lattice_points(side);
  ASSERT_EQ(per, 15u);
  ASSERT_EQ(by_triangle.size(), m.coarse.triangle_count() * per);
  const SurfaceTriangles plain(m.coarse);
  SurfaceTriangles mapped(m.coarse);
  mapped.set_normal_map(side, by_triangle);
  EXPECT_EQ(mapped.normal_map_side(), side);
  EXPECT_EQ(mapped.normal_map_bytes(), m.coarse.triangle_count() * per * 4);

  const EmbreeScene fine_scene(m.fine);
  double mapped_max = 0.0, plain_max = 0.0, depth_max = 0.0;
  std::size_t hits = 0;
  for (const Segment& probe : sample_probes(m.fine, 1500)) {
    const Vec3 d = (probe.end - probe.start).normalized();
    const RayHit exact = fine_scene.intersect(probe.start, d, 0.f, 10.f);
    float s_mapped = 0.f, s_plain = 0.f;
    Vec3 n_mapped, n_plain;
    ASSERT_EQ(first_hit(mapped, probe.start, d, s_mapped, n_mapped), exact.hit);
    ASSERT_TRUE(first_hit(plain, probe.start, d, s_plain, n_plain) == exact.hit);
    if (!exact.hit) continue;
    ++hits;
    depth_max = std::max(depth_max, double(std::fabs(s_mapped - exact.t)));
    mapped_max = std::max(mapped_max, angle_deg(n_mapped, exact.normal));
    plain_max = std::max(plain_max, angle_deg(n_plain, exact.normal));
  }
  EXPECT_GT(hits, 1000u);
  // The same surface (coplanar pieces) and the same shading, up to rounding.
  EXPECT_LT(depth_max, 1e-5);
  EXPECT_LT(mapped_max, 0.05) << "mapped shading off by " << mapped_max << " deg";
  // Without the map the coarse corner normals shade another surface's normals.
  EXPECT_GT(plain_max, 2.0);
}

TEST(NormalMapTest, AKeptLatticeCellShadesWithTheSameBitsAlongAStroke) {
  // SurfaceTriangles::LatticeCache (a probe's query state keeps one): along a slow sweep the
  // crossing stays in a map cell for many steps; shading through the cache gives intersect()'s
  // bits, whether the cell is kept or another triangle, cell or surface comes in between.
  const CoarseAndFine m = coarse_and_fine();
  const int side = 4;
  SurfaceTriangles mapped(m.coarse), other(m.coarse);
  mapped.set_normal_map(side, fit_normal_map(m.fine, m.coarse, side, 0.01 * double(m.fine.bounds().diagonal())));
  other.set_normal_map(side, fit_normal_map(m.fine, m.coarse, side, 0.02 * double(m.fine.bounds().diagonal())));
  SurfaceTriangles::LatticeCache cache;
  std::size_t shaded = 0;
  for (int k = 0; k < 2000; ++k) {
    const float a = 0.0005f * float(k);
    const Vec3 o(2.f * std::cos(a), 2.f * std::sin(a), 0.3f), d = -o.normalized();
    const float of[3] = {o.x(), o.y(), o.z()}, df[3] = {d.x(), d.y(), d.z()};
    const SurfaceTriangles& s = (k % 500 == 499) ? other : mapped;  // another surface now and then
    for (std::uint32_t id = 0; id < s.size(); ++id) {
      float t0 = 0.f, t1 = 0.f;
      Vec3 n0, n1;
      bool f0 = false, f1 = false;
      const bool h0 = s.intersect(id, of, df, 0.f, t0, n0, f0);
      const bool h1 = s.intersect(id, of, df, 0.f, t1, n1, f1, cache);
      ASSERT_EQ(h0, h1);
      if (!h0) continue;
      ASSERT_EQ(t0, t1);
      ASSERT_EQ(n0, n1) << k;
      ASSERT_EQ(f0, f1);
      ++shaded;
    }
  }
  EXPECT_GT(shaded, 2000u);
}

TEST(NormalMapTest, AMapWithoutASideOrDataOrOfAnotherSizeIsRefused) {
  const CoarseAndFine m = coarse_and_fine();
  SurfaceTriangles surface(m.coarse);
  const std::vector<std::uint32_t> codes(m.coarse.triangle_count() * SurfaceTriangles::lattice_points(2), 0u);
  EXPECT_THROW(surface.set_normal_map(0, codes.data(), nullptr), InvalidInput);
  EXPECT_THROW(surface.set_normal_map(SurfaceTriangles::kMaxMapSide + 1, codes.data(), nullptr), InvalidInput);
  EXPECT_THROW(surface.set_normal_map(2, nullptr, nullptr), InvalidInput);
  EXPECT_THROW(surface.set_normal_map(3, codes), InvalidInput);  // sized for side 2
  SurfaceTriangles from_records(surface.records(), surface.size(), nullptr);  // no mesh order to follow
  EXPECT_THROW(from_records.set_normal_map(2, codes), InvalidInput);
  EXPECT_EQ(surface.normal_map_side(), 0);  // every refused call left the surface as it was
  surface.set_normal_map(2, codes);
  EXPECT_EQ(surface.normal_map_side(), 2);
  EXPECT_EQ(surface.normal_map_bytes(), codes.size() * 4);
  EXPECT_THROW(fit_normal_map(m.fine, m.coarse, 0, 0.1), InvalidInput);
}

class NormalMapFileTest : public test::ScratchDirTest {
protected:
  NormalMapFileTest() : ScratchDirTest("hb_normal_map_") {}
};

// The budgeted bake with --simplify of a flat-subdivided mesh: the simplified surface comes
// with a map of side 4 (16 times fewer triangles), meets the budget with the full mesh's
// direction error, and the map goes through the box file and its checks.
TEST_F(NormalMapFileTest, TheSimplifiedBakeKeepsTheFullShadingThroughItsFile) {
  const CoarseAndFine m = coarse_and_fine();
  const TriangleMesh& fine = m.fine;  // 5,120 triangles
  BakeRecipe recipe = default_recipe();
  recipe.pieces.kind = PiecesRecipe::Kind::none;
  recipe.budget.probes = 2000;
  recipe.budget.samplings = {{0.1f, 6}};
  recipe.budget.simplify = true;
  recipe.budget.simplify_above = 1000;
  recipe.budget.fastest_exact = false;  // the simplified surface's scene, not Embree's
  const BakeResult baked = bake(fine, recipe);
  const BudgetReport& rep = baked.scene.parts().budget;
  ASSERT_TRUE(rep.met) << rep.summary();
  EXPECT_LE(rep.surface_triangles, fine.triangle_count() / 8);
  EXPECT_EQ(rep.surface_map_side, 4u);
  EXPECT_LT(rep.direction_p99_deg, 0.1) << rep.summary();
  EXPECT_EQ(BudgetReport::parse(rep.serialize()).surface_map_side, 4u);
  ASSERT_TRUE(baked.scene.parts().surface != nullptr);
  EXPECT_EQ(baked.scene.parts().surface->normal_map_side(), 4);

  const std::string path = (dir_ / "mapped.hbox").string();
  save_box_file(baked.scene, path);
  const BoxScene loaded = load_box_file(path, LoadOptions{true});
  ASSERT_TRUE(loaded.parts().surface != nullptr);
  EXPECT_EQ(loaded.parts().surface->normal_map_side(), 4);
  for (const Segment& s : sample_probes(fine, 500)) {
    const Contact a = baked.scene.query(s, ForceLaw{}), b = loaded.query(s, ForceLaw{});
    ASSERT_EQ(a.contact, b.contact);
    ASSERT_EQ(a.force, b.force);
  }
  // The map is the file's last section: a flipped byte there is caught by its checksum.
  {
    std::fstream f(path, std::ios::in | std::ios::out | std::ios::binary);
    f.seekg(-1, std::ios::end);
    char c = 0;
    f.get(c);
    f.seekp(-1, std::ios::end);
    f.put(char(c ^ 0x5a));
  }
  try {
    load_box_file(path);
    FAIL() << "a corrupt normal map loaded";
  } catch (const InvalidInput& e) {
    EXPECT_NE(std::string(e.what()).find("normal map"), std::string::npos) << e.what();
  }
}

} // namespace
} // namespace hb
