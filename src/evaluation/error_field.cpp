// The error field, computed in three steps:
//  1. choose the surface points (vertices, or an even area-proportional sampling);
//  2. for each point, aim k probes at it from the cone around its inward normal, the random
//     numbers drawn from a generator seeded by (seed, point index) so the result does not
//     depend on the thread schedule;
//  3. answer each probe exactly and approximately and reduce per point (means over the probes,
//     errors over the both-in-contact probes only).
// Points are processed in blocks so progress and cancellation stay on the calling thread.
// With several ranks (ErrorFieldOptions::communicator), the points are dealt to the ranks in
// chunks, each rank computes its chunks, and rank 0 gathers every point's figures in point
// order; a point's figures depend on (seed, point index) only, so the field is one process's.
#include "evaluation/error_field.h"
#include "errors.h"
#include "evaluation/comparison.h"
#include "parallel/byte_buffer.h"
#include "parallel/work_split.h"
#include <tbb/parallel_for.h>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>

namespace hb {
namespace {

// SplitMix64: a small, fast, well-mixed generator; one per point.
struct SplitMix {
  std::uint64_t state;
  std::uint64_t next() noexcept {
    std::uint64_t z = (state += 0x9e3779b97f4a7c15ull);
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ull;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebull;
    return z ^ (z >> 31);
  }
  float uniform() noexcept { return float(next() >> 40) * (1.f / 16777216.f); } // [0, 1)
};

double triangle_area(const TriangleMesh& mesh, const Triangle& tri) {
  const Vec3& a = mesh.positions[tri[0]];
  return 0.5 * double((mesh.positions[tri[1]] - a).cross(mesh.positions[tri[2]] - a).norm());
}

} // namespace

std::vector<SurfacePoint> surface_points_at_vertices(const TriangleMesh& mesh) {
  std::vector<SurfacePoint> points(mesh.vertex_count());
  const bool has_normals = mesh.normals.size() == mesh.positions.size();
  for (std::size_t i = 0; i < points.size(); ++i) {
    points[i].position = mesh.positions[i];
    if (has_normals) points[i].normal = mesh.normals[i];
  }
  return points;
}

std::vector<SurfacePoint> sample_surface_evenly(const TriangleMesh& mesh, std::size_t count, std::uint64_t seed) {
  if (mesh.triangle_count() == 0) throw InvalidInput("sample_surface_evenly: mesh has no triangles");
  std::vector<double> cumulative(mesh.triangle_count());
  double sum = 0.0;
  for (std::size_t t = 0; t < mesh.triangle_count(); ++t) cumulative[t] = (sum += triangle_area(mesh, mesh.triangles[t]));
  if (!(sum > 0.0)) throw InvalidInput("sample_surface_evenly: mesh has zero area");
  SplitMix rng{seed};
  std::vector<SurfacePoint> points;
  points.reserve(count);
  for (std::size_t k = 0; k < count; ++k) {
    // Stratified: one uniform pick inside each of `count` equal slices of the total area.
    const double pick = (double(k) + double(rng.uniform())) / double(count) * sum;
    std::size_t t = std::size_t(std::lower_bound(cumulative.begin(), cumulative.end(), pick) - cumulative.begin());
    t = std::min(t, mesh.triangle_count() - 1);
    const Triangle& tri = mesh.triangles[t];
    const Vec3& a = mesh.positions[tri[0]];
    const Vec3& b = mesh.positions[tri[1]];
    const Vec3& c = mesh.positions[tri[2]];
    float r1 = rng.uniform(), r2 = rng.uniform();
    if (r1 + r2 > 1.f) {
      r1 = 1.f - r1;
      r2 = 1.f - r2;
    }
    const Vec3 n = (b - a).cross(c - a);
    if (!(n.squaredNorm() > 0.f)) continue;  // zero-area triangles never win a pick in practice
    points.push_back({a + r1 * (b - a) + r2 * (c - a), n.normalized()});
  }
  return points;
}

std::vector<Segment> error_field_probes(const SurfacePoint& point, std::size_t index, float diagonal,
                                        const ErrorFieldOptions& options) {
  const float length = options.length_fraction * diagonal;
  const float max_depth = options.max_depth_fraction * diagonal;
  const float cos_max = std::cos(options.cone_degrees * float(M_PI) / 180.f);
  const float jitter = 1e-4f * diagonal;
  SplitMix rng{options.seed * 0x2545f4914f6cdd1dull + std::uint64_t(index) * 0x9e3779b97f4a7c15ull};
  const Vec3 inward = -point.normal.normalized();
  const Vec3 helper = std::fabs(inward.x()) < 0.9f ? Vec3::UnitX() : Vec3::UnitY();
  const Vec3 e1 = inward.cross(helper).normalized();
  const Vec3 e2 = inward.cross(e1);
  std::vector<Segment> probes;
  probes.reserve(std::size_t(std::max(0, options.probes_per_point)));
  for (int p = 0; p < options.probes_per_point; ++p) {
    const float cos_theta = 1.f - rng.uniform() * (1.f - cos_max);
    const float sin_theta = std::sqrt(std::max(0.f, 1.f - cos_theta * cos_theta));
    const float phi = 2.f * float(M_PI) * rng.uniform();
    const Vec3 dir = cos_theta * inward + sin_theta * (std::cos(phi) * e1 + std::sin(phi) * e2);
    // Aim a hair (1e-4 diagonal) beside the point, in its tangent plane: a line through a
    // mesh vertex exactly can slip between its triangles in a non-watertight ray test.
    const float jitter_angle = 2.f * float(M_PI) * rng.uniform();
    const Vec3 aim = point.position + jitter * (std::cos(jitter_angle) * e1 + std::sin(jitter_angle) * e2);
    Segment s;
    s.end = aim + rng.uniform() * max_depth * dir;
    s.start = s.end - length * dir;
    probes.push_back(s);
  }
  return probes;
}

ErrorField compute_error_field(const ContactQuery& approx, const ContactQuery& exact,
                               const std::vector<SurfacePoint>& points, float diagonal,
                               const ErrorFieldOptions& options) {
  if (options.probes_per_point < 1) throw InvalidInput("compute_error_field: probes_per_point must be >= 1");
  if (!(options.cone_degrees >= 0.f && options.cone_degrees <= 89.f))
    throw InvalidInput("compute_error_field: cone_degrees must be in [0, 89]");
  if (!(diagonal > 0.f) || !std::isfinite(diagonal)) throw InvalidInput("compute_error_field: diagonal must be > 0");
  if (!(options.length_fraction > 0.f) || options.max_depth_fraction < 0.f ||
      options.max_depth_fraction >= options.length_fraction)
    throw InvalidInput("compute_error_field: need 0 <= max_depth_fraction < length_fraction");

  const auto t0 = std::chrono::steady_clock::now();
  const std::size_t count = points.size();
  ErrorField field;
  field.exact_force.assign(count, Vec3::Zero());
  field.approx_force.assign(count, Vec3::Zero());
  field.force_error.assign(count, 0.f);
  field.force_error_newtons.assign(count, 0.f);
  field.direction_error.assign(count, 0.f);
  field.contact_disagreement.assign(count, 0.f);
  field.exact_contact_fraction.assign(count, 0.f);
  field.perceptible_ratio.assign(count, 0.f);
  field.perceptible_fraction.assign(count, 0.f);

  const int k = options.probes_per_point;
  const float nan = std::numeric_limits<float>::quiet_NaN();

  auto one_point = [&](std::size_t i) {
    Vec3 fe = Vec3::Zero(), fa = Vec3::Zero();
    double err = 0.0, ang = 0.0, abs_err = 0.0;
    int both = 0, disagree = 0, exact_in = 0, perceptible = 0;
    double ratio = 0.0;
    for (const Segment& s : error_field_probes(points[i], i, diagonal, options)) {
      const Contact ce = exact.query(s, options.law);
      const Contact ca = approx.query(s, options.law);
      fe += ce.force;
      fa += ca.force;
      abs_err += double((ca.force - ce.force).norm());
      const PerceivedDifference felt = perceive(ce, ca, options.thresholds, options.max_force_n);
      ratio = std::max(ratio, felt.ratio);
      if (felt.perceptible()) ++perceptible;
      if (ce.contact) ++exact_in;
      if (ce.contact != ca.contact) ++disagree;
      if (ce.contact && ca.contact) {
        ++both;
        err += relative_force_error(ce, ca);
        ang += angle_error_degrees(ce, ca);
      }
    }
    field.exact_force[i] = fe / float(k);
    field.approx_force[i] = fa / float(k);
    field.force_error[i] = both ? float(err / both) : nan;
    field.force_error_newtons[i] = float(abs_err / k);
    field.direction_error[i] = both ? float(ang / both) : nan;
    field.contact_disagreement[i] = float(disagree) / float(k);
    field.exact_contact_fraction[i] = float(exact_in) / float(k);
    field.perceptible_ratio[i] = float(std::min(ratio, 1e30));
    field.perceptible_fraction[i] = float(perceptible) / float(k);
  };

  Communicator& comm = communicator_or_serial(options.communicator);
  if (comm.size() == 1) {
    // Blocks of about 1% of the work, at least 2048 points: progress stays cheap and prompt.
    const std::size_t block = std::max<std::size_t>(2048, count / 100);
    for (std::size_t begin = 0; begin < count; begin += block) {
      const std::size_t end = std::min(count, begin + block);
      tbb::parallel_for(begin, end, one_point);
      if (options.progress && !options.progress(double(end) / double(count)))
        throw Cancelled("compute_error_field: cancelled");
    }
  } else {
    const DealtChunks deal{count, deal_chunk_size(count, comm.size(), 64, 256), comm.size()};
    const std::size_t mine = deal.items_of(comm.rank());
    std::size_t done = 0;
    ByteWriter w;
    w.reserve(mine * 52);
    deal.for_each_of(comm.rank(), [&](std::size_t begin, std::size_t end) {
      tbb::parallel_for(begin, end, one_point);
      for (std::size_t i = begin; i < end; ++i) {
        w.put(field.exact_force[i]);
        w.put(field.approx_force[i]);
        w.put(field.force_error[i]);
        w.put(field.force_error_newtons[i]);
        w.put(field.direction_error[i]);
        w.put(field.contact_disagreement[i]);
        w.put(field.exact_contact_fraction[i]);
        w.put(field.perceptible_ratio[i]);
        w.put(field.perceptible_fraction[i]);
      }
      done += end - begin;
      if (options.progress && !options.progress(double(done) / double(std::max<std::size_t>(mine, 1))))
        throw Cancelled("compute_error_field: cancelled");
    });
    const std::vector<Bytes> parts = comm.gather(w.bytes());
    if (comm.is_root()) {
      for (int r = 1; r < comm.size(); ++r) {
        ByteReader reader(parts[std::size_t(r)], "compute_error_field: rank " + std::to_string(r));
        deal.for_each_of(r, [&](std::size_t begin, std::size_t end) {
          for (std::size_t i = begin; i < end; ++i) {
            field.exact_force[i] = reader.get<Vec3>();
            field.approx_force[i] = reader.get<Vec3>();
            field.force_error[i] = reader.get<float>();
            field.force_error_newtons[i] = reader.get<float>();
            field.direction_error[i] = reader.get<float>();
            field.contact_disagreement[i] = reader.get<float>();
            field.exact_contact_fraction[i] = reader.get<float>();
            field.perceptible_ratio[i] = reader.get<float>();
            field.perceptible_fraction[i] = reader.get<float>();
          }
        });
      }
    } else {
      field = ErrorField{};  // the whole field lives on rank 0
    }
  }
  field.probes = count * std::size_t(k);
  field.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return field;
}

} // namespace hb

hb::ErrorValuesSummary hb::summarize_error_values(const std::vector<float>& values, std::size_t worst_count) {
  ErrorValuesSummary s;
  std::vector<float> finite;
  finite.reserve(values.size());
  std::vector<std::size_t> order;
  for (std::size_t i = 0; i < values.size(); ++i) {
    if (!std::isfinite(values[i])) continue;
    finite.push_back(values[i]);
    if (values[i] > 0.f) order.push_back(i);
  }
  s.with_data = finite.size();
  s.no_data = values.size() - finite.size();
  s.above_zero = order.size();
  if (!finite.empty()) {
    const auto mid = finite.begin() + static_cast<std::ptrdiff_t>(finite.size() / 2);
    std::nth_element(finite.begin(), mid, finite.end());
    s.median = *mid;
  }
  const std::size_t k = std::min(worst_count, order.size());
  std::partial_sort(order.begin(), order.begin() + static_cast<std::ptrdiff_t>(k), order.end(),
                    [&](std::size_t a, std::size_t b) { return values[a] > values[b] || (values[a] == values[b] && a < b); });
  order.resize(k);
  s.worst = std::move(order);
  return s;
}
