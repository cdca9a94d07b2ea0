#pragma once
// Loading the Falcon's firmware (the file is supplied by the user: its licence forbids shipping
// it; its path is a setting). Sequence after libnifalcon's documented procedure:
//  1. purge; latency timer 16 ms; 9600 baud 8N1, no flow control; RTS low, DTR low then high.
//  2. handshake 1: send 0x0A 0x43 0x0D, expect 0x0A 0x44 0x2C 0x0D (an extra leading 0x00
//     is accepted); retried `handshake_attempts` times.
//  3. DTR low; ~142857 baud (FTDI divisor 21); handshake 2: send 'A', expect 'A'.
//  4. the firmware in `block_size` blocks, each echoed back and compared byte for byte.
//  5. the whole sequence is retried `attempts` times; the error lists every attempt's failed step.
// Then normal mode: latency timer 1 ms, 1.5 Mbaud, purge.
#include "device/falcon/falcon_transport.h"
#include <cstdint>
#include <string>
#include <vector>

namespace hb {

struct FirmwareOptions {
  std::size_t block_size = 128;   ///< bytes per verified block.
  int attempts = 3;               ///< full load attempts.
  int handshake_attempts = 20;    ///< tries of handshake 1 per attempt.
  int timeout_ms = 1000;          ///< per read.
};

constexpr std::uint32_t falcon_bootloader_baud = 9600;
constexpr std::uint32_t falcon_firmware_load_baud = 142857;  ///< FTDI divisor 21.
constexpr std::uint32_t falcon_normal_baud = 1500000;        ///< FTDI divisor 2.

/// Reads a firmware file. Throws IoError (missing, unreadable) or InvalidInput (empty).
std::vector<std::uint8_t> read_firmware_file(const std::string& path);

/// Loads `firmware`. Throws DeviceDisconnected when the device goes away, else DeviceTimeout
/// or DeviceProtocolError whose message names each attempt's failed step, e.g.
/// "attempt 1: handshake 2: wrong echo (got 0x42, expected 0x41)".
void load_falcon_firmware(FalconTransport& t, const std::vector<std::uint8_t>& firmware,
                          const FirmwareOptions& options = {});

/// Switches the link to normal mode (latency 1 ms, 1.5 Mbaud, purge).
void set_falcon_normal_mode(FalconTransport& t);

} // namespace hb
