// Surface deviation along the full mesh's normals, and the shading fit (surface_deviation.h).
#include "evaluation/surface_deviation.h"
#include "errors.h"
#include "stopwatch.h"
#include "exact/embree_scene.h"
#include "surface/surface_triangles.h"
#include "geometry/octahedral.h"
#include <Eigen/Dense>
#include <tbb/parallel_for.h>
#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <memory>
#include <random>

namespace hb {
namespace {

// The hit of `scene` nearest to p along the line p + s u, |s| <= cap: from cap behind p
// towards it and past it, both ways (a ray starting on the surface can miss it at s = 0).
RayHit nearest_hit_along(const EmbreeScene& scene, const Vec3& p, const Vec3& u, double cap, double& distance) {
  RayHit best;
  distance = cap;
  for (const Vec3& dir : {u, Vec3(-u)}) {
    const RayHit h = scene.intersect(p - float(cap) * dir, dir, 0.f, float(2.0 * cap));
    if (h.hit && std::fabs(double(h.t) - cap) < distance) distance = std::fabs(double(h.t) - cap), best = h;
  }
  return best;
}

double normal_angle_deg(const Vec3& a, const Vec3& b) {
  return std::acos(double(std::max(-1.f, std::min(1.f, a.dot(b))))) * 180.0 / M_PI;
}

double deviation_quantile(std::vector<double>& v, double q) {
  if (v.empty()) return 0.0;
  const std::size_t k = std::min(v.size() - 1, std::size_t(q * double(v.size())));
  std::nth_element(v.begin(), v.begin() + std::ptrdiff_t(k), v.end());
  return v[k];
}

// What fit_shading and fit_normal_map need of their meshes, or throws naming `what`.
void check_shading_meshes(const char* what, const TriangleMesh& full, const TriangleMesh& simplified) {
  if (full.triangle_count() == 0 || simplified.triangle_count() == 0)
    throw InvalidInput(std::string(what) + ": a mesh has no triangles");
  if (simplified.normals.size() != simplified.positions.size() || full.normals.size() != full.positions.size())
    throw InvalidInput(std::string(what) + ": both meshes need vertex normals");
}

} // namespace

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
  const bool shaded = full.normals.size() == full.positions.size() && simplified.normals.size() == simplified.positions.size();
  std::vector<double> dist(samples, cap), angle(samples, -1.0);
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
      // The simplified surface nearest along the normal.
      double best = cap;
      const RayHit h = nearest_hit_along(scene, p, u, cap, best);
      dist[i] = best;
      if (shaded && h.hit) {
        const float w0 = 1.f - picks[i].r1 - picks[i].r2;
        Vec3 m = w0 * full.normals[tri[0]] + picks[i].r1 * full.normals[tri[1]] + picks[i].r2 * full.normals[tri[2]];
        if (m.squaredNorm() > 0.f) {
          m.normalize();
          if (m.dot(u) < 0.f) m = -m;  // oriented like the face, as RayHit::normal
          angle[i] = normal_angle_deg(m, h.normal);
        }
      }
    }
  });
  d.samples = samples;
  double total = 0.0;
  for (double x : dist) total += x;
  d.mean = total / double(samples);
  std::sort(dist.begin(), dist.end());
  d.p99 = dist[std::min(samples - 1, std::size_t(0.99 * double(samples)))];
  d.max = dist.back();
  std::vector<double> met;
  for (double x : angle)
    if (x >= 0.0) met.push_back(x);
  d.normal_median_deg = deviation_quantile(met, 0.5);
  d.normal_p95_deg = deviation_quantile(met, 0.95);
  d.normal_p99_deg = deviation_quantile(met, 0.99);
  return d;
}

TriangleMesh fit_shading(const TriangleMesh& full, const TriangleMesh& simplified, double cap, int grid,
                         ShadingFitStats* stats) {
  check_shading_meshes("fit_shading", full, simplified);
  if (grid < 1) throw InvalidInput("fit_shading: grid must be >= 1, got " + std::to_string(grid));
  const auto t0 = std::chrono::steady_clock::now();
  const std::size_t n = simplified.triangle_count();
  TriangleMesh out;
  out.positions.resize(3 * n);
  out.normals.resize(3 * n);
  out.triangles.resize(n);
  // Barycentric grid points (u, v), corners and edges included.
  std::vector<std::pair<float, float>> points;
  for (int i = 0; i <= grid; ++i)
    for (int j = 0; i + j <= grid; ++j) points.emplace_back(float(i) / float(grid), float(j) / float(grid));
  const EmbreeScene scene(full);
  std::atomic<std::size_t> fitted{0};
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, n, 256), [&](const auto& r) {
    std::size_t done = 0;
    for (std::size_t t = r.begin(); t != r.end(); ++t) {
      const Triangle& tri = simplified.triangles[t];
      Vec3 corner[3], normal[3];
      for (int k = 0; k < 3; ++k) {
        corner[k] = simplified.positions[tri[std::size_t(k)]];
        normal[k] = simplified.normals[tri[std::size_t(k)]];
        out.positions[3 * t + std::size_t(k)] = corner[k];
        out.triangles[t][std::size_t(k)] = std::uint32_t(3 * t + std::size_t(k));
      }
      const Vec3 g = (corner[1] - corner[0]).cross(corner[2] - corner[0]);
      bool ok = g.squaredNorm() > 0.f && std::isfinite(g.squaredNorm());
      if (ok) {
        // Normal equations of min sum_k |sum_c w_kc n_c - N_k|^2, one 3x3 system for the
        // three components, with a small pull towards the vertex normals (a triangle whose
        // points all lie on one line still has a unique fit).
        const Vec3 u = g.normalized();
        Eigen::Matrix3d m = Eigen::Matrix3d::Zero();
        Eigen::Matrix3d rhs = Eigen::Matrix3d::Zero();  // row c: the target for corner c
        int met = 0;
        for (const auto& [bu, bv] : points) {
          const Vec3 p = (1.f - bu - bv) * corner[0] + bu * corner[1] + bv * corner[2];
          double distance = 0.0;
          const RayHit h = nearest_hit_along(scene, p, u, cap, distance);
          if (!h.hit || h.normal.dot(u) <= 0.f) continue;  // another sheet, or facing away
          const Eigen::Vector3d w(1.0 - double(bu) - double(bv), double(bu), double(bv));
          m += w * w.transpose();
          rhs += w * h.normal.cast<double>().transpose();
          ++met;
        }
        ok = met >= 3;
        if (ok) {
          const double lambda = 1e-3 * double(met);
          for (int c = 0; c < 3; ++c) {
            m(c, c) += lambda;
            rhs.row(c) += lambda * normal[c].cast<double>().transpose();
          }
          const Eigen::Matrix3d x = m.ldlt().solve(rhs);
          Vec3 fit[3];
          for (int c = 0; c < 3 && ok; ++c) {
            fit[c] = x.row(c).transpose().cast<float>();
            ok = std::isfinite(fit[c].squaredNorm()) && fit[c].squaredNorm() > 1e-12f && fit[c].dot(u) > 0.f;
            if (ok) fit[c].normalize();
          }
          if (ok)
            for (int c = 0; c < 3; ++c) normal[c] = fit[c];
        }
      }
      for (int k = 0; k < 3; ++k) out.normals[3 * t + std::size_t(k)] = normal[k];
      done += ok ? 1 : 0;
    }
    fitted += done;
  });
  if (stats) {
    stats->triangles = n;
    stats->fitted = fitted.load();
    stats->seconds = seconds_since(t0);
  }
  return out;
}

std::vector<std::uint32_t> fit_normal_map(const TriangleMesh& full, const TriangleMesh& simplified, int side,
                                          double cap, const EmbreeScene* scene, ShadingFitStats* stats) {
  check_shading_meshes("fit_normal_map", full, simplified);
  if (side < 1 || side > SurfaceTriangles::kMaxMapSide)
    throw InvalidInput("fit_normal_map: side must be in [1, " + std::to_string(SurfaceTriangles::kMaxMapSide) +
                       "], got " + std::to_string(side));
  const auto t0 = std::chrono::steady_clock::now();
  std::unique_ptr<EmbreeScene> own;
  if (!scene) {
    own = std::make_unique<EmbreeScene>(full);
    scene = own.get();
  }
  const std::size_t n = simplified.triangle_count();
  const std::size_t per = SurfaceTriangles::lattice_points(side);
  std::vector<std::uint32_t> map(n * per);
  std::atomic<std::size_t> fitted{0};
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, n, 64), [&](const auto& r) {
    std::size_t met_all = 0;
    for (std::size_t t = r.begin(); t != r.end(); ++t) {
      const Triangle& tri = simplified.triangles[t];
      const Vec3 a = simplified.positions[tri[0]], e1 = simplified.positions[tri[1]] - a,
                 e2 = simplified.positions[tri[2]] - a;
      const Vec3 na = simplified.normals[tri[0]], nb = simplified.normals[tri[1]], nc = simplified.normals[tri[2]];
      const Vec3 g = e1.cross(e2);
      const bool flat = g.squaredNorm() > 0.f && std::isfinite(g.squaredNorm());
      const Vec3 u = flat ? Vec3(g.normalized()) : Vec3::Zero();
      std::uint32_t* out = map.data() + t * per;
      bool all = flat;
      for (int j = 0; j <= side; ++j)
        for (int i = 0; i + j <= side; ++i) {
          const float bu = float(i) / float(side), bv = float(j) / float(side);
          Vec3 normal = (1.f - bu - bv) * na + bu * nb + bv * nc;
          if (flat) {
            // A line through a vertex or along an edge of `full` can slip between its
            // triangles: then the point moved a little towards the centroid (the shading is
            // continuous, so the normal there is the point's up to that little).
            const Vec3 p = a + bu * e1 + bv * e2, towards = (a + (e1 + e2) * (1.f / 3.f)) - p;
            bool met = false;
            for (const float nudge : {0.f, 1e-5f, 1e-4f, 1e-3f}) {
              double distance = 0.0;
              const RayHit h = nearest_hit_along(*scene, p + nudge * towards, u, cap, distance);
              if (h.hit && h.normal.dot(u) > 0.f) {
                normal = h.normal;
                met = true;
                break;
              }
            }
            all = all && met;
          }
          if (!(normal.squaredNorm() > 1e-24f) || !normal.allFinite()) normal = flat ? u : Vec3(0.f, 0.f, 1.f);
          *out++ = encode_octahedral32(normal.normalized());
        }
      met_all += all ? 1 : 0;
    }
    fitted += met_all;
  });
  if (stats) {
    stats->triangles = n;
    stats->fitted = fitted.load();
    stats->seconds = seconds_since(t0);
  }
  return map;
}

} // namespace hb
