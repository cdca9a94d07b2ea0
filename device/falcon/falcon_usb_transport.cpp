// Falcon USB transport over libusb-1.0. The only file of the project that includes libusb.h.
// 1. A small RAII context; every libusb error is translated at this boundary (translate()).
// 2. FTDI vendor requests on endpoint 0: reset/purge (0), modem control (1), flow control (2),
//    baud rate (3, divisor of 3 MHz in eighths), line properties (4), latency timer (9).
// 3. Data: bulk OUT 0x02; bulk IN 0x81, where every 64-byte USB packet starts with two FTDI
//    modem-status bytes that are stripped here; surplus payload is kept for the next read.
// 4. Hotplug: libusb_hotplug_register_callback when LIBUSB_CAP_HAS_HOTPLUG, else a bus poll.
#include "device/falcon/falcon_usb_transport.h"
#include "device/device_error.h"
#include <libusb.h>
#include <algorithm>
#include <atomic>
#include <chrono>
#include <cstring>
#include <set>
#include <thread>
#include <utility>

namespace hb {
namespace {

constexpr std::uint8_t ftdi_out_type = 0x40;  // vendor, host to device
constexpr std::uint8_t sio_reset = 0, sio_modem_ctrl = 1, sio_flow_ctrl = 2, sio_baud = 3,
                       sio_data = 4, sio_latency = 9;
constexpr std::uint16_t sio_reset_sio = 0, sio_purge_rx = 1, sio_purge_tx = 2;
constexpr unsigned char ep_out = 0x02, ep_in = 0x81;
constexpr unsigned control_timeout_ms = 1000;

std::string usb_error_text(int rc) {
  return std::string(libusb_error_name(rc)) + " (" + libusb_strerror(static_cast<libusb_error>(rc)) + ")";
}

[[noreturn]] void translate(int rc, const std::string& step) {
  const std::string msg = step + ": " + usb_error_text(rc);
  switch (rc) {
    case LIBUSB_ERROR_ACCESS: throw DevicePermissionDenied(msg + ". " + falcon_permission_advice());
    case LIBUSB_ERROR_NO_DEVICE: throw DeviceDisconnected(msg + " (device unplugged?)");
    case LIBUSB_ERROR_NOT_FOUND: throw DeviceNotFound(msg);
    case LIBUSB_ERROR_TIMEOUT: throw DeviceTimeout(msg);
    default: throw DeviceError(msg);
  }
}

IoStatus io_status(int rc) noexcept {
  switch (rc) {
    case 0: return IoStatus::ok;
    case LIBUSB_ERROR_TIMEOUT: return IoStatus::timeout;
    case LIBUSB_ERROR_NO_DEVICE: return IoStatus::disconnected;
    default: return IoStatus::error;
  }
}

struct Context {
  libusb_context* ctx = nullptr;
  Context() {
    const int rc = libusb_init(&ctx);
    if (rc != 0) translate(rc, "libusb_init");
  }
  ~Context() {
    if (ctx) libusb_exit(ctx);
  }
  Context(const Context&) = delete;
  Context& operator=(const Context&) = delete;
};

/// FTDI FT232BM baud divisor: 3 MHz / (n + frac/8); returns (value, index) for the request.
std::pair<std::uint16_t, std::uint16_t> ftdi_divisor(std::uint32_t baud) {
  if (baud == 0) throw InvalidInput("FTDI baud rate 0");
  if (baud >= 3000000) return {0, 0};
  if (baud >= 2000000) return {1, 0};
  static const std::uint8_t frac_code[8] = {0, 3, 2, 4, 1, 5, 6, 7};
  std::uint32_t eighths = (24000000u + baud / 2) / baud;  // divisor in 1/8 units
  if (eighths < 16) eighths = 16;
  const std::uint32_t n = eighths >> 3, code = frac_code[eighths & 7];
  const std::uint32_t value = (n & 0x3FFF) | ((code & 3) << 14);
  return {static_cast<std::uint16_t>(value), static_cast<std::uint16_t>(code >> 2)};
}

std::string port_path(libusb_device* dev) {
  std::uint8_t ports[8];
  const int n = libusb_get_port_numbers(dev, ports, 8);
  std::string s = std::to_string(libusb_get_bus_number(dev));
  for (int i = 0; i < n; ++i) s += (i ? "." : "-") + std::to_string(ports[i]);
  return s;
}

FalconUsbInfo info_of(libusb_device* dev) {
  FalconUsbInfo info;
  info.bus = libusb_get_bus_number(dev);
  info.address = libusb_get_device_address(dev);
  info.port_path = port_path(dev);
  return info;
}

bool is_falcon(libusb_device* dev) {
  libusb_device_descriptor d{};
  return libusb_get_device_descriptor(dev, &d) == 0 && d.idVendor == falcon_vendor_id &&
         d.idProduct == falcon_product_id;
}

class UsbFalconTransport final : public FalconTransport {
public:
  UsbFalconTransport(std::shared_ptr<Context> ctx, libusb_device_handle* h, FalconUsbInfo info)
      : ctx_(std::move(ctx)), h_(h), info_(std::move(info)) {}
  ~UsbFalconTransport() override {
    libusb_release_interface(h_, 0);
    libusb_close(h_);
  }

  std::string description() const override {
    return "Falcon on USB bus " + std::to_string(info_.bus) + " address " +
           std::to_string(info_.address) + " (port " + info_.port_path + ")";
  }

  void reset() override { control(sio_reset, sio_reset_sio, 0, "FTDI reset"); pending_len_ = 0; }
  void purge() override {
    control(sio_reset, sio_purge_rx, 0, "FTDI purge RX");
    control(sio_reset, sio_purge_tx, 0, "FTDI purge TX");
    pending_len_ = 0;
  }
  void set_baud_rate(std::uint32_t baud) override {
    const auto [value, index] = ftdi_divisor(baud);
    control(sio_baud, value, index, "FTDI set baud rate " + std::to_string(baud));
  }
  void set_line_8n1() override { control(sio_data, 8, 0, "FTDI set line 8N1"); }
  void set_flow_control_none() override { control(sio_flow_ctrl, 0, 0, "FTDI disable flow control"); }
  void set_latency_timer(std::uint8_t ms) override {
    control(sio_latency, ms, 0, "FTDI set latency timer " + std::to_string(ms) + " ms");
  }
  // Modem control: high byte = mask of lines changed, low byte = their values (DTR bit 0, RTS bit 1).
  void set_dtr(bool high) override { control(sio_modem_ctrl, 0x0100 | (high ? 1 : 0), 0, "FTDI set DTR"); }
  void set_rts(bool high) override { control(sio_modem_ctrl, 0x0200 | (high ? 2 : 0), 0, "FTDI set RTS"); }

  IoResult write(const std::uint8_t* data, std::size_t n, int timeout_ms) noexcept override {
    int done = 0;
    const int rc = libusb_bulk_transfer(h_, ep_out, const_cast<unsigned char*>(data),
                                        static_cast<int>(n), &done, static_cast<unsigned>(timeout_ms));
    return {io_status(rc), static_cast<std::size_t>(std::max(0, done))};
  }

  IoResult read(std::uint8_t* data, std::size_t n, int timeout_ms) noexcept override {
    if (pending_len_ == 0) {
      int got = 0;
      const int rc = libusb_bulk_transfer(h_, ep_in, raw_, sizeof raw_, &got,
                                          static_cast<unsigned>(timeout_ms));
      if (rc != 0 && rc != LIBUSB_ERROR_TIMEOUT) return {io_status(rc), 0};
      // Strip the two modem-status bytes at the start of every 64-byte USB packet.
      for (int off = 0; off < got; off += 64) {
        const int len = std::min(64, got - off);
        if (len > 2) {
          std::memcpy(pending_ + pending_len_, raw_ + off + 2, static_cast<std::size_t>(len - 2));
          pending_len_ += static_cast<std::size_t>(len - 2);
        }
      }
      pending_off_ = 0;
      if (pending_len_ == 0) return {IoStatus::timeout, 0};
    }
    const std::size_t k = std::min(n, pending_len_ - pending_off_);
    std::memcpy(data, pending_ + pending_off_, k);
    pending_off_ += k;
    if (pending_off_ == pending_len_) pending_len_ = pending_off_ = 0;
    return {IoStatus::ok, k};
  }

private:
  void control(std::uint8_t request, std::uint16_t value, std::uint16_t index, const std::string& step) {
    const int rc = libusb_control_transfer(h_, ftdi_out_type, request, value, index, nullptr, 0,
                                           control_timeout_ms);
    if (rc < 0) translate(rc, description() + ": " + step);
  }

  std::shared_ptr<Context> ctx_;
  libusb_device_handle* h_;
  FalconUsbInfo info_;
  unsigned char raw_[512];
  std::uint8_t pending_[512];
  std::size_t pending_len_ = 0, pending_off_ = 0;
};

/// RAII device list.
struct DeviceList {
  libusb_device** list = nullptr;
  ssize_t count = 0;
  explicit DeviceList(libusb_context* ctx) {
    count = libusb_get_device_list(ctx, &list);
    if (count < 0) translate(static_cast<int>(count), "libusb_get_device_list");
  }
  ~DeviceList() {
    if (list) libusb_free_device_list(list, 1);
  }
};

} // namespace

std::string falcon_permission_advice() {
  return "Permission denied on the Falcon's USB node: install the udev rule shipped in "
         "device/falcon/99-novint-falcon.rules (sudo cp device/falcon/99-novint-falcon.rules "
         "/etc/udev/rules.d/ && sudo udevadm control --reload-rules && sudo udevadm trigger), "
         "make sure your user is in the 'plugdev' group (then log out and in), and replug the "
         "Falcon";
}

FalconScan scan_falcons() {
  FalconScan scan;
  std::shared_ptr<Context> ctx;
  try {
    ctx = std::make_shared<Context>();
    DeviceList devs(ctx->ctx);
    for (ssize_t i = 0; i < devs.count; ++i) {
      libusb_device* d = devs.list[i];
      if (!is_falcon(d)) continue;
      FalconUsbInfo info = info_of(d);
      libusb_device_handle* h = nullptr;
      const int rc = libusb_open(d, &h);
      if (rc == 0) {
        info.accessible = true;
        libusb_close(h);
      } else {
        info.problem = usb_error_text(rc);
        if (rc == LIBUSB_ERROR_ACCESS) info.problem += ". " + falcon_permission_advice();
      }
      scan.falcons.push_back(std::move(info));
    }
    scan.usb_ok = true;
    scan.message = "libusb " + std::to_string(libusb_get_version()->major) + "." +
                   std::to_string(libusb_get_version()->minor) + "." +
                   std::to_string(libusb_get_version()->micro) + " started";
  } catch (const DeviceError& e) {
    scan.usb_ok = false;
    scan.message = e.what();
  }
  return scan;
}

std::unique_ptr<FalconTransport> open_falcon_usb(int index) {
  auto ctx = std::make_shared<Context>();
  DeviceList devs(ctx->ctx);
  int seen = 0;
  for (ssize_t i = 0; i < devs.count; ++i) {
    libusb_device* d = devs.list[i];
    if (!is_falcon(d) || seen++ != index) continue;
    FalconUsbInfo info = info_of(d);
    const std::string who = "Falcon on USB bus " + std::to_string(info.bus) + " address " +
                            std::to_string(info.address);
    libusb_device_handle* h = nullptr;
    int rc = libusb_open(d, &h);
    if (rc != 0) translate(rc, who + ": libusb_open");
    libusb_set_auto_detach_kernel_driver(h, 1);  // ftdi_sio may own it; not fatal if unsupported
    rc = libusb_claim_interface(h, 0);
    if (rc != 0) {
      libusb_close(h);
      translate(rc, who + ": claim interface 0 (is another program using the Falcon?)");
    }
    return std::make_unique<UsbFalconTransport>(ctx, h, std::move(info));
  }
  throw DeviceNotFound(seen == 0 ? "no Falcon found (USB 0403:cb48); is it plugged in and powered?"
                                 : "Falcon #" + std::to_string(index) + " not found (" +
                                       std::to_string(seen) + " connected)");
}

struct FalconHotplugMonitor::Impl {
  Callback callback;
  std::shared_ptr<Context> ctx = std::make_shared<Context>();
  std::atomic<bool> stop{false};
  std::thread thread;
  bool hotplug = false;
  libusb_hotplug_callback_handle handle{};
  double poll_s = 0.5;

  static int LIBUSB_CALL on_event(libusb_context*, libusb_device* dev, libusb_hotplug_event ev,
                                  void* user) {
    auto* self = static_cast<Impl*>(user);
    try {
      self->callback(ev == LIBUSB_HOTPLUG_EVENT_DEVICE_ARRIVED, info_of(dev));
    } catch (...) {
      // Never throw through libusb's C frames.
    }
    return 0;
  }

  void poll_loop() {
    std::set<std::pair<int, int>> known;
    bool first = true;
    while (!stop.load()) {
      std::set<std::pair<int, int>> now;
      std::vector<FalconUsbInfo> infos;
      try {
        DeviceList devs(ctx->ctx);
        for (ssize_t i = 0; i < devs.count; ++i)
          if (is_falcon(devs.list[i])) {
            infos.push_back(info_of(devs.list[i]));
            now.insert({infos.back().bus, infos.back().address});
          }
      } catch (...) {
      }
      if (!first) {
        for (const auto& info : infos)
          if (!known.count({info.bus, info.address})) callback(true, info);
        for (const auto& k : known)
          if (!now.count(k)) {
            FalconUsbInfo gone;
            gone.bus = k.first;
            gone.address = k.second;
            callback(false, gone);
          }
      }
      first = false;
      known = std::move(now);
      const auto until = std::chrono::steady_clock::now() + std::chrono::duration<double>(poll_s);
      while (!stop.load() && std::chrono::steady_clock::now() < until)
        std::this_thread::sleep_for(std::chrono::milliseconds(20));
    }
  }

  void event_loop() {
    while (!stop.load()) {
      timeval tv{0, 100000};
      libusb_handle_events_timeout_completed(ctx->ctx, &tv, nullptr);
    }
  }
};

FalconHotplugMonitor::FalconHotplugMonitor(Callback callback, double poll_interval_s)
    : impl_(std::make_unique<Impl>()) {
  impl_->callback = std::move(callback);
  impl_->poll_s = poll_interval_s > 0 ? poll_interval_s : 0.5;
  if (libusb_has_capability(LIBUSB_CAP_HAS_HOTPLUG)) {
    const int rc = libusb_hotplug_register_callback(
        impl_->ctx->ctx,
        static_cast<libusb_hotplug_event>(LIBUSB_HOTPLUG_EVENT_DEVICE_ARRIVED |
                                          LIBUSB_HOTPLUG_EVENT_DEVICE_LEFT),
        static_cast<libusb_hotplug_flag>(0), falcon_vendor_id, falcon_product_id,
        LIBUSB_HOTPLUG_MATCH_ANY, &Impl::on_event, impl_.get(), &impl_->handle);
    impl_->hotplug = rc == LIBUSB_SUCCESS;
  }
  Impl* impl = impl_.get();
  if (impl_->hotplug) impl_->thread = std::thread([impl] { impl->event_loop(); });
  else impl_->thread = std::thread([impl] { impl->poll_loop(); });
}

FalconHotplugMonitor::~FalconHotplugMonitor() { stop(); }

bool FalconHotplugMonitor::uses_hotplug_api() const noexcept { return impl_->hotplug; }

void FalconHotplugMonitor::stop() noexcept {
  if (!impl_ || impl_->stop.exchange(true)) return;
  if (impl_->hotplug) libusb_hotplug_deregister_callback(impl_->ctx->ctx, impl_->handle);
  if (impl_->thread.joinable()) impl_->thread.join();
}

} // namespace hb
