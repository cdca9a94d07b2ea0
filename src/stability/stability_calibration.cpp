// The stability suite's calibration gate (stability_suite.h): free bounces and prescribed
// strokes on an AnalyticWall must give the reference simulation's figures
// (docs/stability.md), else the harness is wrong. And judge(), every metric's verdict.
#include "stability/stability_harness.h"
#include "stability/trajectory.h"
#include <cmath>
#include <cstdio>

namespace hb {
namespace {

// A closed run of the wall used by the gate: the plane z = 0 of a model in metres.
struct Wall {
  AnalyticWall wall{Vec3::Zero(), Vec3(0, 0, 1)};
  Workspace map;  // model units are metres
  ForceLaw law;
  Wall(double k) {
    map.metres_per_unit = 1.0;
    law.stiffness_n_per_m = float(k);
    law.metres_per_unit = 1.f;
  }
};

} // namespace

void judge(StabilityMetric& m) {
  const auto ok = [&](double v) {
    switch (m.rule) {
      case StabilityRule::info: return true;
      case StabilityRule::at_most: return v <= m.threshold;
      case StabilityRule::at_least: return v >= m.threshold;
      case StabilityRule::within: return std::fabs(v - m.threshold) <= m.tolerance;
      case StabilityRule::difference_at_most: return m.box - m.exact <= m.threshold;
    }
    return false;
  };
  m.pass = ok(m.box);
  m.exact_pass = std::isnan(m.exact) ? true : (m.rule == StabilityRule::difference_at_most ? true : ok(m.exact));
  m.verdict = m.rule == StabilityRule::info ? "info"
              : m.pass ? "pass" : (m.exact_pass ? "fail (box)" : "fail (law: exact fails too)");
}

using stability::Bounce;
using stability::free_bounce;
using stability::kNaN;
using stability::metric;

std::vector<StabilityMetric> run_calibration(const DeviceProfile& device) {
  std::vector<StabilityMetric> out;
  DeviceProfile dev = device;
  dev.delay_ticks = 0;
  dev.quantum_m = 0;
  dev.mass_kg = 0.1;
  dev.max_force_n = 1e9;
  const Wall w(3000.0);
  for (double b : {0.0, 1.5}) {
    dev.damping_n_s_per_m = b;
    const double expected = b > 0 ? 0.990 : 1.148;
    double worst = 0;
    for (double v0 : {0.05, 0.3}) {
      const Bounce r = free_bounce(w.wall, w.law, w.map, dev, Vec3d::Zero(), Vec3d(0, 0, -1), v0, 0.05);
      if (v0 == 0.05 || std::fabs(r.restitution - expected) > std::fabs(worst - expected)) worst = r.restitution;
    }
    out.push_back(metric("calibration", "analytic wall", "free bounce restitution, K = 3000 N/m, b = " +
                                                             std::string(b > 0 ? "1.5" : "0") + " N s/m",
                         "", worst, kNaN, StabilityRule::within, b > 0 ? 0.990 : 1.148, 0.01));
  }
  // Prescribed strokes: K_eff / K in [0.976, 1.000] (reference: 0.976 at 0.1 m/s).
  for (double v : {0.01, 0.1, 0.5}) {
    std::vector<Vec3d> tips;
    const double step = v * 1e-3;
    const double depth = 0.002;
    const int in = int(std::llround(0.003 / step));
    for (int k = 0; k <= in; ++k) tips.push_back(Vec3d(0, 0, 0.001 - k * step));
    for (int k = 1; k <= in; ++k) tips.push_back(Vec3d(0, 0, -depth + k * step));
    const Wall w3(3000.0);
    const auto r = play_positions(w3.wall, w3.law, w3.map, tips, Vec3d(0, 0, -1), 0.05, 1e-3);
    const double ratio = passivity_equivalent_stiffness(r, 1e-3) / 3000.0;
    char name[96];
    std::snprintf(name, sizeof name, "K_eff / K, prescribed in-out stroke 2 mm at %.2f m/s", v);
    out.push_back(metric("calibration", "analytic wall", name, "", ratio, kNaN, StabilityRule::within, 0.988, 0.0125));
  }
  return out;
}

} // namespace hb
