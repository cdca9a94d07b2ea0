#pragma once
// Falcon packets of the Novint SDK firmware: 16 bytes each way, framed by '<' and '>', every
// value sent as 'A' + nibble (so a frame never contains '<' or '>' inside).
//
//   byte  0      '<'
//   bytes 1..12  three 16-bit values, 4 nibbles each, least significant nibble first
//                host -> device: signed motor commands; device -> host: encoder counts
//   bytes 13,14  flags, low nibble then high nibble
//                host -> device: bit 0 homing mode, bits 1..3 LEDs (green, blue, red)
//                device -> host: bits 0..2 axis homed, bits 4..7 buttons
//   byte  15     '>'
#include <array>
#include <cstdint>

namespace hb {

constexpr std::size_t falcon_packet_size = 16;
using FalconPacket = std::array<std::uint8_t, falcon_packet_size>;

/// Host to device.
struct FalconCommand {
  std::array<std::int16_t, 3> motor{};  ///< motor commands, capped at +-4096 by the encoder.
  bool homing_mode = false;
  std::uint8_t leds = 0;                ///< bit 0 green, bit 1 blue, bit 2 red.
};

/// Device to host.
struct FalconReport {
  std::array<std::int16_t, 3> encoder{};  ///< encoder counts per axis.
  std::uint8_t homed = 0;                 ///< bit i: axis i homed.
  std::uint8_t buttons = 0;               ///< bit i: button i pressed.
};

constexpr std::int16_t falcon_motor_limit = 4096;

/// Encodes; motor commands are clamped to +-falcon_motor_limit.
void encode_command(const FalconCommand& c, FalconPacket& out) noexcept;
/// False when the frame or a nibble character is invalid (`c` then unchanged).
bool decode_command(const FalconPacket& in, FalconCommand& c) noexcept;
void encode_report(const FalconReport& r, FalconPacket& out) noexcept;
bool decode_report(const FalconPacket& in, FalconReport& r) noexcept;

} // namespace hb
