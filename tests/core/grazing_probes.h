#pragma once
// Segments into a mesh's surface far from its normal: what a raw box settles across the
// surface (haptic_box.cpp, step 6a).
#include "geometry/segment.h"
#include "mesh/triangle_mesh.h"
#include <cmath>
#include <random>
#include <vector>

namespace hb::test {

/// `count` segments through the centroids of random triangles, each min_deg..max_deg from its
/// triangle's normal (random azimuth): the handle `back` before the centroid along the
/// segment, the tip `depth` below the triangle's plane (depth / cos along the segment).
inline std::vector<Segment> grazing_segments(const TriangleMesh& mesh, int count, unsigned seed, float min_deg,
                                             float max_deg, float back, float depth) {
  std::mt19937 rng(seed);
  std::uniform_int_distribution<std::size_t> which(0, mesh.triangle_count() - 1);
  std::uniform_real_distribution<float> angle(min_deg, max_deg), spin(0.f, 6.2831853f);
  std::vector<Segment> out;
  for (int i = 0; i < count; ++i) {
    const Triangle& t = mesh.triangles[which(rng)];
    const Vec3 a = mesh.positions[t[0]], b = mesh.positions[t[1]], c = mesh.positions[t[2]];
    const Vec3 n = (b - a).cross(c - a).normalized();
    const Vec3 u = n.unitOrthogonal(), v = n.cross(u);
    const float theta = angle(rng) * 3.14159265f / 180.f, phi = spin(rng);
    const Vec3 l = -std::cos(theta) * n + std::sin(theta) * (std::cos(phi) * u + std::sin(phi) * v);
    const Vec3 hit = (a + b + c) / 3.f;
    out.push_back({hit - back * l, hit + (depth / std::cos(theta)) * l});
  }
  return out;
}

} // namespace hb::test
