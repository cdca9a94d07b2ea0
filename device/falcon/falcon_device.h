#pragma once
// The Novint Falcon as a HapticDevice: firmware, homing, then one 16-byte exchange per servo
// tick (write_force sends the motor commands and reads back the encoders).
#include "device/falcon/falcon_firmware.h"
#include "device/falcon/falcon_kinematics.h"
#include "device/falcon/falcon_packet.h"
#include "device/falcon/falcon_transport.h"
#include "device/haptic_device.h"
#include <chrono>
#include <memory>

namespace hb {

/// Falcon limits: about 8 N peak, 3000 N/m stiffness, 0.04 m workspace radius.
DeviceSpec falcon_spec();

struct FalconOptions {
  std::string firmware_path;        ///< user-supplied firmware; required unless already loaded.
  bool skip_firmware_if_running = true;  ///< probe for running firmware before loading.
  FirmwareOptions firmware;
  bool home = true;                 ///< run homing in open().
  double homing_timeout_s = 15.0;   ///< the user moves the grip fully out and in meanwhile.
  int exchange_timeout_ms = 2;      ///< per read in the servo exchange.
  double no_answer_disconnect_s = 0.25;  ///< this long without a valid packet = disconnected.
  FalconGeometry geometry;
};

class FalconDevice final : public HapticDevice {
public:
  FalconDevice(std::unique_ptr<FalconTransport> transport, FalconOptions options);
  ~FalconDevice() override;

  const DeviceSpec& spec() const noexcept override { return spec_; }
  /// Firmware (if needed), normal mode, first exchange, homing. Throws DeviceError subclasses
  /// whose message names the step.
  void open() override;
  void close() noexcept override;
  DeviceStatus read_state(DeviceState& out) noexcept override;
  DeviceStatus write_force(const Vec3& force_n) noexcept override;

  /// Counters for diagnostics.
  std::uint64_t bad_packets() const noexcept { return bad_packets_; }
  std::uint64_t missed_packets() const noexcept { return missed_; }
  const FalconReport& last_report() const noexcept { return report_; }
  FalconTransport& transport() noexcept { return *transport_; }

private:
  DeviceStatus exchange(const FalconCommand& c) noexcept;
  bool firmware_running() noexcept;
  void home();

  std::unique_ptr<FalconTransport> transport_;
  FalconOptions options_;
  DeviceSpec spec_;
  FalconKinematics kin_;
  FalconReport report_;
  Vec3d position_{Vec3d::Zero()};
  Vec3d theta_{Vec3d::Zero()};
  bool state_valid_ = false;
  bool pending_fault_ = false;  ///< the last exchange failed: the next read reports it.
  bool open_ = false;
  std::uint8_t rx_[64] = {};
  std::size_t rx_fill_ = 0;
  std::uint64_t bad_packets_ = 0, missed_ = 0;
  std::chrono::steady_clock::time_point opened_{}, last_good_{};
};

} // namespace hb
