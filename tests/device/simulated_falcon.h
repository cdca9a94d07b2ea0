#pragma once
// A simulated Novint Falcon behind FalconTransport, at packet level: bootloader handshakes,
// echoed firmware blocks, normal-mode 16-byte exchanges, homing, and injected faults.
#include "device/falcon/falcon_kinematics.h"
#include "device/falcon/falcon_packet.h"
#include "device/falcon/falcon_transport.h"
#include <atomic>
#include <deque>
#include <vector>

namespace hb::test {

enum class SimFault : int { none, no_answer, wrong_echo, garbage, unplug };

class SimulatedFalcon final : public FalconTransport {
public:
  /// `firmware_size`: bytes the bootloader expects; `preloaded`: firmware already running.
  explicit SimulatedFalcon(std::size_t firmware_size, bool preloaded = false);

  void inject(SimFault f) noexcept { fault_.store(static_cast<int>(f)); }
  /// The first `n` tries of handshake 1 get a wrong answer (transient failure).
  void fail_first_handshakes(int n) { handshake_failures_left_ = n; }
  /// Corrupts the echo of firmware byte `offset` (from the next load on).
  void corrupt_firmware_echo_at(std::size_t offset) { corrupt_at_ = offset; }
  void set_position(const Vec3d& p_m);
  void set_buttons(std::uint8_t b) { buttons_ = b; }
  int homing_packets_needed = 5;

  bool firmware_running() const { return running_; }
  const std::vector<std::uint8_t>& firmware() const { return firmware_; }
  FalconCommand last_command() const { return last_cmd_; }
  std::uint64_t packets() const { return packets_; }
  std::uint32_t baud() const { return baud_; }
  std::uint8_t latency() const { return latency_; }

  std::string description() const override { return "simulated Falcon"; }
  void reset() override;
  void purge() override;
  void set_baud_rate(std::uint32_t baud) override;
  void set_line_8n1() override;
  void set_flow_control_none() override;
  void set_latency_timer(std::uint8_t ms) override;
  void set_dtr(bool high) override;
  void set_rts(bool high) override;
  IoResult write(const std::uint8_t* data, std::size_t n, int timeout_ms) noexcept override;
  IoResult read(std::uint8_t* data, std::size_t n, int timeout_ms) noexcept override;

private:
  SimFault fault() const noexcept { return static_cast<SimFault>(fault_.load()); }
  void control_check();
  void respond_packet();

  enum class Boot { idle, handshake1_ok, loading };
  std::size_t firmware_size_;
  std::atomic<int> fault_{0};
  bool running_;
  Boot boot_ = Boot::idle;
  std::uint32_t baud_ = 0;
  std::uint8_t latency_ = 16;
  bool dtr_ = false, rts_ = false, line_8n1_ = false;
  int handshake_failures_left_ = 0;
  std::size_t corrupt_at_ = static_cast<std::size_t>(-1);
  std::vector<std::uint8_t> firmware_;
  std::vector<std::uint8_t> cmd_buf_;
  std::deque<std::uint8_t> out_;
  FalconKinematics kin_;
  std::array<std::int16_t, 3> encoder_{};
  std::uint8_t buttons_ = 0;
  int homing_packets_ = 0;
  std::uint8_t homed_ = 0;
  FalconCommand last_cmd_;
  std::uint64_t packets_ = 0;
};

} // namespace hb::test
