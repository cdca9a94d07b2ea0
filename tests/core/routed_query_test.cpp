// The cheap routed path of a scene query: the refined box query from triangle ids alone (no
// samples decoded) and the grid's bricked cell words.
#include "evaluation/comparison.h"
#include "evaluation/probe_sampling.h"
#include "exact/exact_query.h"
#include "scene/bake.h"
#include "surface/scene_grid.h"
#include "surface/surface_cells.h"
#include "two_spheres.h"
#include <gtest/gtest.h>

namespace hb {
namespace {

const ForceLaw kRoutedLaw{};

// The two spheres baked refined at m 12, n 6: one box (pieces = false) or one a sphere.
BoxScene refined_scene(const test::TwoSpheres& two, bool pieces = true) {
  BakeOptions o;
  o.params = {12, 6};
  o.refine = true;
  return bake_scene(two.mesh, pieces ? two.piece : std::vector<std::uint32_t>{}, o, SourceInfo{});
}

TEST(RoutedQueryTest, IdsOnlyRefinedQueryEqualsTheConfirmedRefinedQuery) {
  const test::TwoSpheres two = test::two_spheres(3.f);
  const BoxScene scene = refined_scene(two, false);
  ASSERT_EQ(scene.parts().boxes.size(), 1u);
  const HapticBox& box = scene.parts().boxes[0];
  ASSERT_TRUE(box.refines());
  const std::vector<Segment> probes = sample_probes(two.mesh, 4000, ProbeOptions{});
  std::size_t confirmed = 0, same = 0, flags = 0;
  for (const Segment& s : probes) {
    Contact full, ids;
    float along_full = 0.f, along_ids = 0.f;
    bool refined = false;
    std::uint32_t t_full = kNoTriangle, t_ids = kNoTriangle;
    const bool hit_full = box.query_into(s, kRoutedLaw, full, along_full, Refine::all, &refined, &t_full) && refined;
    const bool hit_ids = box.query_refined(s, kRoutedLaw, ids, along_ids, &t_ids);
    flags += hit_full == hit_ids ? 1 : 0;
    if (!hit_full) continue;
    ++confirmed;
    // The same triangle gives the same bits (write_contact is shared).
    if (hit_ids && t_ids == t_full && ids.depth == full.depth && ids.force == full.force && along_ids == along_full)
      ++same;
  }
  EXPECT_GT(confirmed, probes.size() / 4);
  // Without a blend to agree with, only a candidate the blend's tolerance rejected may differ.
  EXPECT_GE(double(same), 0.995 * double(confirmed)) << same << " of " << confirmed;
  EXPECT_GE(double(flags), 0.995 * double(probes.size())) << flags << " of " << probes.size();
  // A box that does not refine has no ids-only answer.
  Contact c;
  float along = 0.f;
  EXPECT_FALSE(box.without_refinement().query_refined(probes[0], kRoutedLaw, c, along));
  EXPECT_FALSE(c.contact);
}

TEST(RoutedQueryTest, HandlesInSurfaceCellsShownOutsideAreRoutedWithTheUnroutedAnswers) {
  const test::TwoSpheres two = test::two_spheres(2.5f);
  const BoxScene scene = refined_scene(two);
  ASSERT_NE(scene.parts().grid, nullptr);
  SceneParts no_grid = scene.parts();
  no_grid.grid.reset();
  const BoxScene plain(std::move(no_grid));
  const SceneGrid& grid = *scene.parts().grid;
  // Handles in surface cells, a little outside and inside the spheres, segments along the
  // normal's opposite (contacts ahead) and along it (no contact).
  std::size_t probes = 0, same = 0, routed = 0;
  for (std::size_t t = 0; t < two.mesh.triangle_count(); t += 3) {
    const Triangle& tri = two.mesh.triangles[t];
    const Vec3 &p0 = two.mesh.positions[tri[0]], &p1 = two.mesh.positions[tri[1]], &p2 = two.mesh.positions[tri[2]];
    const Vec3 c = (p0 + p1 + p2) / 3.f;
    const Vec3 n = (p1 - p0).cross(p2 - p0).normalized();  // outward on the spheres
    for (float off : {0.3f, 0.6f, -0.3f}) {
      const Vec3 handle = c + (off * grid.cell()) * n;
      if (grid.code_at(handle) < SceneGrid::kFirstSurface) continue;
      for (float dir : {-1.f, 1.f}) {
        const Segment s{handle, handle + (dir * 0.1f) * n};
        const Contact a = scene.query(s, kRoutedLaw), b = plain.query(s, kRoutedLaw);
        ++probes;
        same += a.contact == b.contact ? 1 : 0;
        routed += scene.box_queries(s, kRoutedLaw) < plain.box_queries(s, kRoutedLaw) ? 1 : 0;
      }
    }
  }
  ASSERT_GT(probes, 200u);
  EXPECT_GE(double(same), 0.99 * double(probes)) << same << " of " << probes;
  EXPECT_GT(routed, probes / 4) << routed << " of " << probes;
}

TEST(RoutedQueryTest, HandlesInSurfaceCellsGetExactsAnswerFromAtMostOneBoxQuery) {
  const test::TwoSpheres two = test::two_spheres(2.5f);
  const BoxScene scene = refined_scene(two);
  ASSERT_NE(scene.cells(), nullptr);
  const SceneGrid& grid = *scene.parts().grid;
  const ExactQuery exact(two.mesh);
  // Handles in surface cells just outside and inside the spheres, segments against the
  // normal (a contact ahead from outside) and along it.
  std::size_t probes = 0, agree = 0, inside = 0, inside_free = 0;
  double asked = 0;
  for (std::size_t t = 0; t < two.mesh.triangle_count(); t += 2) {
    const Triangle& tri = two.mesh.triangles[t];
    const Vec3 &p0 = two.mesh.positions[tri[0]], &p1 = two.mesh.positions[tri[1]], &p2 = two.mesh.positions[tri[2]];
    const Vec3 c = (p0 + p1 + p2) / 3.f;
    const Vec3 n = (p1 - p0).cross(p2 - p0).normalized();
    for (float off : {0.15f, 0.45f, -0.15f, -0.45f}) {
      const Vec3 handle = c + (off * grid.cell()) * n;
      if (grid.code_at(handle) < SceneGrid::kFirstSurface) continue;
      for (float dir : {-1.f, 1.f}) {
        const Segment s{handle, handle + (dir * 0.1f) * n};
        const Contact want = exact.query(s, kRoutedLaw);
        ++probes;
        agree += scene.query(s, kRoutedLaw).contact == want.contact ? 1 : 0;
        const std::size_t q = scene.box_queries(s, kRoutedLaw);
        asked += double(q);
        if (off < 0.f) {
          ++inside;
          inside_free += q == 0 ? 1 : 0;
        }
      }
    }
  }
  ASSERT_GT(probes, 400u);
  EXPECT_EQ(agree, probes);
  // A handle inside asks no box; one outside asks one in the common case.
  EXPECT_EQ(inside_free, inside);
  EXPECT_LT(asked / double(probes), 0.75);
}

TEST(RoutedQueryTest, AContactBehindANearerSheetYieldsToTheFirstCrossing) {
  // Sphere B (centre x = 1) in front of sphere A (x = 0) for a probe coming from +x. The
  // grid claims box 0 (baked from A alone) holds every triangle, so it names box 0 in B's
  // cells: box 0 answers A's surface, behind B's. The first crossing (B) must win.
  const test::TwoSpheres two = test::two_spheres(1.f);
  const BoxScene baked = refined_scene(two);
  std::vector<std::vector<std::uint32_t>> lists(2);
  for (std::uint32_t t = 0; t < two.piece.size(); ++t)
    if (two.piece[t] == 1) lists[1].push_back(t);  // lists[0] empty: all triangles
  auto grid = std::make_shared<const SceneGrid>(build_scene_grid(two.mesh, lists, SceneGridOptions{1.f / 40.f}));
  SceneParts parts(baked.parts().boxes, SourceInfo{}, {}, grid);
  parts.route = SceneRoute::boxes;
  const BoxScene scene(std::move(parts));
  const ExactQuery exact(two.mesh);
  std::size_t probes = 0, right = 0;
  for (float y = -0.3f; y <= 0.3f; y += 0.05f)
    for (float z = -0.3f; z <= 0.3f; z += 0.05f) {
      const Segment s{Vec3(2.2f, y, z), Vec3(0.4f, y, z)};
      if (grid->code_at(s.start) != SceneGrid::kOutside) continue;
      const std::uint16_t code = grid->code_at(Vec3(2.f - 0.5f * (y * y + z * z), y, z));
      ASSERT_GE(code, SceneGrid::kFirstSurface);
      ASSERT_EQ(*grid->boxes_begin(code), 0u);
      const Contact want = exact.query(s, kRoutedLaw);
      ASSERT_TRUE(want.contact);
      ++probes;
      const Contact got = scene.query(s, kRoutedLaw);
      right += got.contact && (got.point - want.point).norm() < 1e-3f ? 1 : 0;
    }
  ASSERT_GT(probes, 100u);
  EXPECT_EQ(right, probes);
}

TEST(RoutedQueryTest, TheCellsRouteGivesExactsContactsWithoutAskingABox) {
  // Two spheres apart, one piece each, random probes and probes from just inside and outside the
  // surface: the cells route answers from the surface cells' triangles alone, exact's
  // contacts and forces, and the boxes' route's contact decisions.
  const test::TwoSpheres two = test::two_spheres(2.5f);
  const BoxScene boxes = refined_scene(two);
  ASSERT_NE(boxes.cells(), nullptr);
  const BoxScene cells = with_route(boxes, SceneRoute::cells);
  EXPECT_EQ(cells.route(), SceneRoute::cells);
  const ExactQuery exact(two.mesh);
  std::vector<Segment> probes = sample_probes(two.mesh, 3000, ProbeOptions{});
  const float cell = boxes.parts().grid->cell();
  for (std::size_t t = 0; t < two.mesh.triangle_count(); t += 3) {
    const Triangle& tri = two.mesh.triangles[t];
    const Vec3 &p0 = two.mesh.positions[tri[0]], &p1 = two.mesh.positions[tri[1]], &p2 = two.mesh.positions[tri[2]];
    const Vec3 c = (p0 + p1 + p2) / 3.f, n = (p1 - p0).cross(p2 - p0).normalized();
    for (float off : {0.3f, -0.3f, 2.5f}) probes.push_back({c + off * cell * n, c - 0.1f * n});
  }
  std::size_t contacts = 0, same_as_exact = 0, same_as_boxes = 0, asked = 0;
  for (const Segment& s : probes) {
    const Contact e = exact.query(s, kRoutedLaw), c = cells.query(s, kRoutedLaw), b = boxes.query(s, kRoutedLaw);
    contacts += e.contact ? 1 : 0;
    same_as_boxes += c.contact == b.contact ? 1 : 0;
    asked += cells.box_queries(s, kRoutedLaw);
    if (c.contact != e.contact) continue;
    if (!e.contact || ((c.point - e.point).norm() < 1e-4f && std::fabs(c.depth - e.depth) < 1e-4f &&
                       (c.force - e.force).norm() <= 1e-3f * e.force.norm() + 1e-6f &&
                       (c.normal - e.normal).norm() < 1e-3f))
      ++same_as_exact;
  }
  ASSERT_GT(contacts, probes.size() / 3);
  EXPECT_EQ(same_as_exact, probes.size());
  EXPECT_EQ(same_as_boxes, probes.size());
  // Handles the cells cannot place (an undecided cell centre) take the boxes' path: rare.
  EXPECT_LT(double(asked), 0.01 * double(probes.size()));
}

TEST(RoutedQueryTest, BrickedCellWordsGiveTheCodeOfEveryCell) {
  const test::TwoSpheres two = test::two_spheres(3.f);
  std::vector<std::vector<std::uint32_t>> lists(2);
  for (std::uint32_t t = 0; t < two.piece.size(); ++t) lists[two.piece[t]].push_back(t);
  // An odd cell size: dimensions that are not multiples of the 4-cell bricks.
  const SceneGrid grid = build_scene_grid(two.mesh, lists, SceneGridOptions{1.f / 37.f});
  const auto& d = grid.dims();
  ASSERT_TRUE(d[0] % 4 != 0 || d[1] % 4 != 0 || d[2] % 4 != 0);
  std::size_t index = 0, surface = 0;
  for (int z = 0; z < d[2]; ++z)
    for (int y = 0; y < d[1]; ++y)
      for (int x = 0; x < d[0]; ++x, ++index) {
        const Vec3 centre = grid.origin() + grid.cell() * Vec3(float(x) + 0.5f, float(y) + 0.5f, float(z) + 0.5f);
        ASSERT_EQ(grid.code_at(centre), grid.codes()[index]) << x << " " << y << " " << z;
        surface += grid.codes()[index] >= SceneGrid::kFirstSurface ? 1 : 0;
      }
  EXPECT_GT(surface, 0u);
  EXPECT_EQ(grid.query_bytes() % 256, 0u);
}

} // namespace
} // namespace hb

namespace hb {
namespace {

// Scenes of the same grid and surface share one set of surface cells (a budgeted bake composes
// the same scene several times; at 13M triangles each build took seconds), while the cells
// of another grid and surface are their own.
TEST(RoutedQueryTest, ScenesOfOneGridAndSurfaceShareTheirSurfaceCells) {
  const test::TwoSpheres two = test::two_spheres(2.5f);
  const BoxScene scene = refined_scene(two);
  ASSERT_NE(scene.cells(), nullptr);
  const BoxScene lean = BoxScene(without_triangle_ids(scene));
  EXPECT_EQ(lean.cells().get(), scene.cells().get());
  const BoxScene other = refined_scene(two);  // its own grid and surface
  ASSERT_NE(other.cells(), nullptr);
  EXPECT_NE(other.cells().get(), scene.cells().get());
  for (const Segment& s : sample_probes(two.mesh, 500, ProbeOptions{})) {
    const Contact a = scene.query(s, kRoutedLaw), b = lean.query(s, kRoutedLaw);
    ASSERT_EQ(a.contact, b.contact);
    ASSERT_EQ(a.force, b.force);
  }
}

} // namespace
} // namespace hb
