// `hapticbox devices`: lists what is connected; --watch S reports plugging in and out.
#include "cli_support.h"
#include "commands.h"
#include "device/device_error.h"
#include "device/falcon/falcon_usb_transport.h"
#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>
#include <chrono>
#include <iostream>
#include <memory>
#include <thread>

namespace {

struct DevicesArgs {
  bool json = false;
  double watch_s = 0;
};

void run_devices(const DevicesArgs& a) {
  const hb::FalconScan scan = hb::scan_falcons();
  if (a.json) {
    nlohmann::json j;
    j["usb_ok"] = scan.usb_ok;
    j["usb_message"] = scan.message;
    j["devices"] = nlohmann::json::array();
    j["devices"].push_back({{"kind", "virtual"}, {"available", true}});
    for (const auto& f : scan.falcons)
      j["devices"].push_back({{"kind", "falcon"}, {"bus", f.bus}, {"address", f.address},
                              {"port", f.port_path}, {"available", f.accessible},
                              {"problem", f.problem}});
    std::cout << j.dump(2) << "\n";
  } else {
    std::cout << "virtual      always available (mouse or scripted trajectory)\n";
    std::cout << "replay:LOG   plays back a servo log recorded with --record\n";
    if (!scan.usb_ok) {
      std::cout << "USB: cannot start libusb (" << scan.message
                << "), so no Falcon can be listed. In a container, pass /dev/bus/usb through.\n";
    } else if (scan.falcons.empty()) {
      std::cout << "no Falcon found (USB 0403:cb48): plug it in and power it, or check `lsusb`.\n";
    } else {
      for (const auto& f : scan.falcons) {
        std::cout << "falcon       Novint Falcon on USB bus " << f.bus << " address " << f.address
                  << " (port " << f.port_path << ")";
        if (f.accessible) std::cout << ": ready\n";
        else std::cout << ": cannot open: " << f.problem << "\n";
      }
    }
  }
  if (a.watch_s > 0) {
    if (!scan.usb_ok) throw hb::DeviceError("cannot watch for Falcons: " + scan.message);
    hb::FalconHotplugMonitor monitor([](bool arrived, const hb::FalconUsbInfo& info) {
      std::cout << (arrived ? "plugged in: " : "unplugged:  ") << "Falcon on USB bus " << info.bus
                << " address " << info.address << std::endl;
    });
    std::cout << "watching for " << a.watch_s << " s ("
              << (monitor.uses_hotplug_api() ? "libusb hotplug events" : "polling the bus")
              << ")..." << std::endl;
    std::this_thread::sleep_for(std::chrono::duration<double>(a.watch_s));
  }
}

} // namespace

void add_devices_command(CLI::App& app) {
  auto args = std::make_shared<DevicesArgs>();
  CLI::App* cmd = app.add_subcommand("devices", "List connected haptic devices");
  cmd->add_flag("--json", args->json, "Print JSON");
  cmd->add_option("--watch", args->watch_s, "Then report Falcons plugged in or out for S seconds")
      ->check(hb::cli::finite_range(0.0, 1e6));
  cmd->callback([args] { run_devices(*args); });
}
