#include "analytic_scene.h"
#include "servo_test_support.h"
#include "device/device_choice.h"
#include "device/servo_loop.h"
#include "errors.h"
#include "device/virtual_device.h"
#include <gtest/gtest.h>
#include <chrono>
#include <cmath>
#include <limits>
#include <thread>

using namespace hb;
using namespace std::chrono_literals;

namespace {

ServoOptions test_options() { return test::servo_test_options(); }
using test::wait_ticks;

} // namespace

TEST(ServoLoopTest, RunsWithTheVirtualDeviceAndStopsCleanly) {
  VirtualDevice dev;
  test::HalfSpaceScene scene(-100.f);  // far below: no contact
  ServoLoop loop(dev, scene, test_options());
  loop.start();
  EXPECT_TRUE(loop.running());
  wait_ticks(loop, 50);
  loop.stop();
  EXPECT_FALSE(loop.running());
  const ServoReport& r = loop.report();
  EXPECT_GE(r.ticks, 50u);
  EXPECT_EQ(r.exit, ServoExit::stopped);
  EXPECT_EQ(r.period.count + 1, r.ticks);
  EXPECT_GT(r.rate_hz, 0.0);
  EXPECT_FALSE(r.realtime_granted);
  EXPECT_EQ(dev.last_force(), Vec3::Zero());
  loop.stop();  // idempotent
}

TEST(ServoLoopTest, SnapshotCarriesTheLiveRateAndP99Period) {
  VirtualDevice dev;
  test::HalfSpaceScene scene(-100.f);
  ServoOptions o = test_options();
  o.rate_hz = 500.0;  // windows of 250 ticks
  ServoLoop loop(dev, scene, o);
  loop.start();
  wait_ticks(loop, 600);
  const ServoSnapshot s = loop.snapshot();
  loop.stop();
  EXPECT_GT(s.rate_hz, 100.f);  // loose: the machine is shared; timing belongs in benchmarks
  EXPECT_LT(s.rate_hz, 600.f);
  EXPECT_GE(s.period_p99_us, 1900.f);  // at least the nominal 2 ms period
}

TEST(ServoLoopTest, DeviceChoiceParsesWhatTheCommandLineAndTheWindowName) {
  EXPECT_EQ(parse_device_choice("virtual").kind, DeviceChoice::Kind::virtual_device);
  EXPECT_EQ(parse_device_choice("falcon").kind, DeviceChoice::Kind::falcon);
  const DeviceChoice replay = parse_device_choice("replay:run.hblog");
  EXPECT_EQ(replay.kind, DeviceChoice::Kind::replay);
  EXPECT_EQ(replay.replay_log, "run.hblog");
  EXPECT_EQ(device_choice_spec(replay), "replay:run.hblog");
  EXPECT_THROW(parse_device_choice("replay:"), InvalidInput);
  EXPECT_THROW(parse_device_choice("mouse"), InvalidInput);
  const OpenedDevice v = open_device(DeviceChoice{});
  ASSERT_NE(v.virtual_device, nullptr);
  EXPECT_EQ(v.device.get(), v.virtual_device);
  EXPECT_THROW(open_device(parse_device_choice("replay:/nonexistent/run.hblog")), Error);
}

TEST(ServoLoopTest, PressingIntoTheSurfacePushesBackOut) {
  VirtualDevice dev;
  test::HalfSpaceScene scene(0.f);
  ServoLoop loop(dev, scene, test_options());
  dev.set_target(Vec3(0.f, 0.f, -0.002f));  // 2 mm below the surface
  loop.start();
  wait_ticks(loop, 100);
  const ServoSnapshot s = loop.snapshot();
  loop.stop();
  EXPECT_EQ(s.contact, 1);
  EXPECT_NEAR(s.depth, 2.f, 1e-3f);
  EXPECT_NEAR(s.desired_force_n[2], 2.f, 1e-3f);  // 1000 N/m * 2 mm
  EXPECT_GT(s.force_n[2], 0.f);
  EXPECT_LE(s.force_n[2], 2.f + 1e-5f);
}

TEST(ServoLoopTest, StiffnessIsLimitedToTheDevice) {
  VirtualDevice dev;
  test::HalfSpaceScene scene(0.f);
  ServoOptions o = test_options();
  o.workspace.stiffness_n_per_m = 1e6;  // far above the 3000 N/m the device can render
  ServoLoop loop(dev, scene, o);
  loop.start();
  loop.stop();
  EXPECT_TRUE(loop.report().stiffness_limited);
  EXPECT_FLOAT_EQ(loop.report().stiffness_n_per_m, 3000.f);
}

TEST(ServoLoopTest, DisconnectMidRunZeroesForceStopsAndReports) {
  VirtualDevice dev;
  test::HalfSpaceScene scene(0.f);
  ServoLoop loop(dev, scene, test_options());
  dev.set_target(Vec3(0.f, 0.f, -0.002f));
  loop.start();
  wait_ticks(loop, 30);
  dev.simulate_disconnect();
  for (int i = 0; i < 1000 && loop.running(); ++i) std::this_thread::sleep_for(1ms);
  EXPECT_FALSE(loop.running());
  loop.stop();
  EXPECT_EQ(loop.report().exit, ServoExit::disconnected);
  EXPECT_NE(loop.report().exit_message.find("force zeroed"), std::string::npos);
  EXPECT_EQ(loop.snapshot().running, 0);
  EXPECT_EQ(loop.snapshot().force_n[2], 0.f);
}

TEST(ServoLoopTest, EmergencyStopZeroesForce) {
  VirtualDevice dev;
  test::HalfSpaceScene scene(0.f);
  ServoLoop loop(dev, scene, test_options());
  dev.set_target(Vec3(0.f, 0.f, -0.002f));
  loop.start();
  wait_ticks(loop, 50);
  loop.emergency_stop();
  const std::uint64_t t = loop.snapshot().tick;
  wait_ticks(loop, t + 5);
  const ServoSnapshot s = loop.snapshot();
  loop.stop();
  EXPECT_EQ(s.emergency_stopped, 1);
  EXPECT_EQ(s.force_n[2], 0.f);
  EXPECT_GT(loop.report().safety[static_cast<int>(SafetyEvent::emergency_stop)], 0u);
}

TEST(ServoLoopTest, NanFromTheSceneNeverReachesTheDevice) {
  VirtualDevice dev;
  test::NanScene scene;
  ServoLoop loop(dev, scene, test_options());
  loop.start();
  wait_ticks(loop, 20);
  loop.stop();
  EXPECT_EQ(dev.last_force(), Vec3::Zero());
  EXPECT_GE(loop.report().safety[static_cast<int>(SafetyEvent::non_finite)], 20u);
}

TEST(ServoLoopTest, DeviceFaultIsCountedAndRampedBack) {
  VirtualDevice dev;
  test::HalfSpaceScene scene(0.f);
  ServoLoop loop(dev, scene, test_options());
  dev.set_target(Vec3(0.f, 0.f, -0.001f));
  loop.start();
  wait_ticks(loop, 30);
  dev.simulate_fault();
  const std::uint64_t t = loop.snapshot().tick;
  wait_ticks(loop, t + 30);
  loop.stop();
  EXPECT_EQ(loop.report().safety[static_cast<int>(SafetyEvent::device_fault)], 1u);
}

TEST(ServoLoopTest, RejectsABadRate) {
  VirtualDevice dev;
  test::HalfSpaceScene scene;
  ServoOptions o = test_options();
  o.rate_hz = -5;
  ServoLoop loop(dev, scene, o);
  EXPECT_THROW(loop.start(), InvalidInput);
}

TEST(ServoLoopTest, ScriptedTrajectoryRunsThroughTheSamePath) {
  VirtualDevice dev(circle_probe_trajectory(0.01f, 0.005f, 0.05), 1e-3);
  test::HalfSpaceScene scene(0.f);
  ServoLoop loop(dev, scene, test_options());
  loop.start();
  wait_ticks(loop, 100);
  loop.stop();
  EXPECT_GE(dev.reads(), 100u);
  EXPECT_GT(loop.report().compute.count, 0u);
}

// Found by fuzzing: a non-finite or overflowing force law gave NaN or silently zero force.
TEST(ServoLoopTest, RejectsANonFiniteOrOverflowingForceLaw) {
  VirtualDevice dev;
  test::HalfSpaceScene scene;
  for (float k : {std::numeric_limits<float>::quiet_NaN(), std::numeric_limits<float>::infinity(), -500.f, 0.f}) {
    ServoOptions o = test_options();
    o.workspace.stiffness_n_per_m = k;
    ServoLoop loop(dev, scene, o);
    EXPECT_THROW(loop.start(), InvalidInput) << k;
  }
  ServoOptions o = test_options();
  o.workspace.stiffness_n_per_m = 1e39;  // finite, but not as the law's float
  ServoLoop loop(dev, scene, o);
  EXPECT_THROW(loop.start(), InvalidInput);
  ServoOptions tiny = test_options();
  tiny.workspace.metres_per_unit = 1e-320;  // the device to the model (1 / metres per unit) overflows
  ServoLoop tiny_loop(dev, scene, tiny);
  EXPECT_THROW(tiny_loop.start(), InvalidInput);
}

TEST(ServoLoopTest, RejectsARateBelowOneHertz) {
  VirtualDevice dev;
  test::HalfSpaceScene scene;
  for (double rate : {0.05, 1e-300, std::nan("")}) {
    ServoOptions o = test_options();
    o.rate_hz = rate;
    ServoLoop loop(dev, scene, o);
    EXPECT_THROW(loop.start(), InvalidInput) << rate;
  }
}
