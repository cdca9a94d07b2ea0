// fit_local_quadric and LocalQuadric (surface_fit.h):
//  1. A frame (e1, e2, axis) at the origin; every point's lateral position (x, y) and height
//     z, scaled by 1 / sigma so the normal equations are well conditioned whatever the units.
//  2. Weighted least squares over 6 coefficients: per point one row for the height and two
//     for the slopes (-n.e1 / n.axis, -n.e2 / n.axis), the slope rows at the same weight
//     (a slope error over sigma counts as a height error of the same size).
//  3. Solved in double (6 x 6 Cholesky) and scaled back to the caller's units.
//  4. entry(): the line in the frame, z(s) - Q(x(s), y(s)) = A s^2 + B s + C; the root where
//     that decreases (the line going inside), in the cancellation-free form.
#include "geometry/surface_fit.h"
#include <Eigen/Dense>
#include <cmath>

namespace hb {

namespace {
// The height field's gradient at (x, y) of the frame.
void gradient(const double c[6], double x, double y, double& gx, double& gy) noexcept {
  gx = c[1] + 2.0 * c[3] * x + c[4] * y;
  gy = c[2] + c[4] * x + 2.0 * c[5] * y;
}
}  // namespace

Vec3 LocalQuadric::normal_at(const Vec3& p) const noexcept {
  const Vec3 r = p - origin;
  double gx, gy;
  gradient(c, double(r.dot(e1)), double(r.dot(e2)), gx, gy);
  const Vec3 n = axis - float(gx) * e1 - float(gy) * e2;
  return n / n.norm();
}

LocalQuadric::Height LocalQuadric::height_along(const Vec3& p, const Vec3& l) const noexcept {
  const Vec3 r = p - origin;
  const double x0 = double(r.dot(e1)), y0 = double(r.dot(e2)), z0 = double(r.dot(axis));
  const double lx = double(l.dot(e1)), ly = double(l.dot(e2)), lz = double(l.dot(axis));
  const double q0 = c[0] + c[1] * x0 + c[2] * y0 + c[3] * x0 * x0 + c[4] * x0 * y0 + c[5] * y0 * y0;
  double gx, gy;
  gradient(c, x0, y0, gx, gy);
  return {-(c[3] * lx * lx + c[4] * lx * ly + c[5] * ly * ly), lz - (gx * lx + gy * ly), z0 - q0};
}

bool LocalQuadric::entry(const Vec3& p, const Vec3& l, float& s) const noexcept {
  const Height h = height_along(p, l);
  const double a = h.a, b = h.b, cc = h.c;
  // f(s) = a s^2 + b s + cc, f'(s) = 2 a s + b: at the roots (-b -+ root) / 2a, f' = -+root,
  // so the entering root is (-b - root) / 2a = 2 cc / (root - b) (no cancellation). A
  // tangent line (root 0) does not enter.
  const double disc = b * b - 4.0 * a * cc;
  if (!(disc > 0.0)) return false;
  const double root = std::sqrt(disc);
  if (!(root - b > 0.0)) return false;  // b >= root: a plane-like surface the line leaves
  const double best = 2.0 * cc / (root - b);
  if (!std::isfinite(best)) return false;
  s = float(best);
  return true;
}

bool fit_local_quadric(const OrientedPoint* points, int count, const Vec3& origin, const Vec3& axis, float sigma,
                       float weight_floor, LocalQuadric& out) noexcept {
  if (!(sigma > 0.f) || count < 3) return false;
  const Vec3 e1 = axis.unitOrthogonal(), e2 = axis.cross(e1);
  const double inv_sigma = 1.0 / double(sigma);
  // The normal equations' entries are weighted moments M(p, q) = sum w x^p y^q (p + q <= 4)
  // of the rows f = (1, x, y, x^2, xy, y^2), fx = (0, 1, 0, 2x, y, 0), fy = (0, 0, 1, 0, x, 2y):
  // fifteen sums a point instead of three 6 x 6 outer products (a fit was most of a grazing
  // query's time).
  double m[5][5] = {};  // m[p][q], p + q <= 4
  Eigen::Matrix<double, 6, 1> b = Eigen::Matrix<double, 6, 1>::Zero();
  int used = 0;
  for (int i = 0; i < count; ++i) {
    const OrientedPoint& p = points[i];
    const double nz = double(p.normal.dot(axis));
    if (!(nz >= 0.2)) continue;
    const Vec3 r = p.point - origin;
    const double x = double(r.dot(e1)) * inv_sigma, y = double(r.dot(e2)) * inv_sigma;
    const double z = double(r.dot(axis)) * inv_sigma;
    const double gx = -double(p.normal.dot(e1)) / nz, gy = -double(p.normal.dot(e2)) / nz;
    const double w = double((p.weight + weight_floor) * std::exp(-0.5f * float(x * x + y * y)));  // float exp: cheaper
    if (!(w > 0.0)) continue;
    double xp = w;  // w x^p
    for (int pp = 0; pp <= 4; ++pp) {
      double t = xp;  // w x^p y^q
      for (int q = 0; q + pp <= 4; ++q) {
        m[pp][q] += t;
        t *= y;
      }
      xp *= x;
    }
    b[0] += w * z;
    b[1] += w * (z * x + gx);
    b[2] += w * (z * y + gy);
    b[3] += w * (z * x * x + 2.0 * x * gx);
    b[4] += w * (z * x * y + y * gx + x * gy);
    b[5] += w * (z * y * y + 2.0 * y * gy);
    ++used;
  }
  // f's monomials (p, q), and fx's and fy's as coefficient times monomial.
  static constexpr int fe[6][2] = {{0, 0}, {1, 0}, {0, 1}, {2, 0}, {1, 1}, {0, 2}};
  struct Term { int i; double c; int p, q; };
  static constexpr Term gxt[3] = {{1, 1.0, 0, 0}, {3, 2.0, 1, 0}, {4, 1.0, 0, 1}};
  static constexpr Term gyt[3] = {{2, 1.0, 0, 0}, {4, 1.0, 1, 0}, {5, 2.0, 0, 1}};
  Eigen::Matrix<double, 6, 6> a;
  for (int i = 0; i < 6; ++i)
    for (int j = 0; j < 6; ++j) a(i, j) = m[fe[i][0] + fe[j][0]][fe[i][1] + fe[j][1]];
  for (const Term* g : {gxt, gyt})
    for (int u = 0; u < 3; ++u)
      for (int v = 0; v < 3; ++v) a(g[u].i, g[v].i) += g[u].c * g[v].c * m[g[u].p + g[v].p][g[u].q + g[v].q];
  if (used < 3) return false;
  // Cholesky by hand (6 x 6, symmetric positive definite when the points span the quadric):
  // Eigen's LDLT with its condition estimate cost more than the rest of a fit. A pivot below
  // 1e-12 of the largest diagonal entry is a singular fit.
  double l[6][6] = {};
  const double scale = a.diagonal().maxCoeff();
  if (!(scale > 0.0)) return false;
  for (int j = 0; j < 6; ++j) {
    double d = a(j, j);
    for (int k = 0; k < j; ++k) d -= l[j][k] * l[j][k];
    if (!(d > 1e-12 * scale)) return false;
    l[j][j] = std::sqrt(d);
    for (int i = j + 1; i < 6; ++i) {
      double e = a(i, j);
      for (int k = 0; k < j; ++k) e -= l[i][k] * l[j][k];
      l[i][j] = e / l[j][j];
    }
  }
  Eigen::Matrix<double, 6, 1> c;
  for (int i = 0; i < 6; ++i) {  // L z = b
    double e = b[i];
    for (int k = 0; k < i; ++k) e -= l[i][k] * c[k];
    c[i] = e / l[i][i];
  }
  for (int i = 5; i >= 0; --i) {  // L^T c = z
    double e = c[i];
    for (int k = i + 1; k < 6; ++k) e -= l[k][i] * c[k];
    c[i] = e / l[i][i];
  }
  if (!c.allFinite()) return false;
  const double s = double(sigma);
  out.origin = origin, out.e1 = e1, out.e2 = e2, out.axis = axis;
  // z / sigma = c0 + c1 x / sigma + ... + c3 (x / sigma)^2 ...: back to the caller's units.
  out.c[0] = c[0] * s, out.c[1] = c[1], out.c[2] = c[2];
  out.c[3] = c[3] / s, out.c[4] = c[4] / s, out.c[5] = c[5] / s;
  return true;
}

}  // namespace hb
