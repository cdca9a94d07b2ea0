// Oriented bounding box fitting.
//  1. Area-weighted covariance of the selected triangles (Gottschalk et al. 1996, eq. for
//     continuous triangles); its eigenvectors are the initial axes.
//  2. Local search: rotate about each axis by +-step, keep a rotation when the box volume
//     drops, halve the step when no rotation helps; the volume never grows.
//  3. Pad every half extent by options.padding * diagonal.
// obb_problem() checks a box from elsewhere (a file) before any query uses it.
#include "geometry/obb.h"
#include "geometry/convex_hull.h"
#include "errors.h"
#include <Eigen/Eigenvalues>
#include <Eigen/Geometry>
#include <tbb/blocked_range.h>
#include <tbb/parallel_reduce.h>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>

namespace hb {
namespace {

struct Extent {
  Vec3 lo, hi;
};

// The extremes of the points along the axes, in parallel over blocks of points (min and max
// do not depend on the order: the same result as one loop, bit for bit).
Extent extent_along(const std::vector<Vec3>& points, const Eigen::Matrix3f& axes) {
  const Extent empty{Vec3::Constant(std::numeric_limits<float>::max()), Vec3::Constant(-std::numeric_limits<float>::max())};
  const Eigen::Matrix3f at = axes.transpose();
  const auto block = [&](const tbb::blocked_range<std::size_t>& r, Extent e) {
    for (std::size_t k = r.begin(); k != r.end(); ++k) {
      const Vec3 q = at * points[k];
      e.lo = e.lo.cwiseMin(q);
      e.hi = e.hi.cwiseMax(q);
    }
    return e;
  };
  if (points.size() < 65536) return block(tbb::blocked_range<std::size_t>(0, points.size()), empty);
  return tbb::parallel_reduce(tbb::blocked_range<std::size_t>(0, points.size(), 16384), empty, block,
                              [](const Extent& x, const Extent& y) { return Extent{x.lo.cwiseMin(y.lo), x.hi.cwiseMax(y.hi)}; });
}

float volume_of(const Extent& e) { return (e.hi - e.lo).prod(); }

Eigen::Matrix3f right_handed(Eigen::Matrix3f axes) {
  for (int c = 0; c < 3; ++c) axes.col(c).normalize();
  axes.col(2) = axes.col(0).cross(axes.col(1)).normalized();
  axes.col(1) = axes.col(2).cross(axes.col(0)).normalized();
  return axes;
}

} // namespace

Obb fit_obb(const TriangleMesh& mesh, const std::vector<std::uint32_t>& triangles,
            const ObbOptions& options) {
  const std::size_t count = triangles.empty() ? mesh.triangle_count() : triangles.size();
  if (count == 0) throw InvalidInput("fit_obb: no triangles selected");

  // 1. Area-weighted covariance of the surface. The extents (step 2) come from the vertices,
  // each once: a closed mesh has about half as many vertices as triangles, so a sixth of the
  // three corners per triangle.
  std::vector<Vec3> points;
  std::vector<bool> seen(mesh.vertex_count(), false);  // first use, no sort: the extremes do not depend on order
  Eigen::Vector3d mean = Eigen::Vector3d::Zero();
  Eigen::Matrix3d second = Eigen::Matrix3d::Zero();
  double area_sum = 0.0;
  for (std::size_t k = 0; k < count; ++k) {
    const Triangle& t = mesh.triangles[triangles.empty() ? k : triangles[k]];
    const Eigen::Vector3d a = mesh.positions[t[0]].cast<double>();
    const Eigen::Vector3d b = mesh.positions[t[1]].cast<double>();
    const Eigen::Vector3d c = mesh.positions[t[2]].cast<double>();
    for (auto v : t)
      if (!seen[v]) {
        seen[v] = true;
        points.push_back(mesh.positions[v]);
      }
    const double area = 0.5 * (b - a).cross(c - a).norm();
    const Eigen::Vector3d centroid = (a + b + c) / 3.0;
    mean += area * centroid;
    // Integral of x x^T over the triangle / area = (9 c c^T + a a^T + b b^T + c c^T) / 12.
    second += area / 12.0 * (9.0 * centroid * centroid.transpose() + a * a.transpose() +
                              b * b.transpose() + c * c.transpose());
    area_sum += area;
  }
  Eigen::Matrix3f axes = Eigen::Matrix3f::Identity();
  if (area_sum > 0.0) {
    mean /= area_sum;
    const Eigen::Matrix3d cov = second / area_sum - mean * mean.transpose();
    Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> solver(cov);
    if (solver.info() == Eigen::Success) axes = solver.eigenvectors().cast<float>();
  }
  axes = right_handed(axes);

  // 2. Volume-shrinking local rotation search, over the points that can be extreme; the
  //    extents are then taken over all of them (the box holds every point whatever Qhull's
  //    roundoff left out).
  const std::vector<Vec3> all_points = std::move(points);
  points = hull_candidates(all_points);
  Extent best = extent_along(points, axes);
  float best_volume = volume_of(best);
  float step = 0.2f;  // radians
  for (int it = 0; it < options.refine_iterations && step > 1e-4f; ++it) {
    bool improved = false;
    for (int axis = 0; axis < 3; ++axis) {
      for (float sign : {1.f, -1.f}) {
        const Eigen::Matrix3f trial =
            right_handed(Eigen::AngleAxisf(sign * step, axes.col(axis)).toRotationMatrix() * axes);
        const Extent e = extent_along(points, trial);
        const float v = volume_of(e);
        if (v < best_volume * (1.f - 1e-5f)) {
          best_volume = v;
          best = e;
          axes = trial;
          improved = true;
        }
      }
    }
    if (!improved) step *= 0.5f;
  }

  if (points.size() != all_points.size()) best = extent_along(all_points, axes);

  // 3. Centre, half extents, padding.
  Obb box;
  box.axes = axes;
  const Vec3 mid_local = 0.5f * (best.lo + best.hi);
  box.center = axes * mid_local;
  box.half = 0.5f * (best.hi - best.lo);
  const float pad = options.padding * 2.f * box.half.norm();
  const float min_half = 1e-6f * std::max(1.f, box.half.maxCoeff());
  box.half = (box.half.array() + pad).max(min_half).matrix();
  return box;
}

bool intersect_line_obb(const Obb& box, const Vec3& p, const Vec3& dir, LineBoxHit& hit) noexcept {
  const Vec3 o = box.to_local(p);
  const Vec3 d = box.axes.transpose() * dir;
  float t_enter = -std::numeric_limits<float>::infinity();
  float t_exit = std::numeric_limits<float>::infinity();
  int face = 0;
  for (int a = 0; a < 3; ++a) {
    if (std::fabs(d[a]) < 1e-12f) {
      if (o[a] < -box.half[a] || o[a] > box.half[a]) return false;
      continue;
    }
    const float inv = 1.f / d[a];
    float t0 = (-box.half[a] - o[a]) * inv;  // plane of face 2a (-a)
    float t1 = (box.half[a] - o[a]) * inv;   // plane of face 2a+1 (+a)
    int f0 = 2 * a, f1 = 2 * a + 1;
    if (t0 > t1) {
      std::swap(t0, t1);
      std::swap(f0, f1);
    }
    if (t0 > t_enter) {
      t_enter = t0;
      face = f0;
    }
    t_exit = std::min(t_exit, t1);
  }
  if (!(t_enter <= t_exit) || !std::isfinite(t_enter)) return false;
  hit.t_enter = t_enter;
  hit.t_exit = t_exit;
  hit.enter_face = face;
  return true;
}

std::string obb_problem(const Obb& box) {
  const float limit = 4.f * kMaxCoordinate;
  const auto show = [](float v) {
    char text[32];
    std::snprintf(text, sizeof text, "%g", double(v));
    return std::string(text);
  };
  for (int c = 0; c < 3; ++c) {
    if (!(std::fabs(box.center[c]) <= limit))
      return "centre " + show(box.center[c]) + " is not finite or beyond 4e15";
    if (!(box.half[c] >= 1e-30f && box.half[c] <= limit))
      return "half extent " + show(box.half[c]) + " is not a finite positive size (1e-30 to 4e15)";
    for (int r = 0; r < 3; ++r)
      if (!std::isfinite(box.axes(r, c))) return "axis value " + show(box.axes(r, c)) + " is not finite";
  }
  const Eigen::Matrix3f gram = box.axes.transpose() * box.axes - Eigen::Matrix3f::Identity();
  if (!(gram.cwiseAbs().maxCoeff() <= 1e-3f))
    return "axes are not orthonormal (|A^T A - I| = " + show(gram.cwiseAbs().maxCoeff()) + ")";
  if (!(box.axes.determinant() > 0.f)) return "axes are not right-handed";
  return {};
}

} // namespace hb
