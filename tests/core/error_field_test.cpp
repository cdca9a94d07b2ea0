#include "evaluation/error_field.h"
#include "exact/exact_query.h"
#include "errors.h"
#include "mesh/generators.h"
#include <gtest/gtest.h>
#include <cmath>
#include <limits>

TEST(ErrorFieldTest, ExactAgainstItselfHasNoError) {
  const hb::TriangleMesh mesh = hb::make_sphere(1.f, 3);
  const hb::ExactQuery exact(mesh);
  hb::ErrorFieldOptions options;
  options.probes_per_point = 2;
  const auto points = hb::surface_points_at_vertices(mesh);
  const hb::ErrorField f = hb::compute_error_field(exact, exact, points, mesh.bounds().diagonal(), options);
  ASSERT_EQ(f.size(), mesh.vertex_count());
  EXPECT_EQ(f.probes, 2 * mesh.vertex_count());
  std::size_t with_data = 0;
  for (std::size_t i = 0; i < f.size(); ++i) {
    EXPECT_EQ(f.contact_disagreement[i], 0.f);
    if (!std::isnan(f.force_error[i])) {
      ++with_data;
      EXPECT_EQ(f.force_error[i], 0.f);
    }
  }
  EXPECT_EQ(with_data, mesh.vertex_count());  // every probe aimed at the sphere reaches it
}

TEST(ErrorFieldTest, DeterministicWhateverTheThreadsAndCancellable) {
  const hb::TriangleMesh mesh = hb::make_torus(1.f, 0.3f, 48, 16);
  const hb::ExactQuery exact(mesh);
  const auto points = hb::sample_surface_evenly(mesh, 5000, 3);
  EXPECT_EQ(points.size(), 5000u);
  hb::ErrorFieldOptions options;
  const auto a = hb::compute_error_field(exact, exact, points, 2.f, options);
  const auto b = hb::compute_error_field(exact, exact, points, 2.f, options);
  EXPECT_EQ(a.exact_force, b.exact_force);
  options.progress = [](double f) { return f < 0.3; };
  EXPECT_THROW(hb::compute_error_field(exact, exact, points, 2.f, options), hb::Cancelled);
  options.progress = {};
  options.probes_per_point = 0;
  EXPECT_THROW(hb::compute_error_field(exact, exact, points, 2.f, options), hb::InvalidInput);
}

// The window's error-field panel sums a metric up with this: no-data points apart, the median of
// the rest, the points above zero, and the worst points largest first (ties by index).
TEST(ErrorFieldTest, ValuesSummaryCountsNoDataAndListsTheWorstFirst) {
  const float nan = std::numeric_limits<float>::quiet_NaN();
  const std::vector<float> values = {0.f, 0.5f, nan, 2.f, 0.5f, nan, 0.f, 1.f};
  const hb::ErrorValuesSummary s = hb::summarize_error_values(values, 3);
  EXPECT_EQ(s.with_data, 6u);
  EXPECT_EQ(s.no_data, 2u);
  EXPECT_EQ(s.above_zero, 4u);
  EXPECT_DOUBLE_EQ(s.median, 0.5);  // sorted 0 0 0.5 0.5 1 2: the upper median
  EXPECT_EQ(s.worst, (std::vector<std::size_t>{3, 7, 1}));
  const hb::ErrorValuesSummary none = hb::summarize_error_values({nan, nan}, 10);
  EXPECT_EQ(none.with_data, 0u);
  EXPECT_EQ(none.no_data, 2u);
  EXPECT_DOUBLE_EQ(none.median, 0.0);
  EXPECT_TRUE(none.worst.empty());
}

// A viewer puts its probe on the field's own probe at a point: error_field_probes gives the
// segments compute_error_field ran there (the same exact force, averaged the same way).
TEST(ErrorFieldTest, ProbesOfAPointAreTheOnesTheFieldRan) {
  const hb::TriangleMesh mesh = hb::make_torus(1.f, 0.3f, 48, 16);
  const hb::ExactQuery exact(mesh);
  const auto points = hb::surface_points_at_vertices(mesh);
  hb::ErrorFieldOptions options;
  options.probes_per_point = 3;
  const float diagonal = mesh.bounds().diagonal();
  const hb::ErrorField f = hb::compute_error_field(exact, exact, points, diagonal, options);
  for (std::size_t i : {std::size_t(0), std::size_t(17), points.size() - 1}) {
    const std::vector<hb::Segment> probes = hb::error_field_probes(points[i], i, diagonal, options);
    ASSERT_EQ(probes.size(), 3u);
    hb::Vec3 sum = hb::Vec3::Zero();
    for (const hb::Segment& s : probes) {
      sum += exact.query(s, options.law).force;
      // Each aimed at the point (within the 1e-4 diagonal jitter), inside the cone, one length long.
      const hb::Vec3 d = (s.end - s.start).normalized();
      EXPECT_NEAR((s.end - s.start).norm(), options.length_fraction * diagonal, 1e-4f);
      EXPECT_GE(d.dot(-points[i].normal.normalized()), std::cos(options.cone_degrees * float(M_PI) / 180.f) - 1e-4f);
    }
    EXPECT_EQ(sum / 3.f, f.exact_force[i]);
  }
}
