// The servo's force path in the stability harness: stalls and the energy guard (label `stability`).
#include "device/safety_tick_filter.h"
#include "stability/trajectory.h"
#include <gtest/gtest.h>

using namespace hb;

namespace {

struct WallRun {
  AnalyticWall wall{Vec3::Zero(), Vec3(0, 0, 1)};
  Workspace map;
  ForceLaw law;
  explicit WallRun(float k) {
    map.metres_per_unit = 1.0;
    law.stiffness_n_per_m = k;
    law.metres_per_unit = 1.f;
  }
};

std::unique_ptr<SafetyTickFilter> warm_filter(FaultResponse response, bool guard) {
  SafetyOptions s;
  s.fault_response = response;
  EnergyGuardOptions g;
  g.enabled = guard;
  auto f = std::make_unique<SafetyTickFilter>(device_spec_of(falcon_profile()), s, g, 1e-3);
  for (int i = 0; i < 1000; ++i) f->apply(Vec3d::Zero(), Vec3d::Zero(), Vec3d::Zero(), 0.0);
  return f;
}

// Light grip pushing about 1.5 N into the wall at k = 1500 N/m, a 10 ms stall at 1 s; the
// deepest penetration after it.
double deepest_after_stall(FaultResponse response) {
  const WallRun w(1500.f);
  auto f = warm_filter(response, false);
  ClosedLoopRun run;
  run.device = falcon_profile();
  run.hand = light_grip();
  run.start_m = Vec3d(0, 0, 0.002);
  run.set_point = [](double t) { return Vec3d(0, 0, t < 0.5 ? 0.002 - 0.064 * t : -0.03); };
  run.seconds = 2.0;
  run.stylus_m = 0.008;
  run.stalls = {Stall{1000, 10}};
  run.filter = f.get();
  const auto rec = run_closed_loop(w.wall, w.law, w.map, run);
  double deepest = 0;
  for (const auto& r : rec) deepest = std::max(deepest, -r.x.z());
  return deepest;
}

} // namespace

TEST(StabilityFilterTest, StallWhileHoldingPopsThroughOnlyWithZeroAndRamp) {
  EXPECT_GT(deepest_after_stall(FaultResponse::zero_and_ramp), 0.0075);  // the stylus (8 mm) passes
  EXPECT_LT(deepest_after_stall(FaultResponse::hold_and_ramp), 0.002);   // held at about 1 mm
}

TEST(StabilityFilterTest, EnergyGuardMakesAnOverStiffWallPassive) {
  // k = 3 K_max, damping at the bound of K_max: restitution > 1 without the guard.
  const WallRun w(9000.f);
  for (bool guard : {false, true}) {
    auto f = warm_filter(FaultResponse::hold_and_ramp, guard);
    SafetyOptions unlimited;
    ClosedLoopRun run;
    run.device = falcon_profile();
    run.device.damping_n_s_per_m = 1.5;
    run.start_m = Vec3d(0, 0, 1e-9);
    run.start_velocity = Vec3d(0, 0, -0.05);
    run.seconds = 0.3;
    run.stylus_m = 0.05;
    run.stop_after_contact_ticks = 1;
    run.filter = f.get();
    const auto rec = run_closed_loop(w.wall, w.law, w.map, run);
    const double restitution = rec.back().v.z() / 0.05;
    if (guard) EXPECT_LE(restitution, 1.0);
    else EXPECT_GT(restitution, 1.02);
  }
}
