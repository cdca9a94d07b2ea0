// Surface deviation along the full mesh's normals (surface_deviation.h).
#include "evaluation/surface_deviation.h"
#include "errors.h"
#include "exact/embree_scene.h"
#include <tbb/parallel_for.h>
#include <algorithm>
#include <cmath>
#include <random>

namespace hb {

SurfaceDeviation measure_deviation(const TriangleMesh& full, const TriangleMesh& simplified, std::size_t samples,
                                   double cap, std::uint64_t seed) {
  if (full.triangle_count() == 0 || simplified.triangle_count() == 0)
    throw InvalidInput("measure_deviation: a mesh has no triangles");
  // Points uniform by area: cumulative areas, then sorted picks (one pass).
  std::vector<double> cumulative(full.triangle_count());
  double sum = 0.0;
  for (std::size_t t = 0; t < full.triangle_count(); ++t) {
    const Triangle& tri = full.triangles[t];
    const Vec3& a = full.positions[tri[0]];
    sum += 0.5 * double((full.positions[tri[1]] - a).cross(full.positions[tri[2]] - a).norm());
    cumulative[t] = sum;
  }
  SurfaceDeviation d;
  if (!(sum > 0.0) || samples == 0) return d;
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> uni(0.0, 1.0);
  struct Pick {
    std::size_t t;
    float r1, r2;
  };
  std::vector<Pick> picks(samples);
  for (Pick& p : picks) {
    const double x = uni(rng) * sum;
    p.t = std::min(std::size_t(std::lower_bound(cumulative.begin(), cumulative.end(), x) - cumulative.begin()),
                   full.triangle_count() - 1);
    p.r1 = float(uni(rng));
    p.r2 = float(uni(rng));
    if (p.r1 + p.r2 > 1.f) p.r1 = 1.f - p.r1, p.r2 = 1.f - p.r2;
  }
  const EmbreeScene scene(simplified);
  std::vector<double> dist(samples, cap);
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, samples, 1024), [&](const auto& r) {
    for (std::size_t i = r.begin(); i != r.end(); ++i) {
      const Triangle& tri = full.triangles[picks[i].t];
      const Vec3 &a = full.positions[tri[0]], &b = full.positions[tri[1]], &c = full.positions[tri[2]];
      const Vec3 n = (b - a).cross(c - a);
      if (!(n.squaredNorm() > 0.f)) {
        dist[i] = 0.0;
        continue;
      }
      const Vec3 p = a + picks[i].r1 * (b - a) + picks[i].r2 * (c - a), u = n.normalized();
      // From cap behind the point towards it and past it, both ways (a ray starting on the
      // surface can miss it at t = 0): the simplified surface nearest along the normal.
      double best = cap;
      for (const Vec3& dir : {u, Vec3(-u)}) {
        const RayHit h = scene.intersect(p - float(cap) * dir, dir, 0.f, float(2.0 * cap));
        if (h.hit) best = std::min(best, std::fabs(double(h.t) - cap));
      }
      dist[i] = best;
    }
  });
  d.samples = samples;
  double total = 0.0;
  for (double x : dist) total += x;
  d.mean = total / double(samples);
  std::sort(dist.begin(), dist.end());
  d.p99 = dist[std::min(samples - 1, std::size_t(0.99 * double(samples)))];
  d.max = dist.back();
  return d;
}

} // namespace hb
