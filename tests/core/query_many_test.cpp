// Batched queries (query_many) give the same answers as query(), bit for bit.
#include "evaluation/probe_sampling.h"
#include "scene/bake.h"
#include "scene/box_scene.h"
#include "mesh/generators.h"
#include "grazing_probes.h"
#include "two_spheres.h"
#include <gtest/gtest.h>
#include <cstring>
#include <limits>
#include <random>

namespace hb {
namespace {

const ForceLaw kManyLaw{1000.f, 1.f};

// Bitwise equality of every field (so -0 vs 0 or a last-bit difference fails).
bool same_bits(const Contact& a, const Contact& b) {
  const auto eq = [](const Vec3& x, const Vec3& y) { return std::memcmp(x.data(), y.data(), 3 * sizeof(float)) == 0; };
  return a.contact == b.contact && std::memcmp(&a.depth, &b.depth, sizeof(float)) == 0 && eq(a.point, b.point) &&
         eq(a.normal, b.normal) && eq(a.force, b.force);
}

// Probes of the usual distribution, grazing ones, plus segments that miss the box, a
// degenerate one and reversed ones (handle inside), in a count that is not a multiple of any
// group size.
std::vector<Segment> mixed_probes(const TriangleMesh& mesh) {
  std::vector<Segment> probes = sample_probes(mesh, 997);
  // Segments 55-89 degrees from the normal (the lanes hand them to the scalar query).
  const float diagonal = mesh.bounds().diagonal();
  const std::vector<Segment> grazing = test::grazing_segments(mesh, 301, 5, 55.f, 89.f, 0.06f * diagonal, 0.002f * diagonal);
  probes.insert(probes.end(), grazing.begin(), grazing.end());
  std::mt19937 rng(3);
  std::uniform_real_distribution<float> u(-3.f, 3.f);
  for (int i = 0; i < 40; ++i) probes.push_back({Vec3(u(rng), u(rng), u(rng)), Vec3(u(rng), u(rng), u(rng))});
  probes.push_back({Vec3(0.2f, 0.1f, 2.f), Vec3(0.2f, 0.1f, 2.f)});
  for (int i = 0; i < 20; ++i) probes.push_back({probes[std::size_t(i)].end, probes[std::size_t(i)].start});
  return probes;
}

std::size_t expect_same_as_single(const ContactQuery& q, const std::vector<Segment>& probes) {
  std::vector<Contact> many(probes.size());
  q.query_many(probes.data(), probes.size(), kManyLaw, many.data());
  std::size_t contacts = 0;
  for (std::size_t i = 0; i < probes.size(); ++i) {
    const Contact one = q.query(probes[i], kManyLaw);
    EXPECT_TRUE(same_bits(one, many[i])) << "probe " << i;
    contacts += one.contact ? 1 : 0;
  }
  return contacts;
}

TriangleMesh bumpy_sphere(int subdivisions) {
  BumpySphereOptions bumpy;
  bumpy.subdivisions = subdivisions;
  return make_bumpy_sphere(bumpy);
}

HapticBox raw_box(const TriangleMesh& mesh, BoxParams params) {
  BakeOptions options;
  options.params = params;
  return bake_box(mesh, {}, options);
}

TEST(QueryManyTest, RawBoxGivesTheSameAnswersAsSingleQueries) {
  const TriangleMesh mesh = bumpy_sphere(4);
  const HapticBox box = raw_box(mesh, {12, 8});
  const std::vector<Segment> probes = mixed_probes(mesh);
  EXPECT_GT(expect_same_as_single(box, probes), probes.size() / 2);
  // Sub-ranges and an empty batch.
  std::vector<Contact> out(5);
  box.query_many(probes.data() + 3, 5, kManyLaw, out.data());
  for (std::size_t i = 0; i < 5; ++i) EXPECT_TRUE(same_bits(out[i], box.query(probes[3 + i], kManyLaw)));
  box.query_many(probes.data(), 0, kManyLaw, out.data());
}

// The batched path of raw boxes runs 4 or 8 queries in SIMD lanes, compiled for several
// instruction sets (the best the CPU has is used); each level the CPU runs must give
// query()'s answers, also for segments along the box's faces and through its corners.
TEST(QueryManyTest, EveryInstructionSetLevelGivesTheSameAnswersAsSingleQueries) {
  const TriangleMesh mesh = bumpy_sphere(3);
  const HapticBox box = raw_box(mesh, {9, 5});
  std::vector<Segment> probes = mixed_probes(mesh);
  // Segments along the box's axes and through its edges and corners (parallel slabs, ties).
  const Obb& obb = box.obb();
  for (int a = 0; a < 3; ++a)
    for (float offset : {0.f, 0.5f, 1.f, 1.2f}) {
      Vec3 side = Vec3::Zero();
      side[(a + 1) % 3] = offset * obb.half[(a + 1) % 3];
      Vec3 along = Vec3::Zero();
      along[a] = 2.f * obb.half[a];
      const Vec3 start = obb.to_world(side - along), end = obb.to_world(side);
      probes.push_back({start, end});
      probes.push_back({obb.to_world(obb.half * -1.5f), obb.to_world(obb.half * 0.1f)});
    }
  // Non-finite input: no contact from either path.
  const float nan = std::numeric_limits<float>::quiet_NaN(), inf = std::numeric_limits<float>::infinity();
  probes.push_back({Vec3(nan, 0.f, 0.f), Vec3(0.f, 0.f, 0.f)});
  probes.push_back({Vec3(0.f, 0.f, 2.f), Vec3(0.f, inf, 0.f)});
  probes.push_back({Vec3(-inf, 0.f, 0.f), Vec3(inf, 0.f, 0.f)});
  for (std::size_t i = probes.size() - 3; i < probes.size(); ++i) EXPECT_FALSE(box.query(probes[i], kManyLaw).contact);
  probes.push_back({Vec3(1e30f, 0.f, 0.f), Vec3(-1e30f, 0.f, 0.f)});  // finite, far beyond the box
  const LaneIsa best = lane_isa();
  for (LaneIsa level : {LaneIsa::sse2, LaneIsa::avx, LaneIsa::avx2, LaneIsa::avx512}) {
    set_lane_isa_cap(level);
    if (int(lane_isa()) < int(level)) continue;  // the CPU lacks it
    SCOPED_TRACE(int(level));
    EXPECT_GT(expect_same_as_single(box, probes), probes.size() / 2);
  }
  set_lane_isa_cap(LaneIsa::avx512);
  EXPECT_EQ(lane_isa(), best);
}

TEST(QueryManyTest, CompressedBoxesGiveTheSameAnswersAsSingleQueries) {
  const TriangleMesh mesh = make_torus(1.f, 0.35f, 48, 24);
  BakeOptions options;
  options.params = {8, 12};
  const HapticBox box = bake_box(mesh, {}, options);
  const std::vector<Segment> probes = mixed_probes(mesh);
  for (CodecId codec : {CodecId::block, CodecId::haar}) {
    CodecOptions co;
    co.codec = codec;
    co.max_error = 1e-3f;
    EXPECT_GT(expect_same_as_single(box.compressed(co), probes), probes.size() / 4);
  }
}

TEST(QueryManyTest, SceneOfSeveralBoxesGivesTheSameAnswersAsSingleQueries) {
  const test::TwoSpheres two = test::two_spheres(1.5f);  // overlapping pieces: handle_inside matters
  const TriangleMesh& both = two.mesh;
  BakeOptions options;
  options.params = {8, 6};
  const BoxScene scene = bake_scene(both, two.piece, options, {});
  ASSERT_EQ(scene.parts().boxes.size(), 2u);
  const std::vector<Segment> probes = mixed_probes(both);
  EXPECT_GT(expect_same_as_single(scene, probes), 0u);
  const BoxScene one(SceneParts({scene.parts().boxes[0]}));
  expect_same_as_single(one, mixed_probes(make_sphere(1.f, 4)));
}

TEST(QueryManyTest, ARefinedSceneOnTheCellsRouteGivesTheSameAnswersAsSingleQueries) {
  // The batch of a scene on the cells route (overlapping pieces): the single queries'
  // answers, bit for bit.
  const test::TwoSpheres two = test::two_spheres(1.5f);
  const BoxScene scene = test::refined_two_spheres(two);
  ASSERT_EQ(scene.route(), SceneRoute::cells);
  EXPECT_GT(expect_same_as_single(scene, mixed_probes(two.mesh)), 0u);
  // The walks side by side (the scene leaves so small a surface to one at a time): the same
  // crossings as one walk at a time, bit for bit.
  const SurfaceCells& cells = *scene.cells();
  ASSERT_FALSE(cells.walks_side_by_side());
  const std::vector<Segment> probes = mixed_probes(two.mesh);
  std::vector<Vec3> a, b;
  for (const Segment& s : probes) a.push_back(s.start), b.push_back(s.end);
  std::vector<SurfaceCells::Crossing> side(probes.size());
  cells.first_crossings_along(a.data(), b.data(), probes.size(), side.data());
  std::size_t crossed = 0;
  for (std::size_t i = 0; i < probes.size(); ++i) {
    SurfaceCells::Crossing one;
    cells.first_crossing_along(a[i], b[i], 1.f, one.s, one.front, one.triangle);
    ASSERT_EQ(side[i].triangle, one.triangle) << i;
    if (one.triangle == kNoTriangle) continue;
    ASSERT_EQ(side[i].s, one.s) << i;
    ASSERT_EQ(side[i].front, one.front) << i;
    ++crossed;
  }
  EXPECT_GT(crossed, probes.size() / 4);
}

} // namespace
} // namespace hb
