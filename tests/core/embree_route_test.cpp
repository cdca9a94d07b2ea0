// SceneRoute::embree: a scene that answers by exact Embree over its own surface gives the
// surface cells' contacts, keeps its route through copies, and refuses what it cannot serve.
#include "perception/perceptible.h"
#include "contact/workspace.h"
#include "errors.h"
#include "evaluation/probe_sampling.h"
#include "exact/exact_query.h"
#include "scene/bake.h"
#include "two_spheres.h"
#include <gtest/gtest.h>
#include <cmath>

namespace hb {
namespace {

// The two spheres baked refined in two pieces, without triangle ids: the cells route.
BoxScene cells_scene(const test::TwoSpheres& two) {
  BakeOptions o;
  o.params = {12, 6};
  o.refine = true;
  return BoxScene(without_triangle_ids(bake_scene(two.mesh, two.piece, o, SourceInfo{})));
}

TEST(EmbreeRouteTest, AnswersAsTheSurfaceCellsAndAsExactAtTheWorkspaceScale) {
  const test::TwoSpheres two = test::two_spheres(3.f);
  const BoxScene cells = cells_scene(two);
  ASSERT_EQ(cells.route(), SceneRoute::cells);
  const BoxScene embree = with_route(cells, SceneRoute::embree);
  ASSERT_EQ(embree.route(), SceneRoute::embree);
  EXPECT_GT(embree.bytes().embree, 0u);
  EXPECT_GT(embree.bytes().memory, cells.bytes().memory);
  const ExactQuery exact(two.mesh);
  const float diagonal = two.mesh.bounds().diagonal();
  const ForceLaw law = make_workspace(diagonal).law();
  const std::vector<Segment> probes = sample_probes(two.mesh, 4000, ProbeOptions{});
  std::size_t contacts = 0, same_flag = 0, same_depth = 0, felt = 0;
  for (const Segment& s : probes) {
    const Contact a = cells.query(s, law), b = embree.query(s, law), e = exact.query(s, law);
    contacts += b.contact ? 1 : 0;
    same_flag += a.contact == b.contact ? 1 : 0;
    if (a.contact && b.contact && std::fabs(a.depth - b.depth) <= 1e-5f * diagonal) ++same_depth;
    felt += perceive(e, b, PerceptualThresholds{}, 0.0).perceptible() ? 1 : 0;
  }
  EXPECT_GT(contacts, probes.size() / 4);
  EXPECT_GE(double(same_flag), 0.999 * double(probes.size())) << same_flag;
  EXPECT_GE(double(same_depth), 0.999 * double(contacts)) << same_depth << " of " << contacts;
  EXPECT_EQ(felt, 0u);
  // Batched and stateful queries answer the same as one at a time.
  std::vector<Contact> many(probes.size());
  embree.query_many(probes.data(), probes.size(), law, many.data());
  SceneQueryState state;
  std::size_t agree = 0;
  for (std::size_t i = 0; i < probes.size(); ++i) {
    const Contact one = embree.query(probes[i], law), with_state = embree.query(probes[i], law, state);
    agree += many[i].contact == one.contact && many[i].depth == one.depth && with_state.depth == one.depth ? 1 : 0;
  }
  EXPECT_EQ(agree, probes.size());
  EXPECT_EQ(embree.box_queries(probes[0], law), 0u);
}

TEST(EmbreeRouteTest, CopiesKeepTheRouteAndTheCellsRouteComesBack) {
  const test::TwoSpheres two = test::two_spheres(3.f);
  const BoxScene scene = with_route(cells_scene(two), SceneRoute::embree);
  const BoxScene copy = scene;
  EXPECT_EQ(copy.route(), SceneRoute::embree);
  SceneParts no_grid = scene.parts();
  no_grid.grid.reset();
  EXPECT_EQ(BoxScene(no_grid).route(), SceneRoute::embree);
  EXPECT_EQ(BoxScene(without_triangle_ids(scene)).route(), SceneRoute::embree);
  EXPECT_EQ(with_route(scene, SceneRoute::cells).route(), SceneRoute::cells);
  EXPECT_STREQ(route_name(SceneRoute::embree), "embree");
}

TEST(EmbreeRouteTest, ASceneWithoutASurfaceRefusesTheRouteNamingWhy) {
  const test::TwoSpheres two = test::two_spheres(3.f);
  BakeOptions o;
  o.params = {8, 4};
  const BoxScene raw = bake_scene(two.mesh, {}, o, SourceInfo{});
  try {
    with_route(raw, SceneRoute::embree);
    FAIL() << "a raw scene took the embree route";
  } catch (const InvalidInput& e) {
    EXPECT_NE(std::string(e.what()).find("embree route needs"), std::string::npos) << e.what();
  }
  EXPECT_NE(raw.route(), SceneRoute::embree);
}

} // namespace
} // namespace hb
