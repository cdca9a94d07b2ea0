#pragma once
// Byte transport to a Novint Falcon's FTDI serial chip. The libusb implementation lives in
// falcon_usb_transport.cpp; tests use a simulated Falcon behind the same interface.
#include <cstddef>
#include <cstdint>
#include <string>

namespace hb {

/// Outcome of a data transfer (hot path: no exceptions).
enum class IoStatus : std::uint8_t { ok, timeout, disconnected, error };

struct IoResult {
  IoStatus status = IoStatus::ok;
  std::size_t bytes = 0;  ///< bytes written, or payload bytes read (FTDI status bytes stripped).
};

/// FTDI-style serial link. Control requests are setup-time and throw a DeviceError subclass
/// (DeviceDisconnected, DevicePermissionDenied, DeviceTimeout, DeviceError) naming the request.
/// write/read are noexcept and allocation-free in the implementations of this project.
class FalconTransport {
public:
  virtual ~FalconTransport() = default;

  /// e.g. "Falcon on USB bus 1 address 5" or "simulated Falcon".
  virtual std::string description() const = 0;

  virtual void reset() = 0;                         ///< FTDI SIO reset.
  virtual void purge() = 0;                         ///< purge RX and TX buffers.
  virtual void set_baud_rate(std::uint32_t baud) = 0;
  virtual void set_line_8n1() = 0;                  ///< 8 data bits, no parity, 1 stop bit.
  virtual void set_flow_control_none() = 0;
  virtual void set_latency_timer(std::uint8_t ms) = 0;  ///< 1..255 ms.
  virtual void set_dtr(bool high) = 0;
  virtual void set_rts(bool high) = 0;

  virtual IoResult write(const std::uint8_t* data, std::size_t n, int timeout_ms) noexcept = 0;
  /// Reads at most `n` payload bytes; returns what arrived within `timeout_ms` (0 bytes with
  /// IoStatus::timeout when nothing did).
  virtual IoResult read(std::uint8_t* data, std::size_t n, int timeout_ms) noexcept = 0;
};

} // namespace hb
