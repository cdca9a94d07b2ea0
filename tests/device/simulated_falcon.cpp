#include "simulated_falcon.h"
#include "device/device_error.h"
#include "device/falcon/falcon_firmware.h"

namespace hb::test {

SimulatedFalcon::SimulatedFalcon(std::size_t firmware_size, bool preloaded)
    : firmware_size_(firmware_size), running_(preloaded) {
  set_position(Vec3d::Zero());
}

void SimulatedFalcon::set_position(const Vec3d& p) {
  Vec3d theta;
  if (kin_.inverse(p, theta)) encoder_ = kin_.theta_to_encoder(theta);
}

void SimulatedFalcon::control_check() {
  if (fault() == SimFault::unplug) throw DeviceDisconnected("simulated Falcon: unplugged");
}

void SimulatedFalcon::reset() { control_check(); out_.clear(); cmd_buf_.clear(); }
void SimulatedFalcon::purge() { control_check(); out_.clear(); cmd_buf_.clear(); }
void SimulatedFalcon::set_baud_rate(std::uint32_t b) { control_check(); baud_ = b; }
void SimulatedFalcon::set_line_8n1() { control_check(); line_8n1_ = true; }
void SimulatedFalcon::set_flow_control_none() { control_check(); }
void SimulatedFalcon::set_latency_timer(std::uint8_t ms) { control_check(); latency_ = ms; }
void SimulatedFalcon::set_dtr(bool high) {
  control_check();
  // A DTR pulse (low -> high) at 9600 baud restarts the bootloader unless firmware runs.
  if (high && !dtr_ && !running_) {
    boot_ = Boot::idle;
    firmware_.clear();
  }
  dtr_ = high;
}
void SimulatedFalcon::set_rts(bool high) { control_check(); rts_ = high; }

IoResult SimulatedFalcon::write(const std::uint8_t* d, std::size_t n, int) noexcept {
  const SimFault f = fault();
  if (f == SimFault::unplug) return {IoStatus::disconnected, 0};
  const bool silent = f == SimFault::no_answer;
  if (!running_) {
    if (boot_ == Boot::idle && baud_ == falcon_bootloader_baud && line_8n1_ && dtr_ && n == 3 &&
        d[0] == 0x0A && d[1] == 0x43 && d[2] == 0x0D) {
      if (silent) return {IoStatus::ok, n};
      if (f == SimFault::wrong_echo || handshake_failures_left_ > 0) {
        if (handshake_failures_left_ > 0) --handshake_failures_left_;
        out_.insert(out_.end(), {0x0A, 0x45, 0x2C, 0x0D});
      } else {
        out_.insert(out_.end(), {0x0A, 0x44, 0x2C, 0x0D});
        boot_ = Boot::handshake1_ok;
      }
    } else if (boot_ == Boot::handshake1_ok && !dtr_ && baud_ == falcon_firmware_load_baud &&
               n == 1 && d[0] == 'A') {
      if (!silent) {
        out_.push_back(f == SimFault::wrong_echo ? 'B' : 'A');
        if (f != SimFault::wrong_echo) boot_ = Boot::loading;
      }
    } else if (boot_ == Boot::loading) {
      for (std::size_t i = 0; i < n; ++i) {
        std::uint8_t echo = d[i];
        if (firmware_.size() == corrupt_at_) echo ^= 0x5A;
        firmware_.push_back(d[i]);
        if (!silent) out_.push_back(echo);
      }
      if (firmware_.size() >= firmware_size_) {
        running_ = true;
        boot_ = Boot::idle;
      }
    }
    return {IoStatus::ok, n};
  }
  // Firmware running: 16-byte packets at the normal baud rate.
  if (baud_ != falcon_normal_baud) return {IoStatus::ok, n};
  cmd_buf_.insert(cmd_buf_.end(), d, d + n);
  while (cmd_buf_.size() >= falcon_packet_size) {
    FalconPacket p;
    std::copy(cmd_buf_.begin(), cmd_buf_.begin() + falcon_packet_size, p.begin());
    cmd_buf_.erase(cmd_buf_.begin(), cmd_buf_.begin() + falcon_packet_size);
    FalconCommand c;
    if (!decode_command(p, c)) continue;
    last_cmd_ = c;
    ++packets_;
    if (c.homing_mode && ++homing_packets_ >= homing_packets_needed) homed_ = 0x7;
    if (!silent) respond_packet();
  }
  return {IoStatus::ok, n};
}

void SimulatedFalcon::respond_packet() {
  if (fault() == SimFault::garbage) {
    // Noise before the frame, and every third packet a broken frame instead of a good one.
    out_.insert(out_.end(), {0x00, 'x', '>', 0xFF});
    if (packets_ % 3 == 0) {
      out_.insert(out_.end(), {'<', 'A', 'B', '<', 'Z', 0x01, 'A', 'A', 'A', 'A', 'A', 'A', 'A', 'A', 'A', '>'});
      return;
    }
  }
  FalconReport r;
  r.encoder = encoder_;
  r.homed = homed_;
  r.buttons = buttons_;
  FalconPacket p;
  encode_report(r, p);
  out_.insert(out_.end(), p.begin(), p.end());
}

IoResult SimulatedFalcon::read(std::uint8_t* d, std::size_t n, int) noexcept {
  if (fault() == SimFault::unplug) return {IoStatus::disconnected, 0};
  if (out_.empty()) return {IoStatus::timeout, 0};
  std::size_t k = 0;
  while (k < n && !out_.empty()) {
    d[k++] = out_.front();
    out_.pop_front();
  }
  return {IoStatus::ok, k};
}

} // namespace hb::test
