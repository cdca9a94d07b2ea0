// The scene grid: cell states and box lists, the walk, its bytes, and the routed scene query.
#include "errors.h"
#include "evaluation/comparison.h"
#include "evaluation/probe_sampling.h"
#include "exact/exact_query.h"
#include "scene/bake.h"
#include "store/box_file.h"
#include "surface/scene_grid.h"
#include "surface/surface_cells.h"
#include "two_spheres.h"
#include <gtest/gtest.h>
#include <array>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <memory>
#include <random>
#include <unistd.h>

namespace hb {
namespace {

const ForceLaw kGridLaw{};

std::vector<std::vector<std::uint32_t>> lists_of(const test::TwoSpheres& two) {
  std::vector<std::vector<std::uint32_t>> lists(2);
  for (std::uint32_t t = 0; t < two.piece.size(); ++t) lists[two.piece[t]].push_back(t);
  return lists;
}

std::vector<std::uint32_t> boxes_at(const SceneGrid& grid, const Vec3& p) {
  const std::uint16_t code = grid.code_at(p);
  if (code < SceneGrid::kFirstSurface) return {};
  return {grid.boxes_begin(code), grid.boxes_end(code)};
}

TEST(SceneGridTest, CellsOfTwoSpheresAreInsideOutsideOrListTheirBox) {
  const test::TwoSpheres two = test::two_spheres(3.f);
  const SceneGrid grid = build_scene_grid(two.mesh, lists_of(two));
  ASSERT_FALSE(grid.empty());
  EXPECT_EQ(grid.code_at(Vec3(0.f, 0.f, 0.f)), SceneGrid::kInside);
  EXPECT_EQ(grid.code_at(Vec3(3.f, 0.1f, 0.f)), SceneGrid::kInside);
  EXPECT_EQ(grid.code_at(Vec3(1.5f, 0.f, 0.f)), SceneGrid::kOutside);
  EXPECT_EQ(grid.code_at(Vec3(100.f, 0.f, 0.f)), SceneGrid::kOutside);
  EXPECT_EQ(grid.code_at(Vec3(std::nanf(""), 0.f, 0.f)), SceneGrid::kOutside);
  EXPECT_EQ(boxes_at(grid, Vec3(-1.f, 0.f, 0.f)), std::vector<std::uint32_t>{0});
  EXPECT_EQ(boxes_at(grid, Vec3(4.f, 0.f, 0.f)), std::vector<std::uint32_t>{1});
  EXPECT_EQ(grid.max_box(), 1u);
}

TEST(SceneGridTest, EveryCellWithoutSurfaceHasTheStateOfItsPoints) {
  const test::TwoSpheres two = test::two_spheres(3.f);
  const SceneGrid grid = build_scene_grid(two.mesh, lists_of(two), SceneGridOptions{1.f / 40.f});
  const auto& d = grid.dims();
  std::size_t inside = 0, outside = 0, surface = 0;
  for (int z = 0; z < d[2]; ++z)
    for (int y = 0; y < d[1]; ++y)
      for (int x = 0; x < d[0]; ++x) {
        const Vec3 p = grid.origin() + grid.cell() * Vec3(float(x) + 0.5f, float(y) + 0.5f, float(z) + 0.5f);
        const std::uint16_t code = grid.code_at(p);
        if (code >= SceneGrid::kFirstSurface) {
          ++surface;
          continue;
        }
        // The mesh is a polyhedron inscribed in the unit spheres: a point clear of the surface
        // by half a cell is inside it when it is well inside a sphere.
        const float r = std::min(p.norm(), (p - Vec3(3.f, 0.f, 0.f)).norm());
        ASSERT_NE(code, SceneGrid::kUnknown) << x << " " << y << " " << z;
        EXPECT_EQ(code == SceneGrid::kInside, r < 1.f) << x << " " << y << " " << z << " r " << r;
        (code == SceneGrid::kInside ? inside : outside) += 1;
      }
  EXPECT_GT(inside, 0u);
  EXPECT_GT(outside, inside);
  EXPECT_GT(surface, 0u);
}


TEST(SurfaceCellsTest, EveryPointOfASurfaceCellIsInsideExactlyWhenItIsInsideTheMesh) {
  const test::TwoSpheres two = test::two_spheres(3.f);
  const BoxScene scene = test::refined_two_spheres(two);
  ASSERT_NE(scene.cells(), nullptr);
  const SurfaceCells& cells = *scene.cells();
  const SceneGrid& grid = *scene.parts().grid;
  ASSERT_GT(cells.cell_count(), 0u);
  // Points of surface cells, clear of the polyhedron (inscribed in the unit spheres, within
  // 0.01 of them at this subdivision) by 0.02: inside exactly when inside a sphere.
  std::mt19937 rng(7);
  std::uniform_real_distribution<float> u(-1.3f, 4.3f), v(-1.3f, 1.3f);
  std::size_t tested = 0, decided = 0, right = 0;
  for (int i = 0; i < 2000000 && tested < 20000; ++i) {
    const Vec3 p(u(rng), v(rng), v(rng));
    if (grid.code_at(p) < SceneGrid::kFirstSurface) continue;
    const float r = std::min(p.norm(), (p - Vec3(3.f, 0.f, 0.f)).norm());
    if (std::fabs(r - 1.f) < 0.02f) continue;
    ++tested;
    const std::uint16_t state = cells.state_at(p);
    if (state == SceneGrid::kUnknown) continue;
    ++decided;
    right += (state == SceneGrid::kInside) == (r < 1.f) ? 1 : 0;
  }
  ASSERT_GT(tested, 5000u);
  EXPECT_EQ(decided, tested);  // a closed mesh: every centre decided
  EXPECT_EQ(right, decided);
  // Beyond the surface cells it does not tell.
  EXPECT_EQ(cells.state_at(Vec3(0.f, 0.f, 0.f)), SceneGrid::kUnknown);
  EXPECT_EQ(cells.state_at(Vec3(std::nanf(""), 0.f, 0.f)), SceneGrid::kUnknown);
}

TEST(SurfaceCellsTest, ASurfaceCellListsEveryTriangleThatMeetsIt) {
  const test::TwoSpheres two = test::two_spheres(3.f);
  const BoxScene scene = test::refined_two_spheres(two);
  ASSERT_NE(scene.cells(), nullptr);
  const SurfaceCells& cells = *scene.cells();
  const SurfaceTriangles& surface = cells.surface();
  for (std::uint32_t t = 0; t < two.mesh.triangle_count(); ++t) {
    const Triangle& tri = two.mesh.triangles[t];
    // The centroid and points near the corners: each cell holding one lists the triangle.
    const Vec3 c = (two.mesh.positions[tri[0]] + two.mesh.positions[tri[1]] + two.mesh.positions[tri[2]]) / 3.f;
    for (int k = 0; k < 4; ++k) {
      const Vec3 p = k == 3 ? c : c + 0.98f * (two.mesh.positions[tri[k]] - c);
      const std::uint32_t index = cells.index_at(p);
      ASSERT_NE(index, SurfaceCells::kNone) << t;
      EXPECT_NE(std::find(cells.begin(index), cells.end(index), surface.slot(t)), cells.end(index)) << t << " " << k;
    }
  }
}

TEST(SurfaceCellsTest, FirstCrossingAlongFindsTheNearestCrossingOfAllTrianglesWithAndWithoutSubcells) {
  // A coarse grid (cells listing dozens of triangles: cut into sub-cells) and a fine one
  // (none cut): the crossing of the clearance walk, with or without sub-cells, is the
  // nearest crossing among all the surface's triangles, on segments through the surface,
  // inside, outside and beyond the grid.
  const test::TwoSpheres two = test::two_spheres(3.f);
  const auto surface = std::make_shared<const SurfaceTriangles>(two.mesh);
  std::vector<std::uint32_t> all(surface->size());
  for (std::uint32_t t = 0; t < all.size(); ++t) all[t] = t;
  for (const float cell : {1.f / 12.f, 1.f / 100.f}) {
    const SceneGrid grid = build_scene_grid(two.mesh, lists_of(two), SceneGridOptions{cell});
    const SurfaceCells cells(grid, surface);
    if (cell > 0.05f) {
      EXPECT_GT(cells.subcells().crowded_count(), 0u);
    } else {
      EXPECT_EQ(cells.subcells().crowded_count(), 0u);
    }
    std::mt19937 rng(13);
    std::uniform_real_distribution<float> ux(-1.3f, 4.3f), uyz(-1.3f, 1.3f), far(-3.f, 6.f), dir(-1.f, 1.f);
    std::size_t crossed = 0;
    for (int k = 0; k < 4000; ++k) {
      const Vec3 a(ux(rng), uyz(rng), uyz(rng));
      const Vec3 b = k % 3 == 0 ? Vec3(far(rng), far(rng), far(rng)) : Vec3(a + 0.6f * Vec3(dir(rng), dir(rng), dir(rng)));
      const float o[3] = {a.x(), a.y(), a.z()}, d[3] = {b.x() - a.x(), b.y() - a.y(), b.z() - a.z()};
      float want_s = 0.f, got_s = 0.f;
      bool want_front = false, got_front = false;
      std::uint32_t want_id = kNoTriangle, got_id = kNoTriangle;
      const bool want = surface->first_crossing(all.data(), all.size(), o, d, 0.f, 1.f, want_s, want_front, want_id);
      const bool got = cells.first_crossing_along(a, b, 1.f, got_s, got_front, got_id);
      ASSERT_EQ(got, want) << cell << " " << k;
      if (!want) continue;
      ++crossed;
      EXPECT_EQ(got_s, want_s) << cell << " " << k;
      EXPECT_EQ(got_front, want_front) << cell << " " << k;
    }
    EXPECT_GT(crossed, 1000u) << cell;
  }
}

TEST(SurfaceCellsTest, ASegmentThatStaysOffACellsSlabIsNotTestedThereAndOneThroughItIs) {
  // The cell holding a point of the sphere (normal +x there): a segment three cells out along
  // the normal, moving sideways, passes its triangles by; one through the point does not; an
  // index beyond the cells is never skipped.
  const test::TwoSpheres two = test::two_spheres(3.f);
  const auto surface = std::make_shared<const SurfaceTriangles>(two.mesh);
  const SceneGrid grid = build_scene_grid(two.mesh, lists_of(two), SceneGridOptions{1.f / 40.f});
  const SurfaceCells cells(grid, surface);
  const Vec3 p(-1.f, 0.f, 0.f), n(-1.f, 0.f, 0.f);
  const std::uint32_t index = cells.index_at(p);
  ASSERT_NE(index, SurfaceCells::kNone);
  const float cell = grid.cell();
  const Vec3 off = p + 3.f * cell * n;
  const float o1[3] = {off.x(), off.y(), off.z()}, d1[3] = {0.f, cell, 0.f};
  EXPECT_FALSE(cells.slab_may_cross(index, o1, d1, 0.f, 1.f));
  const Vec3 from = p + 2.f * cell * n;
  const float o2[3] = {from.x(), from.y(), from.z()}, d2[3] = {4.f * cell, 0.f, 0.f};
  EXPECT_TRUE(cells.slab_may_cross(index, o2, d2, 0.f, 1.f));
  EXPECT_TRUE(cells.slab_may_cross(std::uint32_t(cells.cell_count()), o1, d1, 0.f, 1.f));
}

TEST(SurfaceCellsTest, WalksSideBySideFindTheSameCrossingsAsOneByOne) {
  // first_crossings_along (several walks in flight, each stopping where it waits for memory)
  // against first_crossing_along one segment at a time, bit for bit: on a grid with crowded
  // cells cut into sub-cells and on one without, segments through the surface, inside,
  // outside, beyond the grid and degenerate, in a count that is no multiple of the walks in
  // flight.
  const test::TwoSpheres two = test::two_spheres(3.f);
  const auto surface = std::make_shared<const SurfaceTriangles>(two.mesh);
  for (const float cell : {1.f / 12.f, 1.f / 100.f}) {
    const SceneGrid grid = build_scene_grid(two.mesh, lists_of(two), SceneGridOptions{cell});
    const SurfaceCells cells(grid, surface);
    std::mt19937 rng(29);
    std::uniform_real_distribution<float> ux(-1.3f, 4.3f), uyz(-1.3f, 1.3f), far(-3.f, 6.f), dir(-1.f, 1.f);
    std::vector<Vec3> a, b;
    for (int k = 0; k < 3001; ++k) {
      a.emplace_back(ux(rng), uyz(rng), uyz(rng));
      b.push_back(k % 3 == 0 ? Vec3(far(rng), far(rng), far(rng)) : Vec3(a.back() + 0.6f * Vec3(dir(rng), dir(rng), dir(rng))));
    }
    a.emplace_back(0.5f, 0.2f, 0.1f);  // degenerate: handle and tip the same point
    b.push_back(a.back());
    a.emplace_back(-50.f, -50.f, -50.f);  // far beyond the grid
    b.emplace_back(-40.f, -50.f, -50.f);
    std::vector<SurfaceCells::Crossing> many(a.size());
    cells.first_crossings_along(a.data(), b.data(), a.size(), many.data());
    std::size_t found = 0;
    for (std::size_t k = 0; k < a.size(); ++k) {
      float s = 0.f;
      bool front = false;
      std::uint32_t id = kNoTriangle;
      const bool one = cells.first_crossing_along(a[k], b[k], 1.f, s, front, id);
      ASSERT_EQ(many[k].triangle != kNoTriangle, one) << cell << " " << k;
      if (!one) continue;
      ++found;
      EXPECT_EQ(std::memcmp(&many[k].s, &s, sizeof s), 0) << cell << " " << k;
      EXPECT_EQ(many[k].front, front) << cell << " " << k;
      EXPECT_EQ(many[k].triangle, id) << cell << " " << k;
    }
    EXPECT_GT(found, 500u) << cell;
  }
}

TEST(SceneGridTest, WalkVisitsTheCrossedCellsInOrder) {
  const test::TwoSpheres two = test::two_spheres(3.f);
  const SceneGrid grid = build_scene_grid(two.mesh, lists_of(two));
  std::mt19937 rng(5);
  // Ends inside the grid (the spheres' bounds plus a cell), and some beyond it for b.
  std::uniform_real_distribution<float> ux(-0.95f, 3.95f), uyz(-0.95f, 0.95f), far(-3.f, 6.f);
  for (int k = 0; k < 200; ++k) {
    const Vec3 a(ux(rng), uyz(rng), uyz(rng));
    const Vec3 b = k % 2 ? Vec3(ux(rng), uyz(rng), uyz(rng)) : Vec3(far(rng), far(rng), far(rng));
    std::vector<std::pair<std::uint16_t, float>> cells;
    grid.walk(a, b, [&](std::uint16_t code, float s) {
      cells.emplace_back(code, s);
      return true;
    });
    ASSERT_FALSE(cells.empty());
    EXPECT_EQ(cells.front().second, 0.f);  // a is inside the grid
    for (std::size_t i = 0; i < cells.size(); ++i) {
      const float s_end = i + 1 < cells.size() ? cells[i + 1].second : 1.f;
      ASSERT_LE(cells[i].second, s_end);
      if (s_end - cells[i].second < 1e-4f || i + 1 == cells.size()) continue;  // a corner grazed; the last may leave the grid
      EXPECT_EQ(grid.code_at(a + 0.5f * (cells[i].second + s_end) * (b - a)), cells[i].first) << k << " " << i;
    }
  }
  // Stops when told to, and never visits beyond the grid.
  int visited = 0;
  grid.walk(Vec3(-2.f, 0.f, 0.f), Vec3(5.f, 0.f, 0.f), [&](std::uint16_t, float) { return ++visited < 3; });
  EXPECT_EQ(visited, 3);
  visited = 0;
  grid.walk(Vec3(100.f, 0.f, 0.f), Vec3(200.f, 0.f, 0.f), [&](std::uint16_t, float) { return ++visited > 0; });
  EXPECT_EQ(visited, 0);
}

TEST(SceneGridTest, ClearanceIsTheChessboardDistanceToSurface) {
  const test::TwoSpheres two = test::two_spheres(3.f);
  const SceneGrid grid = build_scene_grid(two.mesh, lists_of(two), SceneGridOptions{1.f / 24.f});
  const auto& d = grid.dims();
  const auto index = [&](int x, int y, int z) { return (std::size_t(z) * d[1] + std::size_t(y)) * d[0] + std::size_t(x); };
  std::vector<std::array<int, 3>> surface;
  for (int z = 0; z < d[2]; ++z)
    for (int y = 0; y < d[1]; ++y)
      for (int x = 0; x < d[0]; ++x)
        if (grid.codes()[index(x, y, z)] >= SceneGrid::kFirstSurface) surface.push_back({x, y, z});
  ASSERT_FALSE(surface.empty());
  const std::vector<std::uint8_t> clearance = grid.clearance();
  for (int z = 0; z < d[2]; ++z)
    for (int y = 0; y < d[1]; ++y)
      for (int x = 0; x < d[0]; ++x) {
        int best = 255;
        for (const auto& c : surface)
          best = std::min(best, std::max({std::abs(c[0] - x), std::abs(c[1] - y), std::abs(c[2] - z)}));
        ASSERT_EQ(int(clearance[index(x, y, z)]), best) << x << " " << y << " " << z;
      }
}

TEST(SceneGridTest, SurfaceWalkVisitsTheSurfaceCellsOfTheFullWalk) {
  const test::TwoSpheres two = test::two_spheres(3.f);
  const SceneGrid grid = build_scene_grid(two.mesh, lists_of(two), SceneGridOptions{1.f / 100.f});
  std::mt19937 rng(9);
  std::uniform_real_distribution<float> ux(-1.2f, 4.2f), uyz(-1.2f, 1.2f), far(-3.f, 6.f);
  std::size_t surface_cells = 0;
  for (int k = 0; k < 2000; ++k) {
    const Vec3 a(ux(rng), uyz(rng), uyz(rng));
    const Vec3 b = k % 2 ? Vec3(ux(rng), uyz(rng), uyz(rng)) : Vec3(far(rng), far(rng), far(rng));
    std::vector<std::pair<std::uint16_t, float>> full, jumped;
    grid.walk(a, b, [&](std::uint16_t code, float s) {
      if (code >= SceneGrid::kFirstSurface) full.emplace_back(code, s);
      return true;
    });
    grid.walk_surface(a, b, [&](std::uint16_t code, float s) {
      jumped.emplace_back(code, s);
      return true;
    });
    ASSERT_EQ(jumped.size(), full.size()) << k;
    for (std::size_t i = 0; i < full.size(); ++i) {
      EXPECT_EQ(jumped[i].first, full[i].first) << k << " " << i;
      EXPECT_NEAR(jumped[i].second, full[i].second, 1e-5f) << k << " " << i;
    }
    surface_cells += full.size();
  }
  EXPECT_GT(surface_cells, 1000u);
}

TEST(SceneGridTest, BytesRoundTripAndBadBytesThrow) {
  const test::TwoSpheres two = test::two_spheres(3.f);
  const SceneGrid grid = build_scene_grid(two.mesh, lists_of(two));
  const std::vector<std::uint8_t> bytes = grid.serialize();
  const SceneGrid back = SceneGrid::deserialize(bytes.data(), bytes.size());
  EXPECT_EQ(back.codes(), grid.codes());
  EXPECT_EQ(back.dims(), grid.dims());
  EXPECT_EQ(back.cell(), grid.cell());
  EXPECT_EQ(back.list_count(), grid.list_count());
  EXPECT_THROW(SceneGrid::deserialize(bytes.data(), bytes.size() - 1), InvalidInput);
  EXPECT_THROW(SceneGrid::deserialize(bytes.data(), 10), InvalidInput);
  std::vector<std::uint8_t> bad = bytes;
  bad[0] ^= 1;  // magic
  EXPECT_THROW(SceneGrid::deserialize(bad.data(), bad.size()), InvalidInput);
  bad = bytes;
  const std::size_t first_code = 11 * 4;  // after the header: 11 four-byte fields
  bad[first_code] = 0xff, bad[first_code + 1] = 0xff;  // a code naming no list
  EXPECT_THROW(SceneGrid::deserialize(bad.data(), bad.size()), InvalidInput);
  EXPECT_THROW(build_scene_grid(two.mesh, {}), InvalidInput);
  EXPECT_THROW(build_scene_grid(two.mesh, {{0u, 999999u}}), InvalidInput);
  EXPECT_THROW(build_scene_grid(two.mesh, lists_of(two), SceneGridOptions{0.f}), InvalidInput);
}

TEST(BoxSceneGridTest, RoutedQueriesAskOneBoxAndAgreeWithExactAsWellAsAllBoxes) {
  const test::TwoSpheres two = test::two_spheres(2.5f);
  const BoxScene scene = test::refined_two_spheres(two);
  ASSERT_NE(scene.parts().grid, nullptr);
  SceneParts no_grid = scene.parts();
  no_grid.grid.reset();
  const BoxScene plain(std::move(no_grid));
  ASSERT_EQ(plain.parts().grid, nullptr);
  const ExactQuery exact(two.mesh);
  const auto probes = sample_probes(two.mesh, 3000, ProbeOptions{});
  const float diagonal = two.mesh.bounds().diagonal();
  const ComparisonStats routed = compare_queries(scene, exact, probes, kGridLaw, diagonal);
  const ComparisonStats all = compare_queries(plain, exact, probes, kGridLaw, diagonal);
  EXPECT_GE(routed.contact_agreement, all.contact_agreement - 0.002);
  EXPECT_GT(routed.contact_agreement, 0.99);
  EXPECT_LT(routed.force_error_median, 1e-3);
  double asked_routed = 0, asked_all = 0;
  for (const Segment& s : probes) {
    asked_routed += double(scene.box_queries(s, kGridLaw));
    asked_all += double(plain.box_queries(s, kGridLaw));
  }
  EXPECT_LT(asked_routed / double(probes.size()), 1.2);
  EXPECT_LT(asked_routed, asked_all);
  // A handle inside a sphere: no contact, no box query.
  const Segment inside{Vec3(0.f, 0.f, 0.f), Vec3(-1.5f, 0.f, 0.f)};
  EXPECT_FALSE(scene.query(inside, kGridLaw).contact);
  EXPECT_EQ(scene.box_queries(inside, kGridLaw), 0u);
  // query_many answers as query() one by one.
  std::vector<Contact> many(probes.size());
  scene.query_many(probes.data(), probes.size(), kGridLaw, many.data());
  for (std::size_t i = 0; i < probes.size(); ++i) {
    const Contact one = scene.query(probes[i], kGridLaw);
    ASSERT_EQ(one.contact, many[i].contact) << i;
    EXPECT_EQ(one.depth, many[i].depth) << i;
  }
  // The compressed scene keeps the grid.
  EXPECT_EQ(compressed(scene, CodecOptions{}).grid, scene.parts().grid);
}

TEST(BoxSceneGridTest, TheGridSurvivesTheBoxFileAndACorruptGridFailsToLoad) {
  namespace fs = std::filesystem;
  const fs::path dir = fs::temp_directory_path() / ("hb_scene_grid_test_" + std::to_string(::getpid()));
  fs::create_directories(dir);
  const test::TwoSpheres two = test::two_spheres(3.f);
  BakeOptions options;
  options.params = {8, 4};
  const BoxScene scene = bake_scene(two.mesh, two.piece, options, {});
  const std::string path = (dir / "two.hbox").string();
  save_box_file(scene, path);
  const BoxScene loaded = load_box_file(path);
  ASSERT_NE(loaded.parts().grid, nullptr);
  EXPECT_EQ(loaded.parts().grid->codes(), scene.parts().grid->codes());
  const auto probes = sample_probes(two.mesh, 500, ProbeOptions{});
  for (const Segment& s : probes) {
    const Contact a = scene.query(s, kGridLaw), b = loaded.query(s, kGridLaw);
    ASSERT_EQ(a.contact, b.contact);
    EXPECT_EQ(a.depth, b.depth);
  }
  // Flip a byte in the grid, the last block of the file.
  std::vector<char> bytes;
  {
    std::ifstream in(path, std::ios::binary);
    bytes.assign(std::istreambuf_iterator<char>(in), {});
  }
  bytes[bytes.size() - 10] ^= 0x5a;
  const std::string bad = (dir / "bad.hbox").string();
  std::ofstream(bad, std::ios::binary).write(bytes.data(), std::streamsize(bytes.size()));
  try {
    load_box_file(bad);
    ADD_FAILURE() << "no error";
  } catch (const InvalidInput& e) {
    EXPECT_NE(std::string(e.what()).find("scene grid checksum"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find(bad), std::string::npos) << e.what();
  }
  fs::remove_all(dir);
}

} // namespace
} // namespace hb
