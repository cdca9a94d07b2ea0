#include "device/device_error.h"
#include "device/falcon/falcon_firmware.h"
#include "simulated_falcon.h"
#include <gtest/gtest.h>
#include <cstdio>
#include <fstream>

using namespace hb;
using hb::test::SimFault;
using hb::test::SimulatedFalcon;

namespace {

std::vector<std::uint8_t> fake_firmware(std::size_t n) {
  std::vector<std::uint8_t> fw(n);
  for (std::size_t i = 0; i < n; ++i) fw[i] = static_cast<std::uint8_t>(i * 31 + 7);
  return fw;
}

FirmwareOptions fast() {
  FirmwareOptions o;
  o.attempts = 2;
  o.handshake_attempts = 3;
  o.timeout_ms = 1;
  return o;
}

std::string message_of(const std::function<void()>& f) {
  try {
    f();
  } catch (const std::exception& e) {
    return e.what();
  }
  return "";
}

} // namespace

TEST(FalconFirmwareTest, LoadsFirmwareInVerifiedBlocksAfterTheHandshakes) {
  const auto fw = fake_firmware(1000);  // 8 blocks, the last one short
  SimulatedFalcon sim(fw.size());
  load_falcon_firmware(sim, fw, fast());
  EXPECT_TRUE(sim.firmware_running());
  EXPECT_EQ(sim.firmware(), fw);
  set_falcon_normal_mode(sim);
  EXPECT_EQ(sim.latency(), 1);
  EXPECT_EQ(sim.baud(), falcon_normal_baud);
}

TEST(FalconFirmwareTest, RetriesATransientHandshakeFailure) {
  const auto fw = fake_firmware(300);
  SimulatedFalcon sim(fw.size());
  sim.fail_first_handshakes(2);
  EXPECT_NO_THROW(load_falcon_firmware(sim, fw, fast()));
  EXPECT_TRUE(sim.firmware_running());
}

TEST(FalconFirmwareTest, NoAnswerIsATimeoutNamingHandshakeOne) {
  SimulatedFalcon sim(300);
  sim.inject(SimFault::no_answer);
  const std::string msg = message_of([&] { load_falcon_firmware(sim, fake_firmware(300), fast()); });
  EXPECT_NE(msg.find("handshake 1"), std::string::npos) << msg;
  EXPECT_NE(msg.find("no answer"), std::string::npos) << msg;
  EXPECT_NE(msg.find("attempt 2"), std::string::npos) << msg;
  EXPECT_THROW(load_falcon_firmware(sim, fake_firmware(300), fast()), DeviceTimeout);
}

TEST(FalconFirmwareTest, WrongEchoIsAProtocolErrorNamingTheStep) {
  SimulatedFalcon sim(300);
  sim.inject(SimFault::wrong_echo);
  const std::string msg = message_of([&] { load_falcon_firmware(sim, fake_firmware(300), fast()); });
  EXPECT_NE(msg.find("handshake 1"), std::string::npos) << msg;
  EXPECT_NE(msg.find("wrong echo"), std::string::npos) << msg;
  EXPECT_THROW(load_falcon_firmware(sim, fake_firmware(300), fast()), DeviceProtocolError);
}

TEST(FalconFirmwareTest, BadBlockEchoNamesTheBlockAndByte) {
  const auto fw = fake_firmware(1000);
  SimulatedFalcon sim(fw.size());
  sim.corrupt_firmware_echo_at(300);
  const std::string msg = message_of([&] { load_falcon_firmware(sim, fw, fast()); });
  EXPECT_NE(msg.find("firmware block 3 of 8"), std::string::npos) << msg;
  EXPECT_NE(msg.find("byte 300"), std::string::npos) << msg;
}

TEST(FalconFirmwareTest, UnplugDuringLoadIsDisconnected) {
  SimulatedFalcon sim(300);
  sim.inject(SimFault::unplug);
  EXPECT_THROW(load_falcon_firmware(sim, fake_firmware(300), fast()), DeviceDisconnected);
}

TEST(FalconFirmwareTest, MissingFirmwareFileNamesThePath) {
  const std::string msg = message_of([] { read_firmware_file("/nonexistent/falcon_fw.bin"); });
  EXPECT_NE(msg.find("/nonexistent/falcon_fw.bin"), std::string::npos) << msg;
  EXPECT_THROW(read_firmware_file("/nonexistent/falcon_fw.bin"), IoError);
}
