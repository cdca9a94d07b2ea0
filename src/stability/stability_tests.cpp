// The stability suite's tests T1-T8 (stability_harness.h): each a trajectory run on
// the box and on exact, the same trajectory for both; every figure becomes a StabilityMetric
// judged against its threshold, for the box and for exact (a failure exact shares is the
// law's). Also the sites on the model (surface points by area, kept when exact answers a
// 1 mm-deep probe along the inward normal there) and the simulated free bounce.
#include "stability/stability_harness.h"
#include "perception/perceptible.h"
#include "stability/stability_suite.h"
#include "math/constants.h"
#include "errors.h"
#include "evaluation/probe_sampling.h"
#include "exact/exact_query.h"
#include "scene/bake.h"
#include "mesh/triangle_mesh.h"
#include "parallel/byte_buffer.h"
#include "parallel/work_split.h"
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <optional>
#include <functional>
#include <iterator>
#include <limits>
#include <memory>


namespace hb {
namespace stability {

StabilityMetric metric(const std::string& test, const std::string& scene, const std::string& name,
                       const std::string& unit, double box, double exact, StabilityRule rule, double threshold,
                       double tolerance) {
  StabilityMetric m;
  m.test = test, m.scene = scene, m.metric = name, m.unit = unit;
  m.box = box, m.exact = exact, m.rule = rule, m.threshold = threshold, m.tolerance = tolerance;
  judge(m);
  return m;
}

Bounce free_bounce(const ContactQuery& q, const ForceLaw& law, const Workspace& map, const DeviceProfile& dev,
                   const Vec3d& surface_m, const Vec3d& inward, double v0, double stylus_m,
                   const std::vector<Stall>& stalls, TickFilter* filter,
                   ContactLaw contact_law) {
  ClosedLoopRun run;
  run.contact_law = contact_law;
  run.device = dev;
  run.start_m = surface_m - 1e-9 * inward;  // at the surface: v0 is the entry speed
  run.start_velocity = v0 * inward;
  run.seconds = 0.5;
  run.stylus_dir = inward;
  run.stylus_m = stylus_m;
  run.stop_after_contact_ticks = 1;
  run.stalls = stalls;
  run.filter = filter;
  const auto ticks = run_closed_loop(q, law, map, run);
  Bounce b;
  if (ticks.empty()) return b;
  // Exit speed over entry speed (on a curved surface the exit is not along the entry); a tip
  // still moving inward when the contact ended went through.
  const Vec3d v = ticks.back().v;
  b.popped = v.dot(inward) > 0;
  b.restitution = b.popped ? -v.norm() / v0 : v.norm() / v0;
  return b;
}

Vec3d tilted(const Vec3d& inward, double degrees, std::size_t which) {
  Vec3d u = inward.unitOrthogonal();
  if (which % 2) u = inward.cross(u);
  const double a = degrees * kPi / 180.0;
  return (std::cos(a) * inward + std::sin(a) * u).normalized();
}

std::vector<Site> pick_sites(const TriangleMesh& mesh, const ContactQuery& exact, const Workspace& map,
                             const ForceLaw& law, std::size_t count, std::uint64_t seed, double stylus_m) {
  ProbeOptions po;
  po.cone_degrees = 0.f;
  po.max_depth_fraction = 0.f;
  po.length_fraction = 0.05f;
  po.seed = seed;
  const auto probes = sample_probes(mesh, count * 8, po);
  std::vector<Site> sites;
  for (const Segment& s : probes) {
    if (sites.size() >= count) break;
    Site site;
    site.surface_m = map.to_device(s.end);
    site.inward = (s.end - s.start).cast<double>().normalized();
    // Keep points where exact answers probes 1 mm deep and 2 mm deep along the normal with
    // about those depths (not a pocket of the stylus, not a thin rim).
    bool ok = true;
    for (double depth : {0.001, 0.002}) {
      const Rendered r = render(exact, law, map, site.surface_m + depth * site.inward, site.inward, stylus_m);
      ok = ok && r.contact && std::fabs(r.depth_m - depth) < 0.2e-3;
    }
    if (ok) sites.push_back(site);
  }
  return sites;
}

double rms_speed(const std::vector<TickRecord>& ticks, double t0, double t1) {
  double s = 0;
  int n = 0;
  for (const auto& r : ticks)
    if (r.t >= t0 && r.t < t1) s += r.v.squaredNorm(), ++n;
  return n ? std::sqrt(s / n) : 0.0;
}

double angle_deg(const Vec3d& a, const Vec3d& b) {
  const double na = a.norm(), nb = b.norm();
  if (!(na > 0) || !(nb > 0)) return 0;
  return std::acos(std::clamp(a.dot(b) / (na * nb), -1.0, 1.0)) * 180.0 / kPi;
}

// T1: free bounces at k = K_max with b = 0 and b at the passivity bound; hold and release.
void Suite::t1(const Scene& s) {
  const ForceLaw lw = law(s, k_max());
  double worst_diff = -1e9, box0 = 0, ex0 = 0, boxb = 0, exb = 0, boxf = 0, exf = 0;
  std::size_t n = 0, both_bounce = 0, box_pops = 0, exact_pops = 0;
  for (const Site& site : s.sites) {
    DeviceProfile dev = o_.device;
    dev.damping_n_s_per_m = 0;
    const Bounce bb = free_bounce(*s.box, lw, s.workspace, dev, site.surface_m, site.inward, 0.1, o_.stylus_m, {}, nullptr, cl());
    const Bounce be = free_bounce(*s.exact, lw, s.workspace, dev, site.surface_m, site.inward, 0.1, o_.stylus_m, {}, nullptr, cl());
    dev.damping_n_s_per_m = dev.passivity_damping(k_max());
    const Bounce db = free_bounce(*s.box, lw, s.workspace, dev, site.surface_m, site.inward, 0.1, o_.stylus_m, {}, nullptr, cl());
    const Bounce de = free_bounce(*s.exact, lw, s.workspace, dev, site.surface_m, site.inward, 0.1, o_.stylus_m, {}, nullptr, cl());
    // A bounce that went through (the tip slid off an edge and went on inward) has no
    // restitution: the difference is over the sites where both bounce, and the sites where
    // only one goes through are counted apart (the box going through where exact bounces
    // fails; exact going through is the law's, at edges the box may round off).
    box_pops += bb.popped && !be.popped, exact_pops += be.popped && !bb.popped;
    if (!bb.popped && !be.popped && bb.restitution - be.restitution > worst_diff)
      worst_diff = bb.restitution - be.restitution, box0 = bb.restitution, ex0 = be.restitution;
    both_bounce += !bb.popped && !be.popped;
    boxb = std::max(boxb, db.restitution), exb = std::max(exb, de.restitution);
    if (o_.filter) {  // the same bounce through the servo's force path (energy guard, safety)
      auto fb = filter(), fe = filter();
      const Bounce gb = free_bounce(*s.box, lw, s.workspace, dev, site.surface_m, site.inward, 0.1, o_.stylus_m, {},
                                    fb.get(), cl());
      const Bounce ge = free_bounce(*s.exact, lw, s.workspace, dev, site.surface_m, site.inward, 0.1, o_.stylus_m, {},
                                    fe.get(), cl());
      boxf = std::max(boxf, gb.restitution), exf = std::max(exf, ge.restitution);
    }
    ++n;
  }
  if (n == 0) return;
  if (both_bounce)
    add(metric("T1", s.name, "free bounce restitution, b = 0 (site of the largest box - exact)", "", box0, ex0,
               StabilityRule::difference_at_most, 0.02));
  add(metric("T1", s.name, "free bounces (b = 0) going through where the other bounces, of " + std::to_string(n) +
                 " sites", "", double(box_pops), double(exact_pops), StabilityRule::at_most, 0));
  add(metric("T1", s.name, "free bounce restitution, b = kT/2 (passivity bound), worst site", "", boxb, exb,
             StabilityRule::at_most, 1.0));
  if (o_.filter)
    add(metric("T1", s.name, "same, through the servo's filter (" + o_.filter_name + "), worst site", "", boxf, exf,
               StabilityRule::at_most, 1.0));
  // Hold and release: light grip pushing about 1.5 N at k = K_max / 2, then letting go.
  const ForceLaw lh = law(s, k_half());
  double decay_b = 0, decay_e = 0;
  for (std::size_t i = 0; i < std::min<std::size_t>(3, s.sites.size()); ++i) {
    const Site& site = s.sites[i];
    for (int which = 0; which < 2; ++which) {
      const ClosedLoopRun run = hold_run(site, 2.5);
      const auto ticks = run_closed_loop(which ? *s.exact : *s.box, lh, s.workspace, run);
      const double early = rms_speed(ticks, 1.0, 1.75), late = rms_speed(ticks, 1.75, 2.5);
      const double decay = early > 1e-4 ? late / early : 0.0;
      (which ? decay_e : decay_b) = std::max(which ? decay_e : decay_b, decay);
    }
  }
  add(metric("T1", s.name, "hold decay ratio (light grip, k = K_max/2), worst site", "", decay_b, decay_e,
             StabilityRule::at_most, 0.5));
}

// Path along the surface at 1 mm normal depth, the stylus fixed (as a 3-DOF device's).
std::vector<Vec3d> Suite::surface_path(const Scene& s, const Site& site, const Vec3d& dir, double speed,
                                       std::size_t ticks, std::size_t which) const {
  const ForceLaw lw = law(s, k_half());
  std::vector<Vec3d> tips;
  Vec3d surf = site.surface_m, n = -site.inward;
  Vec3d u = site.inward.unitOrthogonal();
  if (which % 2) u = site.inward.cross(u).normalized();
  const double step = speed * o_.device.period_s, h = 0.004;
  for (std::size_t k = 0; k < ticks; ++k) {
    const double cosine = std::max(0.2, -dir.dot(n));
    tips.push_back(surf + (0.001 / cosine) * dir);
    const Vec3d guess = surf + step * u;
    // The surface along the stylus line through the guess, from exact Embree.
    const Rendered r = render(*s.exact, lw, s.workspace, guess + h * dir, dir, 2 * h);
    if (!r.contact) break;
    surf = guess + h * dir - r.depth_m * dir;
    n = r.normal;
    u = (u - u.dot(n) * n).normalized();
  }
  return tips;
}

// T2: sliding at 1 mm depth, normal and 30-degree stylus, 50-200 mm/s.
void Suite::t2(const Scene& s) {
  const ForceLaw lw = law(s, k_half());
  std::size_t contact = 0, jump = 0, jump_box = 0, jump_exact = 0, dir_jump = 0, lost = 0, extra = 0, ghost = 0, other = 0, ratio_out = 0,
              both = 0, seam = 0, seam_out = 0, ticks = 0, felt = 0;
  std::size_t ticks_at[2] = {0, 0}, felt_at[2] = {0, 0};  // [1]: the stylus within 6 deg of tangent
  double max_excess = 0;
  bool traced = false;
  const PerceptualThresholds felt_thresholds;  // nominal: what a hand tells apart
  for (std::size_t i = 0; i < s.sites.size(); ++i)
    for (double tilt : {0.0, 30.0})
      for (double speed : {0.05, 0.1, 0.2}) {
        const Site& site = s.sites[i];
        const Vec3d dir = tilt > 0 ? tilted(site.inward, tilt, i) : site.inward;
        const auto tips = surface_path(s, site, dir, speed, 150, i + std::size_t(speed * 100));
        if (tips.size() < 10) continue;
        const auto rb = play_positions(*s.box, lw, s.workspace, tips, dir, o_.stylus_m, o_.device.period_s, cl());
        const auto re = play_positions(*s.exact, lw, s.workspace, tips, dir, o_.stylus_m, o_.device.period_s, cl());
        std::size_t prev_met = 0;
        for (std::size_t k = 0; k < tips.size(); ++k) {
          const bool cb = rb[k].contact, ce = re[k].contact;
          const double fb = rb[k].force.norm(), fe = re[k].force.norm();
          if (ce) ++contact;
          if (cb || ce) {
            ++ticks;
            Contact xb, xe;
            xb.contact = cb, xe.contact = ce;
            xb.force = rb[k].force.cast<float>(), xe.force = re[k].force.cast<float>();
            const bool felt_here = perceive(xe, xb, felt_thresholds, o_.device.max_force_n).perceptible();
            felt += felt_here;
            // Where along the slide: the stylus within 6 degrees of the surface's tangent
            // plane (|n . l| < 0.1, the normal of exact's contact, else the box's) or steeper.
            const Vec3d& n = ce ? re[k].normal : rb[k].normal;
            const bool grazing = std::fabs(n.dot(dir)) < 0.1;
            ++ticks_at[grazing], felt_at[grazing] += felt_here;
          }
          if (ce && !cb) ++lost;
          if (cb && !ce && fb > kFloor) ++extra;
          const Rendered qb = render(*s.box, lw, s.workspace, tips[k], dir, o_.stylus_m);
          const Rendered qe = render(*s.exact, lw, s.workspace, tips[k], dir, o_.stylus_m);
          if (qb.contact && qb.force.norm() > kFloor) {
            if (!qe.contact || std::fabs(qb.depth_m - qe.depth_m) > 0.25e-3) ++other;
            // A ghost: no triangle of the mesh within 0.1 mm of the box's surface point (exact
            // Embree on a 0.2 mm segment through it, both ways: front or back face; and on
            // 0.1 mm from just before the point each way, so that a face within a few microns
            // on the other side, an ear touching the head, does not hide the one the point is
            // on), along the stylus and along the box's normal too: a
            // stylus within a degree of the tangent plane passes 0.1 mm of a point 2 um off
            // the surface along itself, and such a point is on the surface for any hand.
            const auto there_along = [&](const Vec3d& u) {
              const Vec3d a = qb.point_m - 1e-4 * u, b = qb.point_m + 1e-4 * u;
              return render(*s.exact, lw, s.workspace, b, u, 2e-4).contact || render(*s.exact, lw, s.workspace, a, -u, 2e-4).contact ||
                     render(*s.exact, lw, s.workspace, b, u, 1e-4 + 1e-6).contact ||
                     render(*s.exact, lw, s.workspace, a, -u, 1e-4 + 1e-6).contact;
            };
            const bool there = there_along(dir) || there_along(-qb.normal);
            if (!there) ++ghost;
          }
          std::size_t met = 0;
          if (s.box_scene) {
            const Vec3 tip = s.workspace.to_model(tips[k]);
            met = boxes_met(*s.box_scene, 
                Segment{tip - (dir * (o_.stylus_m / s.workspace.metres_per_unit)).cast<float>(), tip});
          }
          const bool at_seam = k > 0 && met != prev_met;
          prev_met = met;
          if (cb && ce && fe > kFloor) {
            ++both;
            const double ratio = fb / fe;
            const bool out = ratio < 0.93 || ratio > 1.07;
            ratio_out += out;
            if (at_seam) ++seam, seam_out += out;
          }
          if (k == 0 || !ce || !re[k - 1].contact) continue;
          const double jb = (rb[k].force - rb[k - 1].force).norm(), je = (re[k].force - re[k - 1].force).norm();
          const double thr = std::max(0.07 * fe, kFloor);
          if (jb - je > thr) ++jump;
          if (jb > thr) ++jump_box;
          if (je > thr) ++jump_exact;
          max_excess = std::max(max_excess, jb - je);
          if (cb && rb[k - 1].contact &&
              angle_deg(rb[k].force, rb[k - 1].force) - angle_deg(re[k].force, re[k - 1].force) > 10.0)
            ++dir_jump;
        }
        if (!traced && tilt == 0.0 && speed == 0.1) {
          ForceTrace tr;
          tr.test = "T2", tr.scene = s.name, tr.label = "slide at 1 mm depth, 100 mm/s, normal stylus";
          for (std::size_t k = 0; k < tips.size(); ++k) {
            tr.t_s.push_back(rb[k].t);
            tr.box_n.push_back(rb[k].force.norm());
            tr.exact_n.push_back(re[k].force.norm());
          }
          traces_.push_back(std::move(tr));
          traced = true;
        }
      }
  if (contact == 0) return;
  const double c = double(contact);
  add(metric("T2", s.name, "share of contact ticks perceptibly different from exact (max(10% |F|, 0.04 N), 25 deg)", "",
             ticks ? double(felt) / double(ticks) : 0.0, 0.0, StabilityRule::at_most, 0.001));
  for (int g = 1; g >= 0; --g)
    add(metric("T2", s.name,
               std::string("of them, with the stylus ") +
                   (g ? "within 6 deg of the tangent plane (|n . l| < 0.1): " : "steeper (|n . l| >= 0.1): ") +
                   std::to_string(ticks_at[g]) + " ticks, share felt",
               "", ticks_at[g] ? double(felt_at[g]) / double(ticks_at[g]) : 0.0, 0.0, StabilityRule::info, 0));
  add(metric("T2", s.name, "share of ticks whose jump exceeds exact's by max(7% |F|, 0.05 N)", "", jump / c, 0.0,
             StabilityRule::at_most, 0.001));
  add(metric("T2", s.name, "share of ticks with a jump above max(7% |F|, 0.05 N)", "", jump_box / c,
             jump_exact / c, StabilityRule::difference_at_most, 0.001));
  add(metric("T2", s.name, "largest per-tick jump excess over exact", "N", max_excess, 0.0, StabilityRule::info, 0));
  add(metric("T2", s.name, "share of ticks with a direction jump > 10 deg beyond exact's", "", dir_jump / c, 0.0,
             StabilityRule::at_most, 0.001));
  add(metric("T2", s.name, "share of exact's contact ticks the box loses", "", lost / c, 0.0,
             StabilityRule::at_most, 0.001));
  add(metric("T2", s.name, "share of ticks with a contact exact does not have (> 0.05 N)", "", extra / c, 0.0,
             StabilityRule::at_most, 0.0));
  add(metric("T2", s.name, "ghost ticks: a box force (> 0.05 N) from a point no triangle is at", "", ghost / c, 0.0,
             StabilityRule::at_most, 0.0));
  add(metric("T2", s.name, "ticks answered from another surface than exact's (> 0.25 mm apart)", "", other / c,
             0.0, StabilityRule::at_most, 0.001));
  add(metric("T2", s.name, "share of contact ticks with |F_box|/|F_exact| outside [0.93, 1.07]", "",
             both ? ratio_out / double(both) : 0.0, 0.0, StabilityRule::at_most, 0.01));
  if (s.box_scene && s.box_scene->parts().boxes.size() > 1)
    add(metric("T2", s.name, "same, at ticks where the boxes met change (seams)", "",
               seam ? seam_out / double(seam) : 0.0, 0.0, StabilityRule::at_most, 0.01));
}

// T3: thin plates, prescribed push-through at 0.1 m/s, normal and 45 degrees.
void Suite::t3(const Scene& s, double thickness_mm) {
  const ForceLaw lw = law(s, k_half());
  double flips[2] = {0, 0}, pop[2] = {1e9, 1e9};
  const Vec3d top(0.37e-3, 0.21e-3, 0.5 * thickness_mm * 1e-3);  // off the grid's vertices and edges
  for (double tilt : {0.0, 45.0}) {
    const Vec3d dir = tilted(Vec3d(0, 0, -1), tilt, 0);
    std::vector<Vec3d> tips;
    for (double d = -0.001; d <= 0.012; d += 0.1 * o_.device.period_s) tips.push_back(top + d * dir);
    for (int which = 0; which < 2; ++which) {
      const auto r = play_positions(which ? *s.exact : *s.box, lw, s.workspace, tips, dir, o_.stylus_m,
                                    o_.device.period_s, cl());
      bool began = false;
      for (std::size_t k = 0; k < r.size(); ++k) {
        if (r[k].force.z() < -kFloor) ++flips[which];
        const double depth = (tips[k] - top).dot(dir);
        if (r[k].contact) began = true;
        if (began && !r[k].contact && depth > 0) {
          pop[which] = std::min(pop[which], depth * 1e3);
          break;
        }
      }
    }
  }
  add(metric("T3", s.name, "ticks with the force pointing through the plate (sign flip)", "", flips[0], flips[1],
             StabilityRule::at_most, 0));
  const double need = std::min(o_.stylus_m, o_.device.max_force_n / k_half()) * 1e3 * 0.99;
  add(metric("T3", s.name, "depth at which the force first vanishes (pop-through)", "mm",
             std::min(pop[0], 99.0), std::min(pop[1], 99.0), StabilityRule::at_least, need));
}

// T4: concave corner, light grip pushing along the bisector, 0.5 mm lateral offset, 2 s.
void Suite::t4(const Scene& s) {
  const ForceLaw lw = law(s, k_half());
  double ripple[2], switches[2];
  for (int which = 0; which < 2; ++which) {
    ClosedLoopRun run;
    run.device = o_.device;
    run.hand = light_grip();
    run.start_m = Vec3d(0.0005, 0.0013, 0.002);
    const Vec3d sp(0, 0.0013, -0.02);
    run.set_point = [sp](double) { return sp; };
    run.seconds = 2.0;
    run.stylus_dir = Vec3d(0, 0, -1);
    run.stylus_m = o_.stylus_m;
    run.contact_law = cl();
    const auto ticks = run_closed_loop(which ? *s.exact : *s.box, lw, s.workspace, run);
    double lat2 = 0, fsum = 0;
    int n = 0, sw = 0, last = 0;
    for (const auto& r : ticks) {
      if (r.t < 1.0) continue;
      lat2 += r.force.x() * r.force.x();
      fsum += r.force.norm();
      ++n;
      const int wall = r.normal.x() > 0.05 ? 1 : (r.normal.x() < -0.05 ? -1 : 0);
      if (wall != 0 && last != 0 && wall != last) ++sw;
      if (wall != 0) last = wall;
    }
    // No force at all in the corner (the contact lost) fails both figures.
    const bool held = n && fsum / n > 0.1;
    ripple[which] = held ? std::sqrt(lat2 / n) / (fsum / n) : 99.0;
    switches[which] = held ? sw / std::max(1e-9, ticks.back().t - 1.0) : 99.0;
  }
  add(metric("T4", s.name, "lateral force ripple (rms / mean |F|) after 1 s", "", ripple[0], ripple[1],
             StabilityRule::at_most, 0.07));
  add(metric("T4", s.name, "wall switches per second after 1 s", "1/s", switches[0], switches[1],
             StabilityRule::at_most, 2.0));
}

// T5: felt stiffness of a prescribed normal stroke (1 mm deep, 0.1 m/s) with a tilted stylus.
double Suite::keff_ratio(const Scene& s, const ContactQuery& q, const Site& site, double tilt, std::size_t which) const {
  const double k = k_half();
  const ForceLaw lw = law(s, k);
  const Vec3d dir = tilt > 0 ? tilted(site.inward, tilt, which) : site.inward;
  std::vector<Vec3d> tips;
  const double step = 0.1 * o_.device.period_s;
  for (double d = -0.0005; d < 0.001; d += step) tips.push_back(site.surface_m + d * site.inward);
  for (double d = 0.001; d > -0.0005; d -= step) tips.push_back(site.surface_m + d * site.inward);
  const auto r = play_positions(q, lw, s.workspace, tips, dir, o_.stylus_m, o_.device.period_s, cl());
  return passivity_equivalent_stiffness(r, o_.device.period_s) / k;
}

void Suite::t5(const Scene& s, bool model) {
  for (double tilt : model ? std::vector<double>{30, 60, 75} : std::vector<double>{0, 30, 45, 60, 75}) {
    std::vector<double> b, e;
    for (std::size_t i = 0; i < s.sites.size(); ++i) {
      b.push_back(keff_ratio(s, *s.box, s.sites[i], tilt, i));
      e.push_back(keff_ratio(s, *s.exact, s.sites[i], tilt, i));
    }
    if (b.empty()) continue;
    std::nth_element(b.begin(), b.begin() + b.size() / 2, b.end());
    std::nth_element(e.begin(), e.begin() + e.size() / 2, e.end());
    add(metric("T5", s.name,
               "felt stiffness K_eff / k, stylus tilted " + std::to_string(int(tilt)) + " deg" +
                   (model ? " (median site)" : ""),
               "", b[b.size() / 2], e[e.size() / 2], StabilityRule::at_most, 1.05));
  }
}

// T6: the probe starts inside (0.5-5 mm): first-tick force and ramp; random handles in the
// workspace: forces pointing into the object.
void Suite::t6(const Scene& s) {
  const ForceLaw lw = law(s, k_half());
  double first[2] = {0, 0}, ramp[2] = {1e9, 1e9};
  for (std::size_t i = 0; i < std::min<std::size_t>(4, s.sites.size()); ++i)
    for (double depth : {0.0005, 0.002, 0.005})
      for (int which = 0; which < 2; ++which) {
        const Site& site = s.sites[i];
        const ContactQuery& q = which ? *s.exact : *s.box;
        auto f = o_.filter ? o_.filter() : nullptr;  // a servo (re)starting: its ramp runs
        const Vec3d tip = site.surface_m + depth * site.inward;
        std::vector<double> mags;
        TrajectoryRenderer rend(q, lw, s.workspace, cl());
        for (int k = 0; k < 300; ++k) {
          const Rendered r = rend(tip, site.inward, o_.stylus_m);
          Vec3d out = f ? f->apply(r.force, tip, Vec3d::Zero(), 0.0) : r.force;
          if (out.norm() > o_.device.max_force_n) out *= o_.device.max_force_n / out.norm();
          mags.push_back(out.norm());
        }
        first[which] = std::max(first[which], mags[0]);
        const double target = mags.back();
        std::size_t k90 = 0;
        while (k90 < mags.size() && mags[k90] < 0.9 * target) ++k90;
        if (target > kFloor) ramp[which] = std::min(ramp[which], double(k90) * o_.device.period_s * 1e3);
      }
  add(metric("T6", s.name, "first-tick force, tip starting 0.5-5 mm inside (filter: " + o_.filter_name + ")", "N",
             first[0], first[1], StabilityRule::at_most, 0.5));
  add(metric("T6", s.name, "shortest time to 90% of the force (ramp)", "ms", std::min(ramp[0], 1e6),
             std::min(ramp[1], 1e6), StabilityRule::at_least, 100.0));
  // Random handles inside the workspace (the OBB mapped to 80 mm), random directions.
  std::uint64_t state = o_.seed * 6364136223846793005ULL + 1442695040888963407ULL;
  const auto uniform = [&]() {
    state = state * 6364136223846793005ULL + 1442695040888963407ULL;
    return double(state >> 11) * (1.0 / 9007199254740992.0);
  };
  std::size_t into = 0, wrong = 0, into_exact = 0;
  const std::size_t probes = 4000;
  const double half = 0.5 * o_.workspace.diagonal_m / std::sqrt(3.0);
  for (std::size_t i = 0; i < probes; ++i) {
    const Vec3d tip(half * (2 * uniform() - 1), half * (2 * uniform() - 1), half * (2 * uniform() - 1));
    Vec3d dir(2 * uniform() - 1, 2 * uniform() - 1, 2 * uniform() - 1);
    if (dir.norm() < 1e-6) continue;
    dir.normalize();
    const Rendered b = render(*s.box, lw, s.workspace, tip, dir, o_.stylus_m);
    const Rendered e = render(*s.exact, lw, s.workspace, tip, dir, o_.stylus_m);
    if (b.contact && b.force.norm() > kFloor && !e.contact) ++wrong;
    if (b.contact && e.contact && b.force.dot(e.normal) < -kFloor) ++into;
    if (e.contact && e.force.dot(e.normal) < -kFloor) ++into_exact;
  }
  add(metric("T6", s.name, "random handles: box contacts exact does not have (> 0.05 N)", "",
             wrong / double(probes), 0.0, StabilityRule::at_most, 0.003));
  add(metric("T6", s.name, "random handles: forces pointing into the object", "", double(into), double(into_exact),
             StabilityRule::at_most, 0));
}

// T7: release: retract from 1 mm depth at 0.01-0.5 m/s; hover 0.1-0.5 mm above.
void Suite::t7(const Scene& s) {
  const ForceLaw lw = law(s, k_half());
  double late = 0, hover = 0, hover_exact = 0;
  for (const Site& site : s.sites) {
    for (double speed : {0.01, 0.1, 0.5}) {
      std::vector<Vec3d> tips;
      for (double d = 0.001; d > -0.002; d -= speed * o_.device.period_s)
        tips.push_back(site.surface_m + d * site.inward);
      const auto rb = play_positions(*s.box, lw, s.workspace, tips, site.inward, o_.stylus_m, o_.device.period_s, cl());
      const auto re = play_positions(*s.exact, lw, s.workspace, tips, site.inward, o_.stylus_m, o_.device.period_s, cl());
      std::size_t end_e = 0, end_b = 0;
      for (std::size_t k = 0; k < tips.size(); ++k) {
        if (re[k].contact) end_e = k + 1;
        if (rb[k].contact && rb[k].force.norm() > kFloor) end_b = k + 1;
      }
      late = std::max(late, double(end_b > end_e ? end_b - end_e : 0));
    }
    for (double h : {0.0001, 0.0003, 0.0005}) {
      const Vec3d tip = site.surface_m - h * site.inward;
      hover += render(*s.box, lw, s.workspace, tip, site.inward, o_.stylus_m).force.norm() > kFloor;
      hover_exact += render(*s.exact, lw, s.workspace, tip, site.inward, o_.stylus_m).force.norm() > kFloor;
    }
  }
  add(metric("T7", s.name, "ticks of force after exact's contact ended (retract 0.01-0.5 m/s), worst", "ticks",
             late, 0.0, StabilityRule::at_most, 1.0));
  add(metric("T7", s.name, "forces hovering 0.1-0.5 mm above the surface", "", hover, hover_exact,
             StabilityRule::at_most, 0));
}

// T8: servo stalls of 2, 5, 10 ms while in contact. During a stall the device holds its last
// force (nothing can act then); what is judged is the servo's response after it.
void Suite::t8(const Scene& s) {
  const ForceLaw lh = law(s, k_half());
  const ForceLaw lb = law(s, k_max());
  double popped[2] = {0, 0}, added[2] = {-1e9, -1e9}, with[2] = {0, 0}, alone[2] = {0, 0};
  for (std::size_t i = 0; i < std::min<std::size_t>(4, s.sites.size()); ++i) {
    const Site& site = s.sites[i];
    for (int which = 0; which < 2; ++which) {
      const ContactQuery& q = which ? *s.exact : *s.box;
      DeviceProfile dev = o_.device;
      dev.damping_n_s_per_m = dev.passivity_damping(k_max());
      double deepest_plain = 0;
      for (std::size_t ms : {0, 2, 5, 10}) {
        const std::size_t ticks = std::size_t(std::llround(ms * 1e-3 / o_.device.period_s));
        // A hold: light grip pushing about 1.5 N, no device damping, the stall at 1 s (the
        // first run has none: on a curved model the hand may slide the tip along the
        // surface, and only what the stall adds to the penetration counts).
        ClosedLoopRun run = hold_run(site, 2.0);
        run.stalls = {Stall{1000, ticks}};
        auto f = filter();
        run.filter = f.get();
        const auto rec = run_closed_loop(q, lh, s.workspace, run);
        double deepest = 0;
        for (const auto& r : rec) deepest = std::max(deepest, (r.x - site.surface_m).dot(site.inward));
        if (ms == 0) {
          deepest_plain = deepest;
          continue;
        }
        // Sank under the hand by more than a millimetre: the stylus is going through.
        if (deepest > deepest_plain + 0.001) popped[which] += 1;
        // A free bounce at k = K_max, damping at the bound, the stall on the way out (past the
        // deepest point): the held force then exceeds the spring's, so the stall alone injects
        // energy; the response after it must add none.
        const double quarter = 0.5 * kPi * std::sqrt(dev.mass_kg / k_max()) / dev.period_s;
        const std::vector<Stall> stall{Stall{std::size_t(std::llround(1.2 * quarter)) + 1, ticks}};
        auto g = filter();
        const Bounce b = free_bounce(q, lb, s.workspace, dev, site.surface_m, site.inward, 0.1, o_.stylus_m, stall, g.get(), cl());
        const Bounce n = free_bounce(q, lb, s.workspace, dev, site.surface_m, site.inward, 0.1, o_.stylus_m, stall, nullptr, cl());
        const double rb = b.popped ? 9.0 : b.restitution, rn = n.popped ? 9.0 : n.restitution;
        added[which] = std::max(added[which], rb - rn);
        with[which] = std::max(with[which], rb);
        alone[which] = std::max(alone[which], rn);
      }
    }
  }
  add(metric("T8", s.name, "holds popped through by a 2/5/10 ms stall (filter: " + o_.filter_name + ")", "",
             popped[0], popped[1], StabilityRule::at_most, 0));
  add(metric("T8", s.name, "restitution the servo's response adds to a stalled bounce (b = kT/2), worst", "",
             added[0], added[1], StabilityRule::at_most, 0.02));
  add(metric("T8", s.name, "bounce restitution with the stall and the response, worst", "", with[0], with[1],
             StabilityRule::info, 0));
  add(metric("T8", s.name, "bounce restitution with the stall alone (force held, then fresh)", "", alone[0],
             alone[1], StabilityRule::info, 0));
}

} // namespace stability
} // namespace hb
