#include "device/safety.h"
#include <gtest/gtest.h>
#include <cmath>
#include <limits>
#include <random>

using namespace hb;

namespace {

DeviceSpec spec8() {
  DeviceSpec s;
  s.max_force_n = 8.f;
  s.max_continuous_force_n = 4.f;
  return s;
}

SafetyOptions no_ramp_no_rate() {
  SafetyOptions o;
  o.ramp_seconds = 0.f;
  o.max_force_rate_n_per_s = 1e9f;
  o.continuous_window_s = 1000.f;
  return o;
}

SafetyInput force(float x, float y, float z) {
  SafetyInput in;
  in.desired_force_n = Vec3(x, y, z);
  return in;
}

bool has(const SafetyFilter& f, SafetyEvent e) {
  return f.last_flags() & (1u << static_cast<unsigned>(e));
}

} // namespace

TEST(SafetyTest, NanForceGivesZero) {
  SafetyFilter f(spec8(), no_ramp_no_rate(), 1e-3);
  f.apply(force(1, 0, 0));
  const Vec3 out = f.apply(force(std::numeric_limits<float>::quiet_NaN(), 0, 0));
  EXPECT_EQ(out, Vec3::Zero());
  EXPECT_TRUE(has(f, SafetyEvent::non_finite));
  EXPECT_EQ(f.counters()[static_cast<int>(SafetyEvent::non_finite)], 1u);
}

TEST(SafetyTest, InfPositionGivesZero) {
  SafetyFilter f(spec8(), no_ramp_no_rate(), 1e-3);
  SafetyInput in = force(1, 1, 1);
  in.position_m = Vec3(0, std::numeric_limits<float>::infinity(), 0);
  EXPECT_EQ(f.apply(in), Vec3::Zero());
  EXPECT_TRUE(has(f, SafetyEvent::non_finite));
}

TEST(SafetyTest, NanGivesZeroEvenWhenDisabled) {
  SafetyOptions o = no_ramp_no_rate();
  o.enabled = false;
  SafetyFilter f(spec8(), o, 1e-3);
  EXPECT_EQ(f.apply(force(0, std::nanf(""), 0)), Vec3::Zero());
}

TEST(SafetyTest, ClampsToMaximumForceKeepingDirection) {
  SafetyFilter f(spec8(), no_ramp_no_rate(), 1e-3);
  const Vec3 out = f.apply(force(30, 40, 0));
  EXPECT_NEAR(out.norm(), 8.f, 1e-5f);
  EXPECT_NEAR(out.x() / out.y(), 0.75f, 1e-5f);
  EXPECT_TRUE(has(f, SafetyEvent::force_clamped));
}

TEST(SafetyTest, RampsInAtStart) {
  SafetyOptions o = no_ramp_no_rate();
  o.ramp_seconds = 0.01f;  // 10 ticks
  SafetyFilter f(spec8(), o, 1e-3);
  float prev = 0.f;
  for (int i = 1; i <= 10; ++i) {
    const float x = f.apply(force(2, 0, 0)).x();
    EXPECT_GT(x, prev);
    EXPECT_NEAR(x, 2.f * i / 10.f, 1e-5f);
    prev = x;
  }
  EXPECT_FLOAT_EQ(f.apply(force(2, 0, 0)).x(), 2.f);
}

TEST(SafetyTest, RampsInAgainAfterFault) {
  SafetyOptions o = no_ramp_no_rate();
  o.fault_response = FaultResponse::zero_and_ramp;
  o.ramp_seconds = 0.004f;  // 4 ticks
  SafetyFilter f(spec8(), o, 1e-3);
  for (int i = 0; i < 10; ++i) f.apply(force(2, 0, 0));
  SafetyInput fault = force(2, 0, 0);
  fault.device_fault = true;
  EXPECT_EQ(f.apply(fault), Vec3::Zero());
  EXPECT_TRUE(has(f, SafetyEvent::device_fault));
  EXPECT_NEAR(f.apply(force(2, 0, 0)).x(), 0.5f, 1e-6f);
  EXPECT_NEAR(f.apply(force(2, 0, 0)).x(), 1.0f, 1e-6f);
}

TEST(SafetyTest, LimitsRateOfChange) {
  SafetyOptions o = no_ramp_no_rate();
  o.max_force_rate_n_per_s = 1000.f;  // 1 N per 1 ms tick
  SafetyFilter f(spec8(), o, 1e-3);
  EXPECT_NEAR(f.apply(force(5, 0, 0)).x(), 1.f, 1e-5f);
  EXPECT_TRUE(has(f, SafetyEvent::rate_limited));
  EXPECT_NEAR(f.apply(force(5, 0, 0)).x(), 2.f, 1e-5f);
  EXPECT_NEAR(f.apply(force(-5, 0, 0)).x(), 1.f, 1e-5f);
}

TEST(SafetyTest, WatchdogZeroesForceWhenLate) {
  SafetyOptions o = no_ramp_no_rate();
  o.fault_response = FaultResponse::zero_and_ramp;
  o.watchdog_bound_s = 0.002;
  SafetyFilter f(spec8(), o, 1e-3);
  SafetyInput in = force(1, 0, 0);
  in.lateness_s = 0.0019;
  EXPECT_FLOAT_EQ(f.apply(in).x(), 1.f);
  in.lateness_s = 0.0021;
  EXPECT_EQ(f.apply(in), Vec3::Zero());
  EXPECT_TRUE(has(f, SafetyEvent::watchdog));
}

TEST(SafetyTest, EmergencyStopLatchesZeroUntilCleared) {
  SafetyOptions o = no_ramp_no_rate();
  o.ramp_seconds = 0.002f;
  SafetyFilter f(spec8(), o, 1e-3);
  for (int i = 0; i < 5; ++i) f.apply(force(1, 0, 0));
  f.set_emergency_stop(true);
  for (int i = 0; i < 5; ++i) EXPECT_EQ(f.apply(force(1, 0, 0)), Vec3::Zero());
  EXPECT_TRUE(has(f, SafetyEvent::emergency_stop));
  f.set_emergency_stop(false);
  EXPECT_NEAR(f.apply(force(1, 0, 0)).x(), 0.5f, 1e-6f);  // ramps back in
}

TEST(SafetyTest, ContinuousForceIsLimited) {
  SafetyOptions o = no_ramp_no_rate();
  o.continuous_window_s = 0.05f;  // 50 ticks
  SafetyFilter f(spec8(), o, 1e-3);
  Vec3 out;
  for (int i = 0; i < 2000; ++i) out = f.apply(force(7, 0, 0));
  EXPECT_LE(out.norm(), 4.f + 1e-4f);
  EXPECT_GT(f.counters()[static_cast<int>(SafetyEvent::continuous_limited)], 0u);
  // Short peaks above the continuous rating are allowed.
  SafetyFilter g(spec8(), o, 1e-3);
  EXPECT_FLOAT_EQ(g.apply(force(7, 0, 0)).x(), 7.f);
}

TEST(SafetyTest, OutputIsAlwaysFiniteAndBounded) {
  SafetyFilter f(spec8(), SafetyOptions{}, 1e-3);
  std::mt19937 rng(7);
  std::uniform_real_distribution<float> u(-1e6f, 1e6f);
  for (int i = 0; i < 5000; ++i) {
    SafetyInput in = force(u(rng), u(rng), u(rng));
    if (i % 97 == 0) in.desired_force_n.y() = std::numeric_limits<float>::infinity();
    const Vec3 out = f.apply(in);
    ASSERT_TRUE(out.allFinite());
    ASSERT_LE(out.norm(), 8.f + 1e-4f);
  }
}

TEST(SafetyTest, LateTickHoldsTheForceAndRampsFromIt) {
  SafetyOptions o = no_ramp_no_rate();
  o.ramp_seconds = 0.008f;  // 8 ticks: the ceiling grows by 8 N / 8 = 1 N a tick
  SafetyFilter f(spec8(), o, 1e-3);
  for (int i = 0; i < 20; ++i) f.apply(force(2, 0, 0));
  SafetyInput late = force(3.5f, 0, 0);  // the probe sank during the stall: a larger force
  late.lateness_s = 0.005;
  EXPECT_NEAR(f.apply(late).x(), 2.f, 1e-5f);  // held, not zero, not re-stiffened
  EXPECT_TRUE(has(f, SafetyEvent::watchdog));
  EXPECT_NEAR(f.apply(force(3.5f, 0, 0)).x(), 3.f, 1e-5f);  // ramps from the held force
  EXPECT_NEAR(f.apply(force(3.5f, 0, 0)).x(), 3.5f, 1e-5f);
  EXPECT_NEAR(f.apply(force(1, 0, 0)).x(), 1.f, 1e-5f);     // a smaller force passes at once
}

TEST(SafetyTest, DeviceFaultHoldsTheForceByDefault) {
  SafetyOptions o = no_ramp_no_rate();
  o.ramp_seconds = 0.5f;
  SafetyFilter f(spec8(), o, 1e-3);
  for (int i = 0; i < 600; ++i) f.apply(force(1.5f, 0, 0));
  SafetyInput fault = force(1.5f, 0, 0);
  fault.device_fault = true;
  EXPECT_NEAR(f.apply(fault).x(), 1.5f, 1e-5f);
  EXPECT_TRUE(has(f, SafetyEvent::device_fault));
}
