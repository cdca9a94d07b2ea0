#include "device/virtual_device.h"
#include "device/falcon/falcon_device.h"
#include <cmath>

namespace hb {

DeviceSpec virtual_device_spec() {
  // A Falcon-sized device, so a scene felt with the mouse feels the same on the hardware.
  DeviceSpec s = falcon_spec();
  s.name = "virtual device";
  return s;
}

VirtualDevice::VirtualDevice(DeviceSpec spec) : spec_(std::move(spec)) {}

VirtualDevice::VirtualDevice(Trajectory trajectory, double dt_s, DeviceSpec spec)
    : spec_(std::move(spec)), trajectory_(std::move(trajectory)), dt_(dt_s > 0 ? dt_s : 1e-3) {}

void VirtualDevice::open() {
  opened_ = std::chrono::steady_clock::now();
  reads_.store(0);
  unplugged_.store(false);
  fault_.store(false);
  open_ = true;
}

void VirtualDevice::close() noexcept {
  force_.store({0.f, 0.f, 0.f});
  open_ = false;
}

DeviceStatus VirtualDevice::read_state(DeviceState& out) noexcept {
  if (!open_ || unplugged_.load(std::memory_order_relaxed)) return DeviceStatus::disconnected;
  if (fault_.exchange(false, std::memory_order_relaxed)) return DeviceStatus::fault;
  const std::uint64_t n = reads_.fetch_add(1, std::memory_order_relaxed);
  if (trajectory_) {
    out.time_s = static_cast<double>(n) * dt_;
    out.position_m = trajectory_(out.time_s);
    out.buttons = 0;
  } else {
    const Target t = target_.load();
    out.position_m = Vec3(t.p[0], t.p[1], t.p[2]);
    out.buttons = t.buttons;
    out.time_s =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - opened_).count();
  }
  return DeviceStatus::ok;
}

DeviceStatus VirtualDevice::write_force(const Vec3& f) noexcept {
  if (!open_ || unplugged_.load(std::memory_order_relaxed)) return DeviceStatus::disconnected;
  force_.store({f.x(), f.y(), f.z()});
  return DeviceStatus::ok;
}

void VirtualDevice::set_target(const Vec3& p, std::uint32_t buttons) noexcept {
  Target t;
  t.p = {p.x(), p.y(), p.z()};
  t.buttons = buttons;
  target_.store(t);
}

Vec3 VirtualDevice::last_force() const noexcept {
  const auto f = force_.load();
  return Vec3(f[0], f[1], f[2]);
}

Trajectory circle_probe_trajectory(float radius_m, float depth_m, double period_s) {
  return [=](double t) {
    const double w = 2.0 * M_PI * t / period_s;
    return Vec3(static_cast<float>(radius_m * std::cos(w)),
                static_cast<float>(radius_m * std::sin(w)),
                static_cast<float>(depth_m * std::sin(3.0 * w)));
  };
}

} // namespace hb
