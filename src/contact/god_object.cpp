// The proxy (god-object).
// 1. The stylus query decides contact (the project's definition). None: the proxy is free.
// 2. A new contact puts the proxy just before the stylus's surface point.
// 3. solve(): up to max_queries times: the target is the point nearest the tip in front of
//    the planes found so far (an active set over at most 3 planes); a query from the proxy to
//    the target either reaches it (done) or meets a surface: the proxy stops just in front of
//    it and the surface's plane joins the constraints (a plane nearly parallel to one already
//    found replaces it).
// 4. No plane found although the stylus touches (the proxy slipped past the surface): put it
//    back at the stylus's surface point and solve again; still none: the penalty answer.
// 5. Force k (proxy - tip).
#include "contact/god_object.h"
#include "errors.h"
#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <limits>

namespace hb {
namespace {

using ProxyVec = Eigen::Vector3d;

struct ProxyPlane {
  ProxyVec n;       // unit, the free side
  double c;   // n . x >= c in front
};

// The point of {x : n_i . x >= c_i} nearest g: the nearest feasible among the projections of g
// on the intersections of every subset of the planes (the true projection is one of them).
bool proxy_nearest_feasible(const ProxyPlane* planes, int count, const ProxyVec& g, double tolerance, ProxyVec& out) noexcept {
  double best = std::numeric_limits<double>::infinity();
  for (int mask = 0; mask < (1 << count); ++mask) {
    int idx[3], k = 0;
    for (int i = 0; i < count; ++i)
      if (mask & (1 << i)) idx[k++] = i;
    ProxyVec x = g;
    if (k == 1) {
      const ProxyPlane& p = planes[idx[0]];
      x = g + (p.c - p.n.dot(g)) * p.n;
    } else if (k == 2) {
      const ProxyPlane &a = planes[idx[0]], &b = planes[idx[1]];
      const double ab = a.n.dot(b.n), det = 1.0 - ab * ab;
      if (det < 1e-8) continue;
      const double ra = a.c - a.n.dot(g), rb = b.c - b.n.dot(g);
      const double la = (ra - ab * rb) / det, lb = (rb - ab * ra) / det;
      x = g + la * a.n + lb * b.n;
    } else if (k == 3) {
      Eigen::Matrix3d m;
      m.row(0) = planes[idx[0]].n.transpose();
      m.row(1) = planes[idx[1]].n.transpose();
      m.row(2) = planes[idx[2]].n.transpose();
      if (std::fabs(m.determinant()) < 1e-6) continue;
      x = m.inverse() * ProxyVec(planes[idx[0]].c, planes[idx[1]].c, planes[idx[2]].c);
    }
    bool feasible = true;
    for (int i = 0; i < count && feasible; ++i) feasible = planes[i].n.dot(x) >= planes[i].c - tolerance;
    const double d = (x - g).squaredNorm();
    if (feasible && d < best) best = d, out = x;
  }
  return best < std::numeric_limits<double>::infinity();
}

// The normal of a hit's constraint plane: the face's where the answerer knows it. The shaded
// normal's plane through the point is tilted against the facet it is on (by several degrees
// on the armadillo), so a path along it meets that facet within a few clearances; each such
// grazing hit made a plane, and the proxy crept along the crossings of those planes at rest
// instead of settling, chaotically enough that the box's and exact's proxies parted.
ProxyVec plane_normal(const Contact& c) noexcept {
  return (c.face_normal.squaredNorm() > 0.f ? c.face_normal : c.normal).cast<double>();
}

} // namespace

const char* to_string(ContactLaw law) noexcept { return law == ContactLaw::proxy ? "proxy" : "penalty"; }

ContactLaw contact_law(const std::string& name) {
  if (name == "penalty") return ContactLaw::penalty;
  if (name == "proxy") return ContactLaw::proxy;
  throw InvalidInput("contact law '" + name + "': expected penalty or proxy");
}

int GodObject::solve(const Vec3& goal_f, const ForceLaw& law, float clearance_f, const Vec3& l,
                     float stylus_length) noexcept {
  const double clearance = clearance_f;
  const ProxyVec goal = goal_f.cast<double>();
  ProxyPlane planes[3];
  int count = 0;
  ProxyVec p = proxy_.cast<double>();
  for (int q = 0; q < options_.max_queries; ++q) {
    ProxyVec target = goal;
    if (!proxy_nearest_feasible(planes, count, goal, 0.01 * clearance, target)) break;
    const ProxyVec d = target - p;
    const double len = d.norm();
    if (!(len > 1e-3 * clearance)) break;  // there
    Contact c = query_->query(Segment{p.cast<float>(), target.cast<float>()}, law);
    ++stats_.queries;
    const ProxyVec dir = d / len;
    bool by_stylus = false;
    if (!c.contact && stylus_length > 0.f) {
      // The path is free, but a path that grazes a wall (sliding along one wall of a crease
      // into the other) is the least reliable question for an approximate answerer; the stylus
      // ending at the target is the question every answerer is made for. A wall it meets more
      // than two clearances in front of the target is a constraint too.
      const Vec3 t = target.cast<float>();
      c = query_->query(Segment{t - l * stylus_length, t}, law);
      ++stats_.queries;
      by_stylus = c.contact && plane_normal(c).dot(c.point.cast<double>() - target) > 2.0 * clearance;
      if (!by_stylus) c.contact = false;
    }
    if (!c.contact) {
      p = target;
      break;
    }
    ProxyVec n = plane_normal(c);
    // A front-face crossing met at a grazing angle, or whose shaded normal does not oppose the
    // motion (an answer without the face's normal; thin sheets): the plane must still stop it.
    if (!by_stylus && !(n.dot(dir) < -0.05)) n = (n - (n.dot(dir) + 0.05) * dir).normalized();
    if (!n.allFinite()) break;
    const ProxyVec at = c.point.cast<double>();
    const ProxyPlane plane{n, n.dot(at) + clearance};
    int slot = count;
    for (int i = 0; i < count; ++i)
      if (planes[i].n.dot(n) > 0.9999) slot = i;
    // Back along the way just travelled (free of surfaces: the query met none before `at`)
    // until `clearance` in front of the new plane; the planes found before hold there too
    // (p and the target satisfy them). Stepping off along the normal instead may step behind
    // a wall not found yet, at a crease.
    if (by_stylus) {  // up to the plane along the path (the hit is not on it)
      const double along = n.dot(dir);
      if (along < 0.0) p += std::min(std::max((plane.c - n.dot(p)) / along, 0.0), len) * dir;
    } else {
      const double t_hit = std::min(std::max((at - p).dot(dir), 0.0), len);
      p += std::max(0.0, t_hit - clearance / -n.dot(dir)) * dir;
    }
    if (slot == 3) break;  // a fourth plane: stop in front of it
    planes[slot] = plane;
    if (slot == count) ++count;
  }
  rest_normal_ = Vec3::Zero();
  for (int i = 0; i < count; ++i) rest_normal_ += planes[i].n.cast<float>();
  if (rest_normal_.squaredNorm() > 0.f) rest_normal_.normalize();
  if (p.allFinite()) proxy_ = p.cast<float>();
  return count;
}

Contact GodObject::step(const Segment& probe, const ForceLaw& law) noexcept {
  ++stats_.ticks;
  const Contact stylus = query_->query(probe, law);
  if (!stylus.contact) {
    in_contact_ = false;
    planes_ = 0;
    proxy_ = probe.end;
    return Contact{};
  }
  ++stats_.contact_ticks;
  const float clearance = options_.clearance_m / law.metres_per_unit;
  const Vec3 delta = probe.end - probe.start;
  const float length = delta.norm();
  const Vec3 l = length > 0.f ? Vec3(delta / length) : Vec3(-stylus.normal);
  const auto seed = [&] { proxy_ = stylus.point - l * clearance; };
  if (!in_contact_) {
    seed();
    ++stats_.seeds;
    in_contact_ = true;
  }
  int planes = solve(probe.end, law, clearance, l, length);
  if (planes == 0) {
    ++stats_.reseeds;
    seed();
    planes = solve(probe.end, law, clearance, l, length);
  }
  if (planes == 0) {
    ++stats_.fallbacks;
    in_contact_ = false;
    planes_ = 0;
    return stylus;
  }
  planes_ = planes;
  if (std::uint64_t(planes) > stats_.max_planes) stats_.max_planes = std::uint64_t(planes);
  Contact out;
  out.contact = true;
  out.depth = stylus.depth;
  out.point = proxy_;
  const Vec3 spring = proxy_ - probe.end;
  out.force = spring * (law.stiffness_n_per_m * law.metres_per_unit);
  out.normal = rest_normal_;
  return out;
}

} // namespace hb
