// Steps 6a and 6b of a raw box's query (haptic_box.cpp's overview): a blended crossing
// more than 37 degrees off the surface normal is met on a quadric fitted to the samples,
// across the surface when grazing (settle_grazing), on the line's own samples between 37
// and 53 degrees (refit_on_own_samples); a probe's query state keeps the last quadric
// (SettledQuadric). Instantiated for the three sample fetch policies finish() uses.
#include "box/haptic_box.h"
#include "box/haptic_box_located.h"
#include "box/sample_fetch.h"
#include "geometry/octahedral.h"
#include "geometry/surface_fit.h"
#include <algorithm>
#include <cmath>
#include <limits>

namespace hb {

// The surface points of steps 6a and 6b: the 16 samples of a located query (4 corners x 2 x 2
// directions) that hit, each with its hit point, unit normal and interpolation weight. Each
// corner's quad is read in one go through the fetch policy (a block record's header once), and
// the four directions are the same at every corner.
template <class Fetch>
int HapticBox::surface_points(const Fetch& fetch, Located<Fetch>& q, OrientedPoint out[16]) const noexcept {
  const int sub = int(q.sf / 3), sface = int(q.sf % 3);
  Vec3 dirs[4];
  for (int k = 0; k < 4; ++k)  // q.dir_w's order: (0,0), (1,0), (1,1), (0,1)
    dirs[k] = layout_.sample_direction(q.face, sub, sface, q.a0 + (k == 1 || k == 2 ? 1 : 0), q.b0 + (k >= 2 ? 1 : 0));
  int count = 0;
  for (int c = 0; c < 4; ++c) {
    const int i = q.i0 + (c == 1 || c == 2 ? 1 : 0), j = q.j0 + (c >= 2 ? 1 : 0);
    const float pw = (c == 1 || c == 2 ? q.d1 : 1.f - q.d1) * (c >= 2 ? q.d2 : 1.f - q.d2);
    const Vec3 origin = layout_.position_point(q.face, i, j);
    fetch.resolve(q.corners[c]);
    float t[4], u[4], v[4];
    const unsigned hits = fetch.quad(q.corners[c], t, u, v);
    for (int k = 0; k < 4; ++k) {
      if (!((hits >> k) & 1u) || !(t[k] >= 0.f)) continue;
      const Vec3 n = oct_decode_unnormalized(u[k], v[k]);
      out[count++] = {origin + t[k] * dirs[k], n / n.norm(), pw * q.dir_w[k]};
    }
  }
  return count;
}

namespace {
// The fits' reach (settle_grazing, refit_on_own_samples): a Gaussian of 0.4 position cells
// around the line, on top of the blend's own weights plus 0.1 (measured on grazing lines of
// the bumpy sphere, m32 n16 block-coded: 0.3 a little worse, 0.6 alike).
constexpr float kFitSigmaCells = 0.4f, kFitWeightFloor = 0.1f;

// A probe's last settled quadric (SettledQuadric), when the line from p1 + t l meets it
// within a tenth of a cell of its centre (lateral to its axis) and the blend's normal m
// agrees: its crossing and normal, no fit. A stateless query has none.
bool cross_kept_quadric(SettledQuadric* memo, const Vec3& p1, const Vec3& l, const Vec3& m, float cell, float t,
                        float& t0, float& nx, float& ny, float& nz) noexcept {
  // Within a cell of the blend's crossing too: a kept sheet the line meets farther on is not
  // taken for the nearer one the blend sees.
  constexpr float kMemoCells = 0.1f, kFromBlendCells = 1.f;
  if (!memo || !memo->valid || !(m.dot(memo->quadric.axis) > 0.95f)) return false;
  const LocalQuadric& mq = memo->quadric;
  float s = 0.f;
  if (!mq.entry(p1 + t * l, l, s) || !(std::fabs(s) <= kFromBlendCells * cell)) return false;
  const Vec3 at = p1 + (t + s) * l, r = at - mq.origin;
  const Vec3 lateral = r - r.dot(mq.axis) * mq.axis;
  const Vec3 n = mq.normal_at(at);
  if (!(lateral.squaredNorm() < (kMemoCells * cell) * (kMemoCells * cell)) || !(n.dot(l) < 0.f)) return false;
  ++memo->reused;
  t0 = t + s, nx = n.x(), ny = n.y(), nz = n.z();
  return true;
}
} // namespace

// Step 6a. Along a line that meets the surface at a grazing angle, the blend of parallel rays
// from neighbouring position points is ill-conditioned: their hits lie far apart on the
// surface (a position cell over the cosine), so t0 strays by the surface's curvature times
// that distance squared, over the cosine again (without this step, every slide tick of the
// smooth ellipsoid and the bumpy sphere felt against exact had |n . l| < 0.55, none above).
// The line's crossing is found instead on the surface itself, seen across: from the
// point y on the line, the 16 samples of a segment across the surface along -n (where they
// are well-conditioned) give their hits and normals, and a quadric height field fitted to
// them (surface_fit.h: second-order exact, where a blend is first-order) is met by the line;
// its crossing is the next y, the quadric's normal there the next n. A line that passes the
// quadric moves to where it comes closest; one inside a quadric it does not enter (a hollow
// curving around it) steps back a cell; a step beyond what the fits have shown outside and
// inside bisects that bracket. Near tangency a tangent-plane (Newton) step
// converges slowly and from one side (on a convex surface it stops short: measured before,
// the crossing 0.1-0.6 mm early and the normal a degree steep); the quadric's crossing
// settles in two to four fits. Settled when a step moves y by less than kSettledCells
// position cells along l; otherwise (no fit, a far crossing, no convergence) the blend
// stands (false). Same table; a probe's query state keeps the quadric settled on
// (cross_kept_quadric); only grazing answers pay.
template <class Fetch>
bool HapticBox::settle_grazing(const Fetch& fetch, float p1x, float p1y, float p1z, float lx, float ly, float lz,
                               float& t0, float& nx, float& ny, float& nz) const noexcept {
  // At most 8 fits; the surface is fitted from the samples of a segment 3 position cells
  // either side of the line's point; settled when a step moves less than 0.05 cell along l
  // (a quadric step that small lands well within the fit's reach: on 70,000 lines of each
  // smooth model as accurate as 0.01 and 0.003, with one fit fewer); a step farther than 8
  // cells is no crossing.
  constexpr int kSteps = 8;
  constexpr float kReachCells = 3.f, kFarthestCells = 8.f, kSettledCells = 0.05f;
  const float cell = position_cell();
  const float reach = kReachCells * cell;
  // The surface around y, seen along m: a quadric fitted to the samples of the segment across,
  // within that segment (no other sheet).
  const auto fit = [&](const Vec3& y, const Vec3& m, LocalQuadric& quadric) {
    Located<Fetch> q;
    if (!locate(fetch, Segment{y + reach * m, y - reach * m}, q)) return false;
    OrientedPoint points[16];
    const int count = surface_points(fetch, q, points);
    return fit_local_quadric(points, count, y, m, kFitSigmaCells * cell, kFitWeightFloor, quadric) &&
           std::fabs(quadric.c[0]) <= double(reach);
  };
  const Vec3 p1(p1x, p1y, p1z), l(lx, ly, lz);
  float t = t0;
  Vec3 m(nx, ny, nz);
  SettledQuadric* memo = fetch.settled();
  if (cross_kept_quadric(memo, p1, l, m, cell, t, t0, nx, ny, nz)) return true;
  // What the fits said so far: the line is outside at t_out, inside at t_in (the fit's height
  // at y along m: the surface below y, or above it). A step that would leave that bracket
  // bisects it instead.
  float t_out = -std::numeric_limits<float>::infinity(), t_in = std::numeric_limits<float>::infinity();
  for (int step = 0; step < kSteps; ++step) {
    const Vec3 y = p1 + t * l;
    LocalQuadric quadric;
    if (!fit(y, m, quadric)) return false;
    const bool inside = quadric.c[0] > 0.0;
    if (inside) t_in = std::min(t_in, t);
    else t_out = std::max(t_out, t);
    float s = 0.f;
    const bool enters = quadric.entry(y, l, s) && std::fabs(s) <= kFarthestCells * cell;
    if (!enters) {
      if (inside) {
        // Inside a fit the line does not enter here (a hollow between bumps curving around
        // it): the line came in behind; step back a cell.
        s = -cell;
      } else {
        // The line passes the fitted surface: go to where it comes closest and fit there.
        // When that is here already, it passes within the fit's error: nothing to settle on.
        const LocalQuadric::Height h = quadric.height_along(y, l);
        if (!(h.a > 0.0)) return false;
        s = float(-h.b / (2.0 * h.a));
        if (!(std::fabs(s) <= kFarthestCells * cell) || std::fabs(s) < kSettledCells * cell) return false;
      }
    }
    float next = t + s;
    const bool bracketed = t_out > -std::numeric_limits<float>::infinity() && t_in < std::numeric_limits<float>::infinity();
    if (bracketed && !(next > std::min(t_out, t_in) && next < std::max(t_out, t_in))) next = 0.5f * (t_out + t_in);
    const Vec3 at = p1 + next * l;
    m = quadric.normal_at(at);
    if (!(m.dot(l) < 0.f)) {
      if (enters) return false;
      m = quadric.normal_at(y);
    }
    const bool settled = enters && std::fabs(next - t) < kSettledCells * cell;
    t = next;
    if (settled) {
      t0 = t, nx = m.x(), ny = m.y(), nz = m.z();
      if (memo) memo->valid = true, memo->quadric = quadric;
      return true;
    }
  }
  return false;
}

// Step 6b. Between kGrazingCosine and kRefitCosine the blend is well conditioned but
// first-order: on the bumpy sphere's and the smooth ellipsoid's default boxes, lines 46-53
// degrees from the normal (|n . l| 0.6-0.7) were 0.03-0.1 mm off along l, felt at a light touch
// (under 0.75 N) on 1.1-1.5% of lines with |n . l| 0.6-1 without this step. One quadric
// fitted to the line's own 16 samples (no segment across: at such an angle they are
// well-conditioned) and met by the line puts them within the fit's error. False (the blend
// stands) without a fit, with a sample facing away (a crease) or without a crossing within a
// cell.
template <class Fetch>
bool HapticBox::refit_on_own_samples(const Fetch& fetch, const Located<Fetch>& q, const Vec3& p1, const Vec3& l,
                                     float& t0, float& nx, float& ny, float& nz) const noexcept {
  const float cell = position_cell();
  const Vec3 m(nx, ny, nz);
  SettledQuadric* memo = fetch.settled();
  if (cross_kept_quadric(memo, p1, l, m, cell, t0, t0, nx, ny, nz)) return true;
  Located<Fetch> own = q;
  OrientedPoint points[16];
  const int count = surface_points(fetch, own, points);
  const Vec3 y = p1 + t0 * l;
  LocalQuadric quadric;
  float s = 0.f;
  // Every sample must face along the blend's normal: one that does not (left out of the fit)
  // sees another face across a crease, where the fit would extend one wall past it (the
  // stability suite's crisp 60 degree groove: ripple 0.02 -> 0.52 without this test).
  if (!fit_local_quadric(points, count, y, m, kFitSigmaCells * cell, kFitWeightFloor, quadric) ||
      quadric.used != count || !quadric.entry(y, l, s) || !(std::fabs(s) < cell))
    return false;
  const Vec3 n = quadric.normal_at(y + s * l);
  if (!(n.dot(l) < 0.f)) return false;
  t0 += s, nx = n.x(), ny = n.y(), nz = n.z();
  if (memo) memo->valid = true, memo->quadric = quadric;
  return true;
}

template int HapticBox::surface_points(const box_query::RawFetch&, Located<box_query::RawFetch>&,
                                        OrientedPoint[16]) const noexcept;
template int HapticBox::surface_points(const box_query::CodecFetch<HaarTable>&,
                                        Located<box_query::CodecFetch<HaarTable>>&, OrientedPoint[16]) const noexcept;
template int HapticBox::surface_points(const box_query::CodecFetch<BlockTable>&,
                                        Located<box_query::CodecFetch<BlockTable>>&, OrientedPoint[16]) const noexcept;
#define HB_SETTLE_FOR(Fetch)                                                                                        \
  template bool HapticBox::settle_grazing(const Fetch&, float, float, float, float, float, float, float&, float&,   \
                                          float&, float&) const noexcept;                                          \
  template bool HapticBox::refit_on_own_samples(const Fetch&, const Located<Fetch>&, const Vec3&, const Vec3&, float&, \
                                                float&, float&, float&) const noexcept;
HB_SETTLE_FOR(box_query::RawFetch)
HB_SETTLE_FOR(box_query::CodecFetch<HaarTable>)
HB_SETTLE_FOR(box_query::CodecFetch<BlockTable>)
#undef HB_SETTLE_FOR

} // namespace hb
