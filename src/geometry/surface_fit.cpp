// fit_local_quadric and LocalQuadric (surface_fit.h):
//  1. A frame (e1, e2, axis) at the origin; every point's lateral position (x, y) and height
//     z, scaled by 1 / sigma so the normal equations are well conditioned whatever the units.
//  2. Weighted least squares over 6 coefficients: per point one row for the height and two
//     for the slopes (-n.e1 / n.axis, -n.e2 / n.axis), the slope rows at the same weight
//     (a slope error over sigma counts as a height error of the same size).
//  3. The sums four points side by side in float (accumulate_moments), solved in double
//     (6 x 6 LDL^T) and scaled back to the caller's units (four lanes halve a fit's time).
//  4. entry(): the line in the frame, z(s) - Q(x(s), y(s)) = A s^2 + B s + C; the root where
//     that decreases (the line going inside), in the cancellation-free form.
#include "geometry/surface_fit.h"
#include <emmintrin.h>
#include <algorithm>
#include <cmath>

namespace hb {

namespace {
// e^x for x <= 0, four at a time (Cephes' expf: x = n ln 2 + g, e^g by its degree-5
// polynomial, 2^n into the exponent; within 2 ulp, 0 below -87). A fit's Gaussian weights:
// libm's expf, one at a time, was a fifth of a fit.
inline __m128 exp_negative(__m128 x) noexcept {
  x = _mm_max_ps(x, _mm_set1_ps(-87.f));
  const __m128 fx = _mm_add_ps(_mm_mul_ps(x, _mm_set1_ps(1.44269504088896341f)), _mm_set1_ps(0.5f));
  __m128i n = _mm_cvttps_epi32(fx);
  __m128 nf = _mm_cvtepi32_ps(n);
  const __m128 over = _mm_and_ps(_mm_cmpgt_ps(nf, fx), _mm_set1_ps(1.f));  // floor for negatives
  nf = _mm_sub_ps(nf, over);
  n = _mm_cvttps_epi32(nf);
  const __m128 g = _mm_sub_ps(_mm_sub_ps(x, _mm_mul_ps(nf, _mm_set1_ps(0.693359375f))),
                              _mm_mul_ps(nf, _mm_set1_ps(-2.12194440e-4f)));
  __m128 y = _mm_set1_ps(1.9875691500e-4f);
  y = _mm_add_ps(_mm_mul_ps(y, g), _mm_set1_ps(1.3981999507e-3f));
  y = _mm_add_ps(_mm_mul_ps(y, g), _mm_set1_ps(8.3334519073e-3f));
  y = _mm_add_ps(_mm_mul_ps(y, g), _mm_set1_ps(4.1665795894e-2f));
  y = _mm_add_ps(_mm_mul_ps(y, g), _mm_set1_ps(1.6666665459e-1f));
  y = _mm_add_ps(_mm_mul_ps(y, g), _mm_set1_ps(5.0000001201e-1f));
  y = _mm_add_ps(_mm_add_ps(_mm_mul_ps(_mm_mul_ps(y, g), g), g), _mm_set1_ps(1.f));
  const __m128 pow2n = _mm_castsi128_ps(_mm_slli_epi32(_mm_add_epi32(n, _mm_set1_epi32(127)), 23));
  return _mm_mul_ps(y, pow2n);
}

// The sums of the normal equations, four points side by side in float (the points' offsets
// over sigma are of order one: float sums of 16 lose nothing the fit's own error shows), each
// lane's total added in double in lane order.
struct Moments {
  double m[15];  // M(p, q) in the order (0,0..4), (1,0..3), (2,0..2), (3,0..1), (4,0)
  double b[6];
};
int accumulate_moments(const OrientedPoint* points, int count, const Vec3& origin, const Vec3& e1, const Vec3& e2,
                       const Vec3& axis, float inv_sigma, float weight_floor, Moments& out) noexcept {
  __m128 m[15], b[6];
  for (__m128& v : m) v = _mm_setzero_ps();
  for (__m128& v : b) v = _mm_setzero_ps();
  const auto dot = [](const __m128 v[3], const Vec3& e) {
    return _mm_add_ps(_mm_add_ps(_mm_mul_ps(v[0], _mm_set1_ps(e.x())), _mm_mul_ps(v[1], _mm_set1_ps(e.y()))),
                      _mm_mul_ps(v[2], _mm_set1_ps(e.z())));
  };
  int used = 0;
  for (int first = 0; first < count; first += 4) {
    // Gathered lane by lane in registers (scalar stores read back as a vector stall on
    // store forwarding).
    const OrientedPoint* p[4];
    float wt[4];
    for (int k = 0; k < 4; ++k) {
      const bool real = first + k < count;
      p[k] = points + (real ? first + k : first);
      wt[k] = real ? p[k]->weight + weight_floor : 0.f;
    }
    const auto lanes = [&](auto get) { return _mm_setr_ps(get(*p[0]), get(*p[1]), get(*p[2]), get(*p[3])); };
    const __m128 rv[3] = {_mm_sub_ps(lanes([](const OrientedPoint& q) { return q.point.x(); }), _mm_set1_ps(origin.x())),
                          _mm_sub_ps(lanes([](const OrientedPoint& q) { return q.point.y(); }), _mm_set1_ps(origin.y())),
                          _mm_sub_ps(lanes([](const OrientedPoint& q) { return q.point.z(); }), _mm_set1_ps(origin.z()))};
    const __m128 nv[3] = {lanes([](const OrientedPoint& q) { return q.normal.x(); }),
                          lanes([](const OrientedPoint& q) { return q.normal.y(); }),
                          lanes([](const OrientedPoint& q) { return q.normal.z(); })};
    const __m128 sig = _mm_set1_ps(inv_sigma);
    const __m128 x = _mm_mul_ps(dot(rv, e1), sig), y = _mm_mul_ps(dot(rv, e2), sig), z = _mm_mul_ps(dot(rv, axis), sig);
    const __m128 nz = dot(nv, axis);
    const __m128 facing = _mm_cmpge_ps(nz, _mm_set1_ps(0.2f));  // false for NaN too
    const __m128 inv_nz = _mm_div_ps(_mm_set1_ps(-1.f), _mm_or_ps(_mm_and_ps(facing, nz), _mm_andnot_ps(facing, _mm_set1_ps(1.f))));
    const __m128 gx = _mm_mul_ps(dot(nv, e1), inv_nz), gy = _mm_mul_ps(dot(nv, e2), inv_nz);
    const __m128 r2 = _mm_add_ps(_mm_mul_ps(x, x), _mm_mul_ps(y, y));
    __m128 w = _mm_mul_ps(_mm_setr_ps(wt[0], wt[1], wt[2], wt[3]), exp_negative(_mm_mul_ps(_mm_set1_ps(-0.5f), r2)));
    const __m128 take = _mm_and_ps(facing, _mm_cmpgt_ps(w, _mm_setzero_ps()));
    w = _mm_and_ps(take, w);
    used += __builtin_popcount(unsigned(_mm_movemask_ps(take)));
    const __m128 x2 = _mm_mul_ps(x, x), y2 = _mm_mul_ps(y, y);
    const __m128 wx[5] = {w, _mm_mul_ps(w, x), _mm_mul_ps(w, x2), _mm_mul_ps(_mm_mul_ps(w, x2), x), _mm_mul_ps(_mm_mul_ps(w, x2), x2)};
    const __m128 yq[5] = {_mm_set1_ps(1.f), y, y2, _mm_mul_ps(y2, y), _mm_mul_ps(y2, y2)};
    int at = 0;
    for (int pp = 0; pp <= 4; ++pp)
      for (int q = 0; q + pp <= 4; ++q, ++at) m[at] = _mm_add_ps(m[at], _mm_mul_ps(wx[pp], yq[q]));
    // Zero where not taken (a NaN slope of a point facing away must not reach the sums).
    const __m128 wz = _mm_mul_ps(w, z), wgx = _mm_and_ps(take, _mm_mul_ps(w, gx)), wgy = _mm_and_ps(take, _mm_mul_ps(w, gy));
    const __m128 two = _mm_set1_ps(2.f);
    b[0] = _mm_add_ps(b[0], wz);
    b[1] = _mm_add_ps(b[1], _mm_add_ps(_mm_mul_ps(wz, x), wgx));
    b[2] = _mm_add_ps(b[2], _mm_add_ps(_mm_mul_ps(wz, y), wgy));
    b[3] = _mm_add_ps(b[3], _mm_add_ps(_mm_mul_ps(wz, x2), _mm_mul_ps(two, _mm_mul_ps(x, wgx))));
    b[4] = _mm_add_ps(b[4], _mm_add_ps(_mm_mul_ps(_mm_mul_ps(wz, x), y), _mm_add_ps(_mm_mul_ps(y, wgx), _mm_mul_ps(x, wgy))));
    b[5] = _mm_add_ps(b[5], _mm_add_ps(_mm_mul_ps(wz, y2), _mm_mul_ps(two, _mm_mul_ps(y, wgy))));
  }
  const auto total = [](__m128 v) {
    alignas(16) float lane[4];
    _mm_store_ps(lane, v);
    return (double(lane[0]) + double(lane[1])) + (double(lane[2]) + double(lane[3]));
  };
  for (int k = 0; k < 15; ++k) out.m[k] = total(m[k]);
  for (int k = 0; k < 6; ++k) out.b[k] = total(b[k]);
  return used;
}

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
  Moments mo;
  const int used = accumulate_moments(points, count, origin, e1, e2, axis, float(inv_sigma), weight_floor, mo);
  const double* b = mo.b;
  double m[5][5] = {};  // M(p, q), p + q <= 4, from accumulate_moments' order
  for (int pp = 0, at = 0; pp <= 4; ++pp)
    for (int q = 0; q + pp <= 4; ++q, ++at) m[pp][q] = mo.m[at];
  // f's monomials (p, q), and fx's and fy's as coefficient times monomial.
  static constexpr int fe[6][2] = {{0, 0}, {1, 0}, {0, 1}, {2, 0}, {1, 1}, {0, 2}};
  struct Term { int i; double c; int p, q; };
  static constexpr Term gxt[3] = {{1, 1.0, 0, 0}, {3, 2.0, 1, 0}, {4, 1.0, 0, 1}};
  static constexpr Term gyt[3] = {{2, 1.0, 0, 0}, {4, 1.0, 1, 0}, {5, 2.0, 0, 1}};
  double a[6][6];
  for (int i = 0; i < 6; ++i)
    for (int j = 0; j < 6; ++j) a[i][j] = m[fe[i][0] + fe[j][0]][fe[i][1] + fe[j][1]];
  for (int u = 0; u < 3; ++u)
    for (int v = 0; v < 3; ++v) {
      a[gxt[u].i][gxt[v].i] += gxt[u].c * gxt[v].c * m[gxt[u].p + gxt[v].p][gxt[u].q + gxt[v].q];
      a[gyt[u].i][gyt[v].i] += gyt[u].c * gyt[v].c * m[gyt[u].p + gyt[v].p][gyt[u].q + gyt[v].q];
    }
  if (used < 3) return false;
  // LDL^T by hand (6 x 6, symmetric positive definite when the points span the quadric; no
  // square roots, one division a pivot): Eigen's LDLT with its condition estimate cost more
  // than the rest of a fit. A pivot below 1e-12 of the largest diagonal entry is a singular fit.
  double l[6][6] = {}, dia[6], inv[6];
  double scale = a[0][0];
  for (int j = 1; j < 6; ++j) scale = std::max(scale, a[j][j]);
  if (!(scale > 0.0)) return false;
  for (int j = 0; j < 6; ++j) {
    double v[6];  // l[j][k] d[k]
    double d = a[j][j];
    for (int k = 0; k < j; ++k) {
      v[k] = l[j][k] * dia[k];
      d -= l[j][k] * v[k];
    }
    if (!(d > 1e-12 * scale)) return false;
    dia[j] = d;
    inv[j] = 1.0 / d;
    for (int i = j + 1; i < 6; ++i) {
      double e = a[i][j];
      for (int k = 0; k < j; ++k) e -= l[i][k] * v[k];
      l[i][j] = e * inv[j];
    }
  }
  double c[6];
  for (int i = 0; i < 6; ++i) {  // L y = b
    double e = b[i];
    for (int k = 0; k < i; ++k) e -= l[i][k] * c[k];
    c[i] = e;
  }
  for (int i = 0; i < 6; ++i) c[i] *= inv[i];  // D z = y
  for (int i = 5; i >= 0; --i) {  // L^T c = z
    double e = c[i];
    for (int k = i + 1; k < 6; ++k) e -= l[k][i] * c[k];
    c[i] = e;
  }
  for (double v : c)
    if (!std::isfinite(v)) return false;
  const double s = double(sigma);
  out.origin = origin, out.e1 = e1, out.e2 = e2, out.axis = axis;
  out.used = used;
  // z / sigma = c0 + c1 x / sigma + ... + c3 (x / sigma)^2 ...: back to the caller's units.
  out.c[0] = c[0] * s, out.c[1] = c[1], out.c[2] = c[2];
  out.c[3] = c[3] / s, out.c[4] = c[4] / s, out.c[5] = c[5] / s;
  return true;
}

}  // namespace hb
