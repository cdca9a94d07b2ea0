#pragma once
// The device interface the servo loop drives: real hardware (Falcon), the virtual device and
// the replay device all implement it, so they run through exactly the same servo path.
#include "device/device_error.h"
#include "math/vec3.h"
#include <cstdint>
#include <string>

namespace hb {

/// What a device can do. Used by the safety layer (force clamp, stiffness limit) and by the
/// workspace mapping. All values in SI units.
struct DeviceSpec {
  std::string name;                       ///< human-readable model name.
  float workspace_radius_m = 0.04f;       ///< radius of the reachable sphere around the origin, m.
  float max_force_n = 8.f;                ///< peak force the device may be commanded, N.
  float max_continuous_force_n = 4.f;     ///< force sustainable indefinitely (thermal), N.
  float max_stiffness_n_per_m = 3000.f;   ///< largest stable stiffness at a 1 kHz servo rate, N/m.
  float max_damping_n_s_per_m = 10.f;     ///< largest stable damping, N s/m.
};

/// Bounds no haptic device exceeds (desktop devices: 0.04-0.2 m, 3-40 N, up to a few
/// thousand N/m; large industrial arms stay well inside these). A spec outside them is corrupt.
constexpr double kMinWorkspaceRadiusM = 1e-3;
constexpr double kMaxWorkspaceRadiusM = 2.0;
constexpr double kMinDeviceForceN = 0.01;
constexpr double kMinDeviceStiffnessNPerM = 1.0;
constexpr double kMaxDeviceForceN = 500.0;
constexpr double kMaxDeviceStiffnessNPerM = 1e5;
constexpr double kMaxDeviceDampingNsPerM = 1e4;
/// Servo rates a device can run at, Hz (ServoLoop and servo logs).
constexpr double kMinServoRateHz = 1.0;
constexpr double kMaxServoRateHz = 20000.0;

/// Why `spec` describes no possible device, or an empty string when it is plausible: every
/// value finite; workspace radius in [1e-3, 2] m; maximum force in [0.01, 500] N; continuous
/// force in (0, maximum force]; maximum stiffness in [1, 1e5] N/m; damping in [0, 1e4] N s/m.
std::string device_spec_problem(const DeviceSpec& spec);

/// One sample of device state. `position_m` is in the device frame (origin at the workspace
/// centre, metres); `time_s` is the device's own clock (monotonic, from open()).
struct DeviceState {
  Vec3 position_m{Vec3::Zero()};
  std::uint32_t buttons = 0;   ///< bit i set while button i is pressed.
  double time_s = 0.0;
  /// Replay only: the recorded tick's timing faults (bits of SafetyEvent: watchdog, device
  /// fault, emergency stop). A replay re-applies them instead of its own wall-clock lateness,
  /// so it gives the recorded forces bit for bit. Live devices leave `replayed` false.
  bool replayed = false;
  std::uint32_t replayed_flags = 0;
};

/// A haptic device. Pure virtual: a device that does not implement a method does not compile.
///
/// Threading: open() and close() are called from the owner's thread; read_state() and
/// write_force() only from the servo thread, once per tick, in that order. The two hot-path
/// methods are noexcept and must neither allocate nor block longer than one exchange.
class HapticDevice {
public:
  virtual ~HapticDevice() = default;

  /// Capabilities; valid before open().
  virtual const DeviceSpec& spec() const noexcept = 0;

  /// Connects and prepares the device (firmware, homing). Throws a DeviceError subclass naming
  /// the step that failed.
  virtual void open() = 0;

  /// Zeroes force and releases the device. Safe to call twice.
  virtual void close() noexcept = 0;

  /// Latest state. On anything but DeviceStatus::ok `out` is left unchanged.
  virtual DeviceStatus read_state(DeviceState& out) noexcept = 0;

  /// Commands a force in the device frame, N. Must be finite (the safety layer guarantees it).
  virtual DeviceStatus write_force(const Vec3& force_n) noexcept = 0;
};

} // namespace hb
