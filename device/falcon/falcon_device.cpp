// Falcon device.
// 1. open(): if no firmware answers packets, load the user's firmware file; normal mode;
//    first exchange; homing (homing-mode packets until the three homed bits are set).
// 2. write_force(): force -> J^T -> motor counts -> packet; read until one whole frame arrives
//    (garbage before '<' is skipped); decode; encoders -> angles -> forward kinematics (Newton
//    warm-started from the last position).
// 3. No valid frame: DeviceStatus::fault (safety zeroes and re-ramps); none for
//    `no_answer_disconnect_s` or a transport disconnect: DeviceStatus::disconnected.
#include "device/falcon/falcon_device.h"
#include <cstring>
#include <thread>

namespace hb {

DeviceSpec falcon_spec() {
  DeviceSpec s;
  s.name = "Novint Falcon";
  s.workspace_radius_m = 0.04f;
  s.max_force_n = 8.f;
  s.max_continuous_force_n = 4.f;
  s.max_stiffness_n_per_m = 3000.f;
  s.max_damping_n_s_per_m = 10.f;
  return s;
}

FalconDevice::FalconDevice(std::unique_ptr<FalconTransport> transport, FalconOptions options)
    : transport_(std::move(transport)),
      options_(std::move(options)),
      spec_(falcon_spec()),
      kin_(options_.geometry) {
  if (!transport_) throw DeviceError("Falcon: no transport");
}

FalconDevice::~FalconDevice() { close(); }

bool FalconDevice::firmware_running() noexcept {
  try {
    set_falcon_normal_mode(*transport_);
  } catch (...) {
    return false;
  }
  rx_fill_ = 0;
  for (int i = 0; i < 3; ++i)
    if (exchange(FalconCommand{}) == DeviceStatus::ok) return true;
  return false;
}

void FalconDevice::open() {
  const std::string who = transport_->description();
  opened_ = last_good_ = std::chrono::steady_clock::now();
  state_valid_ = false;
  if (!(options_.skip_firmware_if_running && firmware_running())) {
    if (options_.firmware_path.empty())
      throw DeviceError(who + ": the Falcon has no firmware running and no firmware file is set "
                              "(the firmware cannot be shipped; pass its path with --firmware)");
    const auto fw = read_firmware_file(options_.firmware_path);
    load_falcon_firmware(*transport_, fw, options_.firmware);
    set_falcon_normal_mode(*transport_);
    rx_fill_ = 0;
    bool ok = false;
    for (int i = 0; i < 20 && !ok; ++i) ok = exchange(FalconCommand{}) == DeviceStatus::ok;
    if (!ok)
      throw DeviceProtocolError(who + ": firmware loaded but the Falcon sends no valid packets "
                                      "(wrong firmware file?)");
  }
  if (options_.home) home();
  open_ = true;
}

void FalconDevice::home() {
  const std::string who = transport_->description();
  const auto t0 = std::chrono::steady_clock::now();
  FalconCommand c;
  c.homing_mode = true;
  c.leds = 0x4;  // red while homing
  while (std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count() <
         options_.homing_timeout_s) {
    const DeviceStatus s = exchange(c);
    if (s == DeviceStatus::disconnected)
      throw DeviceDisconnected(who + ": disconnected during homing");
    if (s == DeviceStatus::ok && (report_.homed & 0x7) == 0x7) {
      FalconCommand done;
      done.leds = 0x1;  // green: ready
      exchange(done);
      return;
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(1));
  }
  std::string missing;
  for (int i = 0; i < 3; ++i)
    if (!(report_.homed & (1 << i))) missing += (missing.empty() ? "" : ", ") + std::to_string(i + 1);
  throw DeviceTimeout(who + ": homing timed out after " + std::to_string(options_.homing_timeout_s) +
                      " s, axes not homed: " + missing +
                      " (move the grip all the way out, then all the way in)");
}

void FalconDevice::close() noexcept {
  if (!open_) return;
  open_ = false;
  exchange(FalconCommand{});  // zero force, best effort
}

DeviceStatus FalconDevice::exchange(const FalconCommand& c) noexcept {
  FalconPacket out;
  encode_command(c, out);
  const IoResult w = transport_->write(out.data(), out.size(), options_.exchange_timeout_ms);
  if (w.status == IoStatus::disconnected) return DeviceStatus::disconnected;
  bool got = false;
  if (w.status == IoStatus::ok) {
    for (int attempt = 0; attempt < 4 && !got; ++attempt) {
      if (rx_fill_ == sizeof rx_) rx_fill_ = 0;  // only garbage: drop it
      const IoResult r = transport_->read(rx_ + rx_fill_, sizeof rx_ - rx_fill_,
                                          options_.exchange_timeout_ms);
      if (r.status == IoStatus::disconnected) return DeviceStatus::disconnected;
      rx_fill_ += r.bytes;
      // Find the first whole valid frame; skip anything before a '<' that frames badly.
      std::size_t i = 0;
      while (i < rx_fill_) {
        if (rx_[i] != '<') { ++i; ++bad_packets_; continue; }
        if (rx_fill_ - i < falcon_packet_size) break;
        FalconPacket p;
        std::memcpy(p.data(), rx_ + i, falcon_packet_size);
        FalconReport rep;
        if (decode_report(p, rep)) {
          report_ = rep;
          got = true;
          i += falcon_packet_size;
          break;
        }
        ++bad_packets_;
        ++i;
      }
      std::memmove(rx_, rx_ + i, rx_fill_ - i);
      rx_fill_ -= i;
      if (r.bytes == 0 && !got) break;
    }
  }
  const auto now = std::chrono::steady_clock::now();
  if (!got) {
    ++missed_;
    if (std::chrono::duration<double>(now - last_good_).count() > options_.no_answer_disconnect_s)
      return DeviceStatus::disconnected;
    return DeviceStatus::fault;
  }
  last_good_ = now;
  const Vec3d theta = kin_.encoder_to_theta(report_.encoder);
  Vec3d p;
  if (!kin_.forward(theta, state_valid_ ? position_ : Vec3d::Zero(), p)) return DeviceStatus::fault;
  theta_ = theta;
  position_ = p;
  state_valid_ = true;
  return DeviceStatus::ok;
}

DeviceStatus FalconDevice::read_state(DeviceState& out) noexcept {
  if (!open_) return DeviceStatus::disconnected;
  if (pending_fault_ || !state_valid_) {
    pending_fault_ = false;
    return DeviceStatus::fault;
  }
  out.position_m = position_.cast<float>();
  out.buttons = report_.buttons;
  out.time_s = std::chrono::duration<double>(last_good_ - opened_).count();
  return DeviceStatus::ok;
}

DeviceStatus FalconDevice::write_force(const Vec3& f) noexcept {
  if (!open_) return DeviceStatus::disconnected;
  FalconCommand c;
  c.leds = 0x1;
  if (state_valid_) c.motor = kin_.force_to_motor(f.cast<double>(), position_, theta_);
  const DeviceStatus s = exchange(c);
  if (s == DeviceStatus::fault) pending_fault_ = true;
  return s;
}

} // namespace hb
