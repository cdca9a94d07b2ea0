#include "evaluation/probe_sampling.h"
#include "errors.h"
#include <algorithm>
#include <cmath>
#include <random>

namespace hb {
namespace {
// Two unit vectors completing unit `axis` to an orthonormal basis.
void perpendicular_basis(const Vec3& axis, Vec3& e1, Vec3& e2) {
  const Vec3 helper = std::fabs(axis.x()) < 0.9f ? Vec3::UnitX() : Vec3::UnitY();
  e1 = axis.cross(helper).normalized();
  e2 = axis.cross(e1);
}
} // namespace

std::vector<Segment> sample_probes(const TriangleMesh& mesh, std::size_t count, const ProbeOptions& options) {
  if (mesh.triangle_count() == 0) throw InvalidInput("sample_probes: mesh has no triangles");
  // Cumulative areas for area-proportional triangle choice.
  std::vector<double> cumulative(mesh.triangle_count());
  double sum = 0.0;
  for (std::size_t t = 0; t < mesh.triangle_count(); ++t) {
    const Triangle& tri = mesh.triangles[t];
    const Vec3& a = mesh.positions[tri[0]];
    sum += 0.5 * double((mesh.positions[tri[1]] - a).cross(mesh.positions[tri[2]] - a).norm());
    cumulative[t] = sum;
  }
  if (!(sum > 0.0)) throw InvalidInput("sample_probes: mesh has zero area");
  const float diagonal = mesh.bounds().diagonal();
  const float length = options.length_fraction * diagonal;
  const float max_depth = options.max_depth_fraction * diagonal;
  const float cos_max = std::cos(options.cone_degrees * float(M_PI) / 180.f);

  std::mt19937_64 rng(options.seed);
  std::uniform_real_distribution<double> uni(0.0, 1.0);
  std::vector<Segment> probes;
  probes.reserve(count);
  while (probes.size() < count) {
    const double pick = uni(rng) * sum;
    const std::size_t t = std::size_t(std::lower_bound(cumulative.begin(), cumulative.end(), pick) - cumulative.begin());
    const Triangle& tri = mesh.triangles[std::min(t, mesh.triangle_count() - 1)];
    const Vec3& a = mesh.positions[tri[0]];
    const Vec3& b = mesh.positions[tri[1]];
    const Vec3& c = mesh.positions[tri[2]];
    float r1 = float(uni(rng)), r2 = float(uni(rng));
    if (r1 + r2 > 1.f) {
      r1 = 1.f - r1;
      r2 = 1.f - r2;
    }
    const Vec3 surface = a + r1 * (b - a) + r2 * (c - a);
    const Vec3 nrm = (b - a).cross(c - a);
    if (!(nrm.squaredNorm() > 0.f)) continue;
    const Vec3 inward = -nrm.normalized();
    // Uniform direction in the cone around `inward`.
    const float cos_theta = 1.f - float(uni(rng)) * (1.f - cos_max);
    const float sin_theta = std::sqrt(std::max(0.f, 1.f - cos_theta * cos_theta));
    const float phi = float(2.0 * M_PI * uni(rng));
    Vec3 e1, e2;
    perpendicular_basis(inward, e1, e2);
    const Vec3 dir = cos_theta * inward + sin_theta * (std::cos(phi) * e1 + std::sin(phi) * e2);
    const float depth = float(uni(rng)) * max_depth;
    Segment s;
    s.end = surface + depth * dir;
    s.start = s.end - length * dir;
    probes.push_back(s);
  }
  return probes;
}

std::vector<Segment> sample_strokes(const TriangleMesh& mesh, std::size_t strokes, std::size_t steps,
                                    float radius_fraction, const ProbeOptions& options) {
  if (steps < 1) throw InvalidInput("sample_strokes: a stroke needs at least one step");
  const float radius = radius_fraction * mesh.bounds().diagonal();
  std::vector<Segment> out;
  out.reserve(strokes * steps);
  for (const Segment& anchor : sample_probes(mesh, strokes, options)) {
    const Vec3 l = (anchor.end - anchor.start).normalized();
    Vec3 e1, e2;
    perpendicular_basis(l, e1, e2);
    for (std::size_t i = 0; i < steps; ++i) {
      const float phase = float(2.0 * M_PI * double(i) / double(steps));
      const Vec3 offset = radius * (std::cos(phase) * e1 + std::sin(phase) * e2);
      out.push_back({anchor.start + offset, anchor.end + offset});
    }
  }
  return out;
}

namespace {
std::uint64_t spread_bits(std::uint64_t v) {  // 21 bits -> every third bit
  v &= 0x1fffff;
  v = (v | v << 32) & 0x1f00000000ffffULL;
  v = (v | v << 16) & 0x1f0000ff0000ffULL;
  v = (v | v << 8) & 0x100f00f00f00f00fULL;
  v = (v | v << 4) & 0x10c30c30c30c30c3ULL;
  v = (v | v << 2) & 0x1249249249249249ULL;
  return v;
}
} // namespace

void sort_probes_coherently(std::vector<Segment>& probes) {
  if (probes.empty()) return;
  Vec3 lo = probes.front().end, hi = lo;
  for (const Segment& s : probes) {
    lo = lo.cwiseMin(s.end);
    hi = hi.cwiseMax(s.end);
  }
  const Vec3 scale = (hi - lo).cwiseMax(Vec3::Constant(1e-20f)).cwiseInverse() * float((1 << 21) - 1);
  std::vector<std::pair<std::uint64_t, std::size_t>> keys(probes.size());
  for (std::size_t i = 0; i < probes.size(); ++i) {
    const Vec3 q = (probes[i].end - lo).cwiseProduct(scale);
    keys[i] = {spread_bits(std::uint64_t(q.x())) | spread_bits(std::uint64_t(q.y())) << 1 |
                   spread_bits(std::uint64_t(q.z())) << 2,
               i};
  }
  std::sort(keys.begin(), keys.end());
  std::vector<Segment> sorted(probes.size());
  for (std::size_t i = 0; i < keys.size(); ++i) sorted[i] = probes[keys[i].second];
  probes = std::move(sorted);
}

} // namespace hb
