// Per-probe query state (BoxScene::query with a SceneQueryState): along strokes it answers
// most ticks from the last contact, with the answers of the stateless query.
#include "evaluation/probe_sampling.h"
#include "haptic_box/bake.h"
#include "two_spheres.h"
#include <gtest/gtest.h>
#include <cmath>

namespace hb {
namespace {

const ForceLaw kStateLaw{};

void expect_same_answers_along_strokes(const test::TwoSpheres& two, std::size_t& from_state, std::size_t& ticks,
                                       SceneRoute route = SceneRoute::boxes) {
  BakeOptions o;
  o.params = {12, 6};
  o.refine = true;
  BoxScene scene = bake_scene(two.mesh, two.piece, o, SourceInfo{});
  scene.set_route(route);
  ASSERT_TRUE(scene.grid() != nullptr);
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
    if ((stateful.force - stateless.force).norm() > 1e-4f * scale) ++differ;
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

TEST(QueryStateTest, TheCellsRouteGivesTheStatelessAnswersAlongStrokes) {
  // The default route answers every tick in full (the cells' walk from the handle): a state
  // changes nothing.
  std::size_t from_state = 0, ticks = 0;
  expect_same_answers_along_strokes(test::two_spheres(3.f), from_state, ticks, SceneRoute::cells);
  expect_same_answers_along_strokes(test::two_spheres(1.6f), from_state, ticks, SceneRoute::cells);
  EXPECT_EQ(from_state, 0u);
}

TEST(QueryStateTest, PrimingAProbeLeavesItsStateAndItsAnswersAsTheyWere) {
  // The servo loop primes its caches with the last tick's segment (ContactQuery::prime):
  // on the boxes' route, where the state answers most ticks, a probe primed before every
  // tick answers as one never primed, and its state counts the real ticks only.
  const test::TwoSpheres two = test::two_spheres(1.6f);
  BakeOptions o;
  o.params = {12, 6};
  o.refine = true;
  BoxScene scene = bake_scene(two.mesh, two.piece, o, SourceInfo{});
  scene.set_route(SceneRoute::boxes);
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
