// Trajectories in device space.
// 1. render(): device tip (m) -> model segment (handle stylus_m behind the tip) -> query ->
//    force in N (the law's metres_per_unit is the map's).
// 2. run_closed_loop(): per tick, sample the position (quantum), render, delay, filter,
//    saturate, then hold that force while RK4 integrates device (+ hand) over T in
//    `substeps` steps. A stall holds the last force for its ticks; the next tick is late.
// 3. play_positions(): prescribed tips, one query per tick.
#include "stability/trajectory.h"
#include "errors.h"
#include <algorithm>
#include <cmath>
#include <deque>

namespace hb {

HandModel no_hand() { return HandModel{}; }
HandModel light_grip() { return HandModel{"light grip", 0.1, 2.0, 50.0}; }
HandModel arm_hand() { return HandModel{"arm", 0.554, 6.45, 135.0}; }

namespace {

Segment trajectory_segment(const Workspace& map, const Vec3d& tip_m, const Vec3d& dir, double stylus_m) {
  const Vec3 tip = map.to_model(tip_m);
  return Segment{tip - (dir * (stylus_m / map.metres_per_unit)).cast<float>(), tip};
}

Rendered rendered_answer(const Contact& c, const Workspace& map) {
  Rendered r;
  if (!c.contact) return r;
  r.contact = true;
  r.force = c.force.cast<double>();
  r.normal = c.normal.cast<double>();
  r.depth_m = c.depth * map.metres_per_unit;
  r.point_m = map.to_device(c.point);
  return r;
}

} // namespace

Rendered render(const ContactQuery& query, const ForceLaw& law, const Workspace& map, const Vec3d& tip_m,
                const Vec3d& dir, double stylus_m) {
  return rendered_answer(query.query(trajectory_segment(map, tip_m, dir, stylus_m), law), map);
}

TrajectoryRenderer::TrajectoryRenderer(const ContactQuery& query, const ForceLaw& law, const Workspace& map,
                                       ContactLaw kind, GodObjectOptions proxy_options)
    : query_(query), law_(law), map_(map), kind_(kind), proxy_(query, proxy_options) {}

Rendered TrajectoryRenderer::operator()(const Vec3d& tip_m, const Vec3d& dir, double stylus_m) noexcept {
  const Segment s = trajectory_segment(map_, tip_m, dir, stylus_m);
  return rendered_answer(kind_ == ContactLaw::proxy ? proxy_.step(s, law_) : query_.query(s, law_), map_);
}

Contact AnalyticWall::query(const Segment& segment, const ForceLaw& law) const noexcept {
  Contact c;
  const Vec3 delta = segment.end - segment.start;
  const float length = delta.norm();
  if (!(length > 0.f)) return c;
  const Vec3 l = delta / length;
  const float hs = (segment.start - point_).dot(normal_);  // handle height above the wall
  const float ln = l.dot(normal_);
  if (hs < 0.f || !(ln < 0.f)) return c;                    // handle inside, or moving away
  const float t = hs / -ln;
  if (t > length) return c;
  return contact_along(segment.start, l, length, t, normal_, law);
}

std::vector<TickRecord> run_closed_loop(const ContactQuery& query, const ForceLaw& law, const Workspace& map,
                                        const ClosedLoopRun& run) {
  const DeviceProfile& dev = run.device;
  if (!(dev.period_s > 0) || !(dev.mass_kg > 0) || dev.delay_ticks < 0 || run.substeps < 1 || !(run.seconds > 0))
    throw InvalidInput("closed-loop run: period, mass, substeps and duration must be positive, delay >= 0");
  const double T = dev.period_s, dt = T / run.substeps;
  const std::size_t ticks = static_cast<std::size_t>(std::llround(run.seconds / T));
  const bool hand = run.hand.present();
  std::vector<TickRecord> out;
  out.reserve(ticks);
  std::deque<Vec3d> pending(std::size_t(dev.delay_ticks), Vec3d::Zero());
  Vec3d x = run.start_m, v = run.start_velocity, applied = Vec3d::Zero(), prev_sample = x;
  TrajectoryRenderer renderer(query, law, map, run.contact_law);
  std::size_t contact_ticks = 0, stall_left = 0, stall_length = 0, next_stall = 0;
  for (std::size_t k = 0; k < ticks; ++k) {
    const double t = k * T;
    TickRecord rec;
    rec.t = t;
    rec.x = x;
    rec.v = v;
    if (next_stall < run.stalls.size() && run.stalls[next_stall].at == k && run.stalls[next_stall].ticks > 0) {
      stall_left = stall_length = run.stalls[next_stall].ticks;
      ++next_stall;
    }
    if (stall_left > 0) {
      --stall_left;
      rec.stalled = true;  // no tick: the device holds `applied`
    } else {
      Vec3d xs = x;
      if (dev.quantum_m > 0)
        for (int a = 0; a < 3; ++a) xs[a] = dev.quantum_m * std::floor(x[a] / dev.quantum_m);
      const Rendered r = renderer(xs, run.stylus_dir, run.stylus_m);
      rec.desired = r.force;
      rec.normal = r.normal;
      rec.contact = r.contact;
      Vec3d f = r.force;
      if (dev.delay_ticks > 0) {
        pending.push_back(f);
        f = pending.front();
        pending.pop_front();
      }
      const double lateness = stall_length > 0 ? stall_length * T : 0.0;
      stall_length = 0;
      if (run.filter) f = run.filter->apply(f, xs, (xs - prev_sample) / T, lateness);
      prev_sample = xs;
      const double mag = f.norm();
      if (mag > dev.max_force_n) f *= dev.max_force_n / mag;
      if (!f.allFinite()) f.setZero();
      applied = f;
    }
    rec.force = applied;
    out.push_back(rec);
    if (rec.contact) ++contact_ticks;
    if (run.stop_after_contact_ticks > 0 && contact_ticks >= run.stop_after_contact_ticks && !rec.contact &&
        !rec.stalled)
      break;
    const bool hand_on = hand && t < run.hand_release_s;
    const double m = dev.mass_kg + (hand_on ? run.hand.mass_kg : 0.0);
    const double b = dev.damping_n_s_per_m + (hand_on ? run.hand.damping_n_s_per_m : 0.0);
    for (int s = 0; s < run.substeps; ++s) {
      const double ts = t + s * dt;
      const auto acc = [&](const Vec3d& xx, const Vec3d& vv, double tt) -> Vec3d {
        Vec3d f = applied - b * vv;
        if (hand_on && run.set_point) f -= run.hand.stiffness_n_per_m * (xx - run.set_point(tt));
        return f / m;
      };
      const Vec3d k1x = v, k1v = acc(x, v, ts);
      const Vec3d k2x = v + 0.5 * dt * k1v, k2v = acc(x + 0.5 * dt * k1x, v + 0.5 * dt * k1v, ts + 0.5 * dt);
      const Vec3d k3x = v + 0.5 * dt * k2v, k3v = acc(x + 0.5 * dt * k2x, v + 0.5 * dt * k2v, ts + 0.5 * dt);
      const Vec3d k4x = v + dt * k3v, k4v = acc(x + dt * k3x, v + dt * k3v, ts + dt);
      x += dt / 6 * (k1x + 2 * k2x + 2 * k3x + k4x);
      v += dt / 6 * (k1v + 2 * k2v + 2 * k3v + k4v);
    }
    if (!x.allFinite() || x.norm() > 10.0) break;  // diverged: the record so far says so
  }
  return out;
}

std::vector<TickRecord> play_positions(const ContactQuery& query, const ForceLaw& law, const Workspace& map,
                                       const std::vector<Vec3d>& tips_m, const Vec3d& stylus_dir, double stylus_m,
                                       double period_s, ContactLaw contact_law) {
  std::vector<TickRecord> out(tips_m.size());
  TrajectoryRenderer renderer(query, law, map, contact_law);
  for (std::size_t k = 0; k < tips_m.size(); ++k) {
    TickRecord& r = out[k];
    r.t = k * period_s;
    r.x = tips_m[k];
    if (k + 1 < tips_m.size()) r.v = (tips_m[k + 1] - tips_m[k]) / period_s;
    else if (k > 0) r.v = (tips_m[k] - tips_m[k - 1]) / period_s;
    const Rendered q = renderer(tips_m[k], stylus_dir, stylus_m);
    r.contact = q.contact;
    r.force = r.desired = q.force;
    r.normal = q.normal;
  }
  return out;
}

double passivity_equivalent_stiffness(const std::vector<TickRecord>& ticks, double period_s) {
  double work = 0, v2 = 0;
  for (std::size_t k = 0; k + 1 < ticks.size(); ++k) {
    const Vec3d dx = ticks[k + 1].x - ticks[k].x;
    work += ticks[k].force.dot(dx);
    if (ticks[k].force.squaredNorm() > 0 || ticks[k + 1].force.squaredNorm() > 0) v2 += dx.squaredNorm() / (period_s * period_s) * period_s;
  }
  return v2 > 0 ? work / (0.5 * period_s * v2) : 0.0;
}

} // namespace hb
