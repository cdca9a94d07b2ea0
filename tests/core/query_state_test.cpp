// Per-probe query state (BoxScene::query with a SceneQueryState): along strokes it answers
// most ticks from the last contact, with the answers of the stateless query.
#include "evaluation/probe_sampling.h"
#include "scene/bake.h"
#include "mesh/generators.h"
#include "two_spheres.h"
#include <gtest/gtest.h>
#include <cmath>

namespace hb {
namespace {

const ForceLaw kStateLaw{};

// One raw m16 n8 box of an ellipsoid (radii 1, 0.8, 0.6), block-coded within max_error.
BoxScene block_coded_ellipsoid(const TriangleMesh& ellipsoid, float max_error) {
  BakeOptions o;
  o.params = {16, 8};
  CodecOptions codec;
  codec.codec = CodecId::block;
  codec.max_error = max_error;
  return BoxScene(compressed(bake_scene(ellipsoid, {}, o, SourceInfo{}), codec));
}

void expect_same_answers_along_strokes(const test::TwoSpheres& two, std::size_t& from_state, std::size_t& ticks,
                                       SceneRoute route = SceneRoute::boxes) {
  BakeOptions o;
  o.params = {12, 6};
  o.refine = true;
  const BoxScene scene = with_route(bake_scene(two.mesh, two.piece, o, SourceInfo{}), route);
  ASSERT_TRUE(scene.parts().grid != nullptr);
  const std::vector<Segment> strokes = sample_strokes(two.mesh, 20, 200, 0.02f);
  SceneQueryState state;
  std::size_t differ = 0, contacts = 0;
  for (std::size_t i = 0; i < strokes.size(); ++i) {
    if (i % 200 == 0) state = SceneQueryState{};  // a new stroke, a new probe
    const Contact stateless = scene.query(strokes[i], kStateLaw);
    const Contact stateful = scene.query(strokes[i], kStateLaw, state);
    ASSERT_EQ(stateful.contact, stateless.contact) << i;
    if (!stateless.contact) continue;
    ++contacts;
    const float scale = std::max(1e-6f, stateless.force.norm());
    if (route == SceneRoute::cells ? stateful.force != stateless.force
                                   : (stateful.force - stateless.force).norm() > 1e-4f * scale)
      ++differ;
    EXPECT_NEAR(stateful.depth, stateless.depth, 1e-4f * two.mesh.bounds().diagonal()) << i;
  }
  EXPECT_GT(contacts, strokes.size() / 2);
  EXPECT_EQ(differ, 0u);
  EXPECT_EQ(state.from_state + state.full, 200u);
  ticks += strokes.size();
  // The ticks answered from the state, one probe over all strokes.
  SceneQueryState all;
  for (const Segment& s : strokes) scene.query(s, kStateLaw, all);
  from_state += all.from_state;
}

TEST(QueryStateTest, StrokesGetTheStatelessAnswersMostlyFromTheLastContact) {
  // The state resumes the boxes' route (SceneRoute::boxes): a bounded walk from the last
  // tick's triangle in the last tick's box.
  std::size_t from_state = 0, ticks = 0;
  expect_same_answers_along_strokes(test::two_spheres(3.f), from_state, ticks);
  expect_same_answers_along_strokes(test::two_spheres(1.6f), from_state, ticks);  // overlapping pieces: seams
  EXPECT_GT(from_state, ticks / 2) << from_state << " of " << ticks;
}

TEST(QueryStateTest, TheCellsRouteStartsMostWalksWhereTheLastFullWalkWasFreeWithTheStatelessAnswers) {
  // The default route: while a stroke's segment stays within kFreeReach cells of the last
  // one walked from its handle, its walk starts where that one came within a cell of the
  // surface; the same contacts and forces bit for bit.
  std::size_t from_state = 0, ticks = 0;
  expect_same_answers_along_strokes(test::two_spheres(3.f), from_state, ticks, SceneRoute::cells);
  expect_same_answers_along_strokes(test::two_spheres(1.6f), from_state, ticks, SceneRoute::cells);
  EXPECT_GT(from_state, ticks / 2) << from_state << " of " << ticks;
}

TEST(QueryStateTest, ABlockCodedBoxDecodesAQuadOnceWhileAStrokeStaysInItsCellsWithTheSameBits) {
  // One raw box, block-coded: along strokes the state keeps the last quads decoded; the
  // answers are the stateless ones bit for bit, most ticks reuse the decode, and a state
  // used in another scene (the same place, another table) forgets it.
  const TriangleMesh sphere = make_ellipsoid(Vec3(1.f, 0.8f, 0.6f), 4);
  const BoxScene scene = block_coded_ellipsoid(sphere, 4e-5f);
  ASSERT_EQ(scene.parts().boxes.size(), 1u);
  ASSERT_EQ(scene.parts().boxes[0].codec(), CodecId::block);
  const std::vector<Segment> strokes = sample_strokes(sphere, 10, 200, 0.02f);
  SceneQueryState state;
  std::size_t contacts = 0;
  // A grazing tick may settle on the quadric the last one fitted (SettledQuadric): within a
  // tenth of a cell of where the stateless query settles, not the same bits.
  const float cell = scene.parts().boxes[0].layout().obb().diagonal() / 16.f;
  std::size_t from_quadric = 0;
  for (const Segment& s : strokes) {
    const std::uint64_t before = state.quads.settled.reused;
    const Contact a = scene.query(s, kStateLaw, state), b = scene.query(s, kStateLaw);
    ASSERT_EQ(a.contact, b.contact);
    contacts += a.contact;
    if (state.quads.settled.reused != before) {
      ++from_quadric;
      EXPECT_LT((a.point - b.point).norm(), 0.1f * cell);
      continue;
    }
    ASSERT_EQ(a.force, b.force);
    ASSERT_EQ(a.point, b.point);
  }
  EXPECT_GT(contacts, strokes.size() / 2);
  EXPECT_LT(from_quadric, strokes.size() / 2) << from_quadric;
  EXPECT_GT(state.quads.reused, strokes.size() / 2) << "of " << strokes.size();
  // Another scene's table (coded coarser): its own answers, not the kept decode.
  const BoxScene other = block_coded_ellipsoid(sphere, 4e-3f);
  const Contact a = other.query(strokes.back(), kStateLaw, state), b = other.query(strokes.back(), kStateLaw);
  EXPECT_EQ(a.force, b.force);
  EXPECT_EQ(state.quads.reused, 0u);  // forgotten, then decoded afresh
}

TEST(QueryStateTest, AGrazingStrokeSettlesOnTheQuadricItsLastTickFittedWithinATenthOfACell) {
  // One raw box, block-coded; a stroke of lines along -x sliding over the ellipsoid's flank
  // where they meet it 75 degrees from its normal (settled, step 6a). Most ticks cross the
  // quadric the last settle fitted instead of fitting again; their contacts stay within a
  // tenth of a position cell of the stateless ones, and another table does not take it.
  const TriangleMesh ellipsoid = make_ellipsoid(Vec3(1.f, 0.8f, 0.6f), 5);
  const BoxScene scene = block_coded_ellipsoid(ellipsoid, 4e-5f);
  ASSERT_EQ(scene.parts().boxes.size(), 1u);
  const float cell = scene.parts().boxes[0].layout().obb().diagonal() / 16.f;
  SceneQueryState state;
  std::size_t contacts = 0;
  for (int i = 0; i < 200; ++i) {
    const float y = -0.05f + 0.0005f * float(i), z = 0.55f;
    const float x_hit = std::sqrt(1.f - (y / 0.8f) * (y / 0.8f) - (z / 0.6f) * (z / 0.6f));
    const Segment s{Vec3(2.f, y, z), Vec3(x_hit - 0.02f, y, z)};
    const Contact a = scene.query(s, kStateLaw, state), b = scene.query(s, kStateLaw);
    ASSERT_EQ(a.contact, b.contact);
    if (!a.contact) continue;
    ++contacts;
    EXPECT_LT(std::fabs(a.normal.x()), 0.6f);  // grazing: the settle's range
    EXPECT_LT((a.point - b.point).norm(), 0.1f * cell) << "tick " << i;
    EXPECT_LT((a.force - b.force).norm(), 0.05f * b.force.norm()) << "tick " << i;
  }
  EXPECT_EQ(contacts, 200u);
  EXPECT_GT(state.quads.settled.reused, 100u);
  // Another scene's table: the kept quadric is forgotten, its own settle answers.
  const BoxScene other = block_coded_ellipsoid(ellipsoid, 4e-3f);
  const Segment last{Vec3(2.f, 0.05f, 0.55f), Vec3(0.3f, 0.05f, 0.55f)};
  const Contact a = other.query(last, kStateLaw, state), b = other.query(last, kStateLaw);
  EXPECT_EQ(a.force, b.force);
  EXPECT_EQ(state.quads.settled.reused, 0u);
}

TEST(QueryStateTest, AStateIsNotTakenForAnotherScenesOrAFarSegments) {
  // A probe's state walked in one scene says nothing about another one's surface, even one
  // made at the same place after the first is gone; and a segment far from the one walked
  // in full is walked in full.
  const test::TwoSpheres two = test::two_spheres(3.f);
  BakeOptions o;
  o.params = {12, 6};
  o.refine = true;
  SceneQueryState state;
  const std::vector<Segment> probes = sample_probes(two.mesh, 200);
  {
    const BoxScene first = with_route(bake_scene(two.mesh, two.piece, o, SourceInfo{}), SceneRoute::cells);
    first.query(probes[0], kStateLaw, state);
    EXPECT_EQ(state.full, 1u);
  }
  const BoxScene second = with_route(bake_scene(two.mesh, two.piece, o, SourceInfo{}), SceneRoute::cells);
  const Contact c = second.query(probes[0], kStateLaw, state);
  EXPECT_EQ(state.full, 2u);
  EXPECT_EQ(state.from_state, 0u);
  EXPECT_EQ(c.force, second.query(probes[0], kStateLaw).force);
  // Random probes, one after another, are far apart: each is walked in full.
  std::size_t contacts = 0;
  for (const Segment& s : probes) {
    const Contact a = second.query(s, kStateLaw, state), b = second.query(s, kStateLaw);
    ASSERT_EQ(a.contact, b.contact);
    ASSERT_EQ(a.force, b.force);
    contacts += a.contact;
  }
  EXPECT_GT(contacts, probes.size() / 4);
  EXPECT_LT(state.from_state, probes.size() / 10);
}

TEST(QueryStateTest, PrimingAProbeLeavesItsStateAndItsAnswersAsTheyWere) {
  // The servo loop primes its caches with the last tick's segment (ContactQuery::prime):
  // on the boxes' route, where the state answers most ticks, a probe primed before every
  // tick answers as one never primed, and its state counts the real ticks only.
  const test::TwoSpheres two = test::two_spheres(1.6f);
  BakeOptions o;
  o.params = {12, 6};
  o.refine = true;
  const BoxScene scene = with_route(bake_scene(two.mesh, two.piece, o, SourceInfo{}), SceneRoute::boxes);
  const std::vector<Segment> strokes = sample_strokes(two.mesh, 4, 200, 0.02f);
  SceneProbe primed(scene), plain(scene);
  std::size_t contacts = 0;
  for (std::size_t i = 0; i < strokes.size(); ++i) {
    if (i > 0) primed.prime(strokes[i - 1], kStateLaw);
    const Contact a = primed.query(strokes[i], kStateLaw), b = plain.query(strokes[i], kStateLaw);
    ASSERT_EQ(a.contact, b.contact) << i;
    ASSERT_EQ(a.force, b.force) << i;
    contacts += a.contact;
  }
  EXPECT_GT(contacts, strokes.size() / 2);
  EXPECT_EQ(primed.state().from_state + primed.state().full, strokes.size());
  EXPECT_EQ(primed.state().from_state, plain.state().from_state);
  EXPECT_GT(primed.state().from_state, 0u);
}

TEST(QueryStateTest, ScenesWithoutAGridAndUnknownStatesTakeTheFullQuery) {
  const test::TwoSpheres two = test::two_spheres(3.f);
  BakeOptions o;
  o.params = {10, 4};
  o.refine = true;
  const BoxScene one = bake_scene(two.mesh, {}, o, SourceInfo{});  // one box: no grid
  SceneQueryState state;
  for (const Segment& s : sample_strokes(two.mesh, 2, 50, 0.02f)) {
    const Contact a = one.query(s, kStateLaw), b = one.query(s, kStateLaw, state);
    EXPECT_EQ(a.contact, b.contact);
    EXPECT_EQ(a.force, b.force);
  }
  EXPECT_EQ(state.from_state, 0u);
  EXPECT_EQ(state.full, 100u);
  // A stale state naming a box or triangle the scene does not have is ignored.
  const BoxScene two_boxes = bake_scene(two.mesh, two.piece, o, SourceInfo{});
  SceneQueryState stale;
  stale.box = 7;
  stale.triangle = 123456789;
  const Segment s = sample_probes(two.mesh, 1).front();
  EXPECT_EQ(two_boxes.query(s, kStateLaw, stale).contact, two_boxes.query(s, kStateLaw).contact);
  stale.box = 0;
  stale.triangle = 123456789;
  EXPECT_EQ(two_boxes.query(s, kStateLaw, stale).contact, two_boxes.query(s, kStateLaw).contact);
}

} // namespace
} // namespace hb
