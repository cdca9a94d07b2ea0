#include "device/device_choice.h"
#include "device/falcon/falcon_device.h"
#include "device/falcon/falcon_usb_transport.h"
#include "device/servo_log.h"
#include "errors.h"

namespace hb {

OpenedDevice::OpenedDevice() = default;
OpenedDevice::OpenedDevice(OpenedDevice&&) noexcept = default;
OpenedDevice& OpenedDevice::operator=(OpenedDevice&&) noexcept = default;
OpenedDevice::~OpenedDevice() = default;

DeviceChoice parse_device_choice(const std::string& spec) {
  DeviceChoice c;
  if (spec == "virtual") return c;
  if (spec == "falcon") {
    c.kind = DeviceChoice::Kind::falcon;
    return c;
  }
  if (spec.rfind("replay:", 0) == 0 && spec.size() > 7) {
    c.kind = DeviceChoice::Kind::replay;
    c.replay_log = spec.substr(7);
    return c;
  }
  throw InvalidInput("device '" + spec + "' is not one of virtual, replay:LOG, falcon");
}

std::string device_choice_spec(const DeviceChoice& c) {
  switch (c.kind) {
  case DeviceChoice::Kind::virtual_device: return "virtual";
  case DeviceChoice::Kind::replay: return "replay:" + c.replay_log;
  case DeviceChoice::Kind::falcon: return "falcon";
  }
  return "virtual";
}

OpenedDevice open_device(const DeviceChoice& choice, const DeviceOpenOptions& options) {
  OpenedDevice d;
  switch (choice.kind) {
  case DeviceChoice::Kind::virtual_device: {
    auto v = options.virtual_trajectory ? std::make_unique<VirtualDevice>(*options.virtual_trajectory, options.dt_s)
                                        : std::make_unique<VirtualDevice>();
    d.virtual_device = v.get();
    d.device = std::move(v);
    d.description = options.virtual_trajectory ? "Virtual (scripted)" : "Virtual (mouse)";
    break;
  }
  case DeviceChoice::Kind::replay: {
    auto r = std::make_unique<ReplayDevice>(choice.replay_log);
    d.rate_hz = r->log().rate_hz;
    d.device = std::move(r);
    const std::size_t slash = choice.replay_log.find_last_of('/');
    d.description = "Replay: " + (slash == std::string::npos ? choice.replay_log : choice.replay_log.substr(slash + 1));
    break;
  }
  case DeviceChoice::Kind::falcon: {
    FalconOptions o;
    o.firmware_path = choice.falcon_firmware;
    d.device = std::make_unique<FalconDevice>(open_falcon_usb(0), o);
    d.description = "Novint Falcon";
    if (options.on_hotplug) {
      auto cb = options.on_hotplug;
      try {
        d.hotplug = std::make_unique<FalconHotplugMonitor>(
            [cb](bool arrived, const FalconUsbInfo& i) { cb(arrived, int(i.bus), int(i.address)); });
      } catch (const std::exception&) {
        d.hotplug.reset();  // the device opened, so libusb works; a monitor is a convenience
      }
    }
    break;
  }
  }
  return d;
}

} // namespace hb
