#include "evaluation/comparison.h"
#include "evaluation/probe_sampling.h"
#include "exact/exact_query.h"
#include "mesh/generators.h"
#include "vtkHapticBoxCellLocatorQuery.h"
#include "vtkHapticBoxReferenceQueries.h"
#include <gtest/gtest.h>

TEST(CellLocatorQueryTest, AgreesWithEmbreeOnTheSameProbes) {
  const hb::TriangleMesh mesh = hb::make_torus(1.f, 0.3f, 64, 24);
  const hb::ExactQuery exact(mesh);
  const vtkHapticBoxCellLocatorQuery locator(mesh);
  const auto probes = hb::sample_probes(mesh, 3000, {});
  // compare_queries runs in parallel: this also checks that the locator is thread-safe.
  const hb::ComparisonStats s = hb::compare_queries(locator, exact, probes, {}, mesh.bounds().diagonal());
  EXPECT_GT(s.exact_contacts, 2500u);
  EXPECT_GT(s.contact_agreement, 0.998);
  EXPECT_LT(s.force_error_p95, 1e-3);
  EXPECT_LT(s.angle_error_median_deg, 1e-2);
}

TEST(CellLocatorQueryTest, HandleInsideAndShortTipAreNoContact) {
  const hb::TriangleMesh mesh = hb::make_sphere(1.f, 3);
  const vtkHapticBoxCellLocatorQuery locator(mesh);
  hb::Segment inside{hb::Vec3(0, 0, 0), hb::Vec3(0, 0, 2)};   // starts inside: back side first
  hb::Segment short_tip{hb::Vec3(0, 0, 3), hb::Vec3(0, 0, 1.5f)};
  hb::Segment hit{hb::Vec3(0, 0, 3), hb::Vec3(0, 0, 0.9f)};
  EXPECT_FALSE(locator.query(inside, {}).contact);
  EXPECT_FALSE(locator.query(short_tip, {}).contact);
  const hb::Contact c = locator.query(hit, {});
  ASSERT_TRUE(c.contact);
  EXPECT_NEAR(c.depth, 0.1f, 0.01f);
  EXPECT_GT(c.normal.z(), 0.99f);
  EXPECT_GT(c.force.z(), 0.f);
}

TEST(ReferenceQueriesTest, ExactComesFirst) {
  const hb::TriangleMesh mesh = hb::make_sphere(1.f, 2);
  const vtkHapticBoxReferenceQueries refs(mesh);
  const auto r = refs.References();
  ASSERT_EQ(r.size(), 2u);
  EXPECT_EQ(r[0].method, "exact_embree");
  EXPECT_EQ(r[1].method, "vtk_static_cell_locator");
  EXPECT_GT(r[1].memory_bytes, 0u);
}
