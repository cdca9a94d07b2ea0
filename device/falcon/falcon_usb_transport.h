#pragma once
// Novint Falcon over libusb-1.0 (FTDI FT232, vendor 0x0403, product 0xCB48). No libusb type
// appears here: the context and handles live in falcon_usb_transport.cpp, and libusb errors
// are translated there to DeviceError subclasses.
#include "device/falcon/falcon_transport.h"
#include <functional>
#include <memory>
#include <string>
#include <vector>

namespace hb {

constexpr std::uint16_t falcon_vendor_id = 0x0403;
constexpr std::uint16_t falcon_product_id = 0xCB48;

/// One Falcon seen on the bus.
struct FalconUsbInfo {
  int bus = 0;
  int address = 0;
  std::string port_path;     ///< e.g. "1-2.3".
  bool accessible = false;   ///< it could be opened (permissions).
  std::string problem;       ///< why not, with what to do (udev rule).
};

/// Result of a bus scan. `usb_ok` is false when libusb itself could not start (`message` why).
struct FalconScan {
  bool usb_ok = false;
  std::string message;
  std::vector<FalconUsbInfo> falcons;
};

/// Scans the bus; never throws (a failing libusb_init is reported in the result).
FalconScan scan_falcons();

/// What to do when opening fails with a permission error.
std::string falcon_permission_advice();

/// Opens the `index`-th Falcon. Throws DeviceNotFound, DevicePermissionDenied (with the udev
/// advice), DeviceDisconnected or DeviceError naming the libusb step and error.
std::unique_ptr<FalconTransport> open_falcon_usb(int index = 0);

/// Notices Falcons plugged in or out while the program runs: libusb hotplug callbacks when the
/// platform supports them, else a poll of the bus every `poll_interval_s`. Callbacks run on the
/// monitor's own thread. The destructor stops and joins it.
class FalconHotplugMonitor {
public:
  using Callback = std::function<void(bool arrived, const FalconUsbInfo& info)>;
  /// Throws DeviceError when libusb cannot start.
  explicit FalconHotplugMonitor(Callback callback, double poll_interval_s = 0.5);
  ~FalconHotplugMonitor();
  FalconHotplugMonitor(const FalconHotplugMonitor&) = delete;
  FalconHotplugMonitor& operator=(const FalconHotplugMonitor&) = delete;

  /// True when libusb's hotplug API is in use, false when polling.
  bool uses_hotplug_api() const noexcept;
  void stop() noexcept;

private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

} // namespace hb
