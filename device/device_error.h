#pragma once
// Typed errors of the device layer. Setup paths (open, firmware, homing) throw these; the
// servo hot path never throws: it returns a DeviceStatus and a fault latches force to zero.
#include "errors.h"
#include <cstdint>

namespace hb {

/// Base of every device-layer error; what() names the device and the step that failed.
class DeviceError : public Error {
public:
  explicit DeviceError(const std::string& what) : Error(what) {}
};

/// No device of the requested kind is connected.
class DeviceNotFound : public DeviceError {
public:
  explicit DeviceNotFound(const std::string& what) : DeviceError(what) {}
};

/// The operating system refused access (USB node not writable: install the udev rule).
class DevicePermissionDenied : public DeviceError {
public:
  explicit DevicePermissionDenied(const std::string& what) : DeviceError(what) {}
};

/// The device went away (unplugged, powered off) during an operation.
class DeviceDisconnected : public DeviceError {
public:
  explicit DeviceDisconnected(const std::string& what) : DeviceError(what) {}
};

/// The device did not answer in time.
class DeviceTimeout : public DeviceError {
public:
  explicit DeviceTimeout(const std::string& what) : DeviceError(what) {}
};

/// The device answered something unexpected (wrong echo, garbage packet, bad firmware block).
class DeviceProtocolError : public DeviceError {
public:
  explicit DeviceProtocolError(const std::string& what) : DeviceError(what) {}
};

/// Status of one hot-path device operation (read_state / write_force). Never thrown.
enum class DeviceStatus : std::uint8_t {
  ok = 0,
  disconnected,   ///< the device is gone; the servo loop zeroes force and stops.
  end_of_stream,  ///< a replay reached the end of its log; the loop stops cleanly.
  fault,          ///< a transient error (bad packet, timeout); force is zeroed and ramped back.
};

const char* to_string(DeviceStatus status) noexcept;

} // namespace hb
