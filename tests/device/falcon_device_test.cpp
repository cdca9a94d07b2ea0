#include "analytic_scene.h"
#include "device/falcon/falcon_device.h"
#include "device/servo_loop.h"
#include "simulated_falcon.h"
#include <gtest/gtest.h>
#include <chrono>
#include <cstdio>
#include <fstream>
#include <thread>

using namespace hb;
using hb::test::SimFault;
using hb::test::SimulatedFalcon;

namespace {

struct FirmwareFile {
  std::string path = ::testing::TempDir() + "hb_falcon_fw_test.bin";
  std::vector<std::uint8_t> bytes = std::vector<std::uint8_t>(700, 0x5A);
  FirmwareFile() {
    std::ofstream(path, std::ios::binary).write(reinterpret_cast<const char*>(bytes.data()),
                                                 static_cast<std::streamsize>(bytes.size()));
  }
  ~FirmwareFile() { std::remove(path.c_str()); }
};

FalconOptions options(const std::string& fw) {
  FalconOptions o;
  o.firmware_path = fw;
  o.firmware.timeout_ms = 1;
  o.firmware.handshake_attempts = 3;
  o.homing_timeout_s = 2.0;
  return o;
}

} // namespace

TEST(FalconDeviceTest, OpenLoadsFirmwareAndHomes) {
  FirmwareFile fw;
  auto sim = std::make_unique<SimulatedFalcon>(fw.bytes.size());
  SimulatedFalcon* s = sim.get();
  FalconDevice dev(std::move(sim), options(fw.path));
  dev.open();
  EXPECT_TRUE(s->firmware_running());
  EXPECT_EQ(s->firmware(), fw.bytes);
  EXPECT_EQ(dev.last_report().homed, 0x7);
  DeviceState st;
  EXPECT_EQ(dev.read_state(st), DeviceStatus::ok);
  dev.close();
}

TEST(FalconDeviceTest, SkipsFirmwareWhenAlreadyRunning) {
  auto sim = std::make_unique<SimulatedFalcon>(700, /*preloaded=*/true);
  SimulatedFalcon* s = sim.get();
  FalconDevice dev(std::move(sim), options(""));
  dev.open();
  EXPECT_TRUE(s->firmware().empty());
}

TEST(FalconDeviceTest, NoFirmwarePathGivesAClearError) {
  FalconDevice dev(std::make_unique<SimulatedFalcon>(700), options(""));
  try {
    dev.open();
    FAIL() << "open() should throw";
  } catch (const DeviceError& e) {
    EXPECT_NE(std::string(e.what()).find("no firmware"), std::string::npos) << e.what();
  }
}

TEST(FalconDeviceTest, HomingTimeoutNamesTheAxes) {
  auto sim = std::make_unique<SimulatedFalcon>(700, true);
  sim->homing_packets_needed = 1 << 30;
  FalconOptions o = options("");
  o.homing_timeout_s = 0.05;
  FalconDevice dev(std::move(sim), o);
  try {
    dev.open();
    FAIL() << "open() should throw";
  } catch (const DeviceTimeout& e) {
    EXPECT_NE(std::string(e.what()).find("axes not homed: 1, 2, 3"), std::string::npos) << e.what();
  }
}

TEST(FalconDeviceTest, PositionFollowsTheSimulatedArm) {
  auto sim = std::make_unique<SimulatedFalcon>(700, true);
  SimulatedFalcon* s = sim.get();
  FalconDevice dev(std::move(sim), options(""));
  dev.open();
  const Vec3d target(0.012, -0.02, 0.015);
  s->set_position(target);
  s->set_buttons(0x2);
  ASSERT_EQ(dev.write_force(Vec3::Zero()), DeviceStatus::ok);
  DeviceState st;
  ASSERT_EQ(dev.read_state(st), DeviceStatus::ok);
  // Encoder quantisation: 6.4e-4 rad per count on a 0.06 m arm is well under a millimetre.
  EXPECT_LT((st.position_m.cast<double>() - target).norm(), 1e-3);
  EXPECT_EQ(st.buttons, 0x2u);
}

TEST(FalconDeviceTest, ForceBecomesMotorCommands) {
  auto sim = std::make_unique<SimulatedFalcon>(700, true);
  SimulatedFalcon* s = sim.get();
  FalconDevice dev(std::move(sim), options(""));
  dev.open();
  ASSERT_EQ(dev.write_force(Vec3(0, 0, 4)), DeviceStatus::ok);
  const auto m = s->last_command().motor;
  EXPECT_TRUE(m[0] != 0 || m[1] != 0 || m[2] != 0);
  ASSERT_EQ(dev.write_force(Vec3::Zero()), DeviceStatus::ok);
  EXPECT_EQ(s->last_command().motor, (std::array<std::int16_t, 3>{0, 0, 0}));
}

TEST(FalconDeviceTest, GarbagePacketsAreSkipped) {
  auto sim = std::make_unique<SimulatedFalcon>(700, true);
  SimulatedFalcon* s = sim.get();
  FalconDevice dev(std::move(sim), options(""));
  dev.open();
  s->inject(SimFault::garbage);
  int ok = 0;
  DeviceState st;
  for (int i = 0; i < 30; ++i) {
    dev.write_force(Vec3::Zero());
    if (dev.read_state(st) == DeviceStatus::ok) ++ok;
    ASSERT_TRUE(st.position_m.allFinite());
  }
  EXPECT_GT(ok, 10);
  EXPECT_GT(dev.bad_packets(), 0u);
}

TEST(FalconDeviceTest, NoAnswerIsAFaultThenADisconnect) {
  auto sim = std::make_unique<SimulatedFalcon>(700, true);
  SimulatedFalcon* s = sim.get();
  FalconOptions o = options("");
  o.no_answer_disconnect_s = 0.05;
  FalconDevice dev(std::move(sim), o);
  dev.open();
  s->inject(SimFault::no_answer);
  EXPECT_EQ(dev.write_force(Vec3::Zero()), DeviceStatus::fault);
  DeviceState st;
  EXPECT_EQ(dev.read_state(st), DeviceStatus::fault);
  std::this_thread::sleep_for(std::chrono::milliseconds(80));
  EXPECT_EQ(dev.write_force(Vec3::Zero()), DeviceStatus::disconnected);
}

TEST(FalconDeviceTest, UnplugMidRunStopsTheServoLoopAndReports) {
  auto sim = std::make_unique<SimulatedFalcon>(700, true);
  SimulatedFalcon* s = sim.get();
  FalconDevice dev(std::move(sim), options(""));
  hb::test::HalfSpaceScene scene(0.f);
  ServoOptions so;
  so.request_realtime = false;
  ServoLoop loop(dev, scene, so);
  loop.start();
  std::this_thread::sleep_for(std::chrono::milliseconds(50));
  s->inject(SimFault::unplug);
  for (int i = 0; i < 200 && loop.running(); ++i)
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
  EXPECT_FALSE(loop.running());
  loop.stop();
  EXPECT_EQ(loop.report().exit, ServoExit::disconnected);
  EXPECT_NE(loop.report().exit_message.find("disconnected"), std::string::npos);
  EXPECT_GT(loop.report().ticks, 0u);
  const ServoSnapshot snap = loop.snapshot();
  EXPECT_EQ(snap.running, 0);
  EXPECT_EQ(snap.force_n[0], 0.f);
}
