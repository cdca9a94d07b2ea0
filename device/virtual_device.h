#pragma once
// A device without hardware: its position comes from the mouse (set_target, any thread) or
// from a scripted trajectory, and it runs through the same servo path as a real device.
#include "device/haptic_device.h"
#include "device/seqlock.h"
#include <array>
#include <atomic>
#include <chrono>
#include <functional>

namespace hb {

/// A scripted trajectory: device position (m) at time t (s, from open()). Called on the servo
/// thread; must be noexcept in spirit (no allocation, no locks).
using Trajectory = std::function<Vec3(double t_s)>;

/// Spec of the virtual device: Falcon-like limits so that what feels right here is safe there.
DeviceSpec virtual_device_spec();

class VirtualDevice final : public HapticDevice {
public:
  /// Mouse-driven: the position is the last target set with set_target (starts at the origin).
  explicit VirtualDevice(DeviceSpec spec = virtual_device_spec());
  /// Scripted: position = trajectory(tick * dt_s). Time is counted in reads, not wall time,
  /// so the same script gives the same positions on every run.
  VirtualDevice(Trajectory trajectory, double dt_s, DeviceSpec spec = virtual_device_spec());

  const DeviceSpec& spec() const noexcept override { return spec_; }
  void open() override;
  void close() noexcept override;
  DeviceStatus read_state(DeviceState& out) noexcept override;
  DeviceStatus write_force(const Vec3& force_n) noexcept override;

  /// Mouse input (GUI thread): device-frame position, m, and buttons. Lock-free.
  void set_target(const Vec3& position_m, std::uint32_t buttons = 0) noexcept;
  /// Last force the servo loop wrote, N (any thread).
  Vec3 last_force() const noexcept;
  /// Simulates unplugging: the next read returns DeviceStatus::disconnected.
  void simulate_disconnect() noexcept { unplugged_.store(true); }
  /// Simulates a transient fault on the next read.
  void simulate_fault() noexcept { fault_.store(true); }
  std::uint64_t reads() const noexcept { return reads_.load(); }

private:
  struct Target {
    std::array<float, 3> p{};
    std::uint32_t buttons = 0;
  };
  DeviceSpec spec_;
  Trajectory trajectory_;
  double dt_ = 1e-3;
  Seqlock<Target> target_;
  Seqlock<std::array<float, 3>> force_;
  std::atomic<bool> unplugged_{false};
  std::atomic<bool> fault_{false};
  std::atomic<std::uint64_t> reads_{0};
  std::chrono::steady_clock::time_point opened_{};
  bool open_ = false;
};

/// A scripted trajectory for tests and `hapticbox servo --device virtual`: a circle of radius
/// `radius_m` in the XY plane at height z(t) oscillating between +-`depth_m`, period `period_s`.
Trajectory circle_probe_trajectory(float radius_m, float depth_m, double period_s);

} // namespace hb
