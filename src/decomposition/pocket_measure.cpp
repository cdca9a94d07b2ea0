// Pocket measure.
//  1. Fit the piece's PBB as the bake does; build an Embree scene of the piece only.
//  2. Sample isotropic uniform lines through the PBB's bounding sphere (direction uniform on
//     the sphere, offset uniform on the disc across it), one RNG stream per line.
//  3. Along each line collect every crossing of the piece (repeated first-hit rays) and add
//     up the pocket gaps (line_pockets) and the chord inside the PBB. For isotropic uniform
//     lines, (sum of pocket lengths) / (sum of chords) is the probability for a point uniform
//     in the box and a uniform direction.
//  4. Sum per-line results in line order (deterministic on any thread count).
#include "decomposition/pocket_measure.h"
#include "errors.h"
#include <tbb/parallel_for.h>
#include <algorithm>
#include <cmath>
#include <random>

namespace hb {

void collect_line_hits(const EmbreeScene& scene, const Vec3& origin, const Vec3& dir, float t_far,
                       float merge_eps, std::vector<LineHit>& out, int max_hits) {
  float t_near = 0.f;
  float last_t = -1e30f;
  for (int k = 0; k < max_hits && t_near <= t_far; ++k) {
    const RayHit h = scene.intersect(origin, dir, t_near, t_far);
    if (!h.hit) break;
    if (h.t - last_t > merge_eps) out.push_back({h.t, h.triangle, !h.back_face});
    last_t = h.t;
    t_near = h.t + merge_eps;
  }
}

namespace {

// A uniform isotropic line through the sphere (centre, radius): origin on the near side.
void random_line(std::uint64_t seed, std::uint64_t index, const Vec3& centre, float radius, Vec3& origin,
                 Vec3& dir) {
  std::mt19937_64 rng(seed * 0x9E3779B97F4A7C15ull + index * 0xD1B54A32D192ED03ull + 1);
  std::uniform_real_distribution<double> uni(0.0, 1.0);
  const double z = 2.0 * uni(rng) - 1.0, phi = 2.0 * M_PI * uni(rng);
  const double s = std::sqrt(std::max(0.0, 1.0 - z * z));
  dir = Vec3(float(s * std::cos(phi)), float(s * std::sin(phi)), float(z));
  const Vec3 helper = std::fabs(dir.x()) < 0.9f ? Vec3::UnitX() : Vec3::UnitY();
  const Vec3 e1 = dir.cross(helper).normalized();
  const Vec3 e2 = dir.cross(e1);
  const double r = radius * std::sqrt(uni(rng)), a = 2.0 * M_PI * uni(rng);
  origin = centre + float(r * std::cos(a)) * e1 + float(r * std::sin(a)) * e2 - radius * dir;
}

} // namespace

PocketScore measure_pockets(const TriangleMesh& mesh, const std::vector<std::uint32_t>& triangles,
                            const PocketOptions& options) {
  if (options.lines < 1) throw InvalidInput("measure_pockets: lines must be >= 1");
  const Obb box = fit_obb(mesh, triangles, options.obb);
  const EmbreeScene scene(mesh, triangles);
  const float radius = 0.5f * box.diagonal();
  const float eps = 1e-6f * radius;
  struct PerLine {
    double chord = 0.0;
    LinePockets pockets;
  };
  std::vector<PerLine> per_line(std::size_t(options.lines));
  tbb::parallel_for(0, options.lines, [&](int i) {
    Vec3 origin, dir;
    random_line(options.seed, std::uint64_t(i), box.center, radius, origin, dir);
    LineBoxHit bh;
    if (!intersect_line_obb(box, origin, dir, bh)) return;
    per_line[std::size_t(i)].chord = std::max(0.f, bh.t_exit - bh.t_enter);
    thread_local std::vector<LineHit> hits;
    hits.clear();
    collect_line_hits(scene, origin, dir, 2.f * radius, eps, hits);
    per_line[std::size_t(i)].pockets = line_pockets(hits.data(), hits.size(), [](const LineHit&) { return true; });
  });
  PocketScore score;
  double chord = 0.0, length = 0.0, weighted = 0.0;
  for (const PerLine& p : per_line) {
    if (p.chord > 0.0) ++score.lines;
    chord += p.chord;
    length += p.pockets.length;
    weighted += p.pockets.gap_weighted;
    score.max_depth = std::max(score.max_depth, p.pockets.max_gap);
  }
  const double diag = box.diagonal();
  score.probability = chord > 0.0 ? length / chord : 0.0;
  score.mean_depth = length > 0.0 ? weighted / length / diag : 0.0;
  score.max_depth /= diag;
  return score;
}

} // namespace hb
