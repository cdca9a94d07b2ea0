#pragma once
// A surface known only by scattered points with normals (the haptic box's samples around a
// query), seen as a local quadric height field: fitted to the points' heights and slopes
// (second-order exact), then met by a line. Used by the box's grazing settle
// (haptic_box.cpp, step 6a), where a first-order blend of the samples strays by the
// surface's curvature times a cell squared: measured on the smooth ellipsoid at m32 n16, the
// blend's crossing along the normal is off by 0.0014 cell (median, 0.004 at p99), the fit's
// by 0.00003 (0.0001), and a tangent-plane (Newton) step converges slowly near tangency where
// the quadric's own crossing does not.
#include "math/vec3.h"

namespace hb {

/// One point of a surface with its unit normal and a weight (>= 0; the caller's interpolation
/// weight: samples the caller would blend count more).
struct OrientedPoint {
  Vec3 point, normal;
  float weight = 0.f;
};

/// z = c0 + c1 x + c2 y + c3 x^2 + c4 x y + c5 y^2 in the frame (origin; e1, e2, axis), in
/// the caller's units; the outside is +axis.
struct LocalQuadric {
  Vec3 origin{Vec3::Zero()}, e1{Vec3::UnitX()}, e2{Vec3::UnitY()}, axis{Vec3::UnitZ()};
  double c[6] = {0, 0, 0, 0, 0, 0};
  /// The points the fit used (the others face away from the axis or weigh nothing).
  int used = 0;

  /// The unit normal (facing +axis) at the quadric's point above or below p.
  Vec3 normal_at(const Vec3& p) const noexcept;
  /// The line p + s l's height above the quadric along the axis, as a s^2 + b s + c.
  struct Height {
    double a, b, c;
  };
  Height height_along(const Vec3& p, const Vec3& l) const noexcept;
  /// Where the line p + s l (l a unit vector) enters the quadric from outside (+axis side):
  /// the one root where the line goes inside; false when there is none (the line misses,
  /// touches or only leaves the quadric).
  bool entry(const Vec3& p, const Vec3& l, float& s) const noexcept;
};

/// Fits a LocalQuadric in the frame with origin `origin` and z along the unit `axis` to the
/// points' heights and to the slopes their normals give, each point weighted by
/// (weight + weight_floor) exp(-r^2 / 2 sigma^2) (r: its distance from the axis through the
/// origin). Points whose normal is within 78 degrees of perpendicular to the axis
/// (n . axis < 0.2) are left out. False (`out` untouched) when fewer than three points
/// remain, sigma is not positive or the fit is singular or not finite. Allocates nothing.
bool fit_local_quadric(const OrientedPoint* points, int count, const Vec3& origin, const Vec3& axis, float sigma,
                       float weight_floor, LocalQuadric& out) noexcept;

}  // namespace hb
