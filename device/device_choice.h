#pragma once
// One device choice for every front end: `virtual | replay:LOG | falcon`, parsed once and
// opened once (the Falcon with its firmware and a hotplug monitor), so the command line's
// `servo` and the window get the same device from the same words.
#include "device/haptic_device.h"
#include "device/virtual_device.h"
#include <functional>
#include <memory>
#include <optional>
#include <string>

namespace hb {

class FalconHotplugMonitor;

/// Which device: what `--device` and the window's device panel name.
struct DeviceChoice {
  enum class Kind { virtual_device, replay, falcon };
  Kind kind = Kind::virtual_device;
  std::string replay_log;       ///< Kind::replay: a servo log recorded with `servo --record`.
  std::string falcon_firmware;  ///< Kind::falcon: firmware file to load (empty: the device's own).
};

/// "virtual", "replay:LOG" or "falcon". Throws hb::InvalidInput naming the accepted forms.
DeviceChoice parse_device_choice(const std::string& spec);
/// The inverse of parse_device_choice.
std::string device_choice_spec(const DeviceChoice& choice);

/// How to open the chosen device.
struct DeviceOpenOptions {
  /// Virtual device: follow this trajectory at `dt_s` per read (scripted runs); without one it
  /// is mouse-driven (VirtualDevice::set_target).
  std::optional<Trajectory> virtual_trajectory;
  double dt_s = 1e-3;
  /// Falcon: called from the monitor's thread when a Falcon is plugged in or out.
  std::function<void(bool arrived, int bus, int address)> on_hotplug;
};

/// An opened device and what goes with it.
struct OpenedDevice {
  std::unique_ptr<HapticDevice> device;
  VirtualDevice* virtual_device = nullptr;        ///< `device` when it is the virtual one.
  std::unique_ptr<FalconHotplugMonitor> hotplug;  ///< Falcon only (when libusb starts).
  double rate_hz = 0.0;  ///< a replay's recorded rate (run the servo at it); 0 otherwise.
  std::string description;  ///< e.g. "Virtual", "Replay: run.hblog", "Novint Falcon".
  OpenedDevice();
  OpenedDevice(OpenedDevice&&) noexcept;
  OpenedDevice& operator=(OpenedDevice&&) noexcept;
  ~OpenedDevice();
};

/// Opens `choice`. Throws the device's hb::DeviceError (no Falcon, no permission, bad
/// firmware) or hb::IoError / hb::InvalidInput (replay log).
OpenedDevice open_device(const DeviceChoice& choice, const DeviceOpenOptions& options = {});

} // namespace hb
