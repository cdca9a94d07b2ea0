#include "device/falcon/falcon_packet.h"
#include <algorithm>

namespace hb {
namespace {

void put16(std::uint16_t v, std::uint8_t* p) noexcept {
  for (int i = 0; i < 4; ++i) p[i] = static_cast<std::uint8_t>('A' + ((v >> (4 * i)) & 0xF));
}

bool nibble(std::uint8_t ch, std::uint16_t& out) noexcept {
  if (ch < 'A' || ch > 'A' + 15) return false;
  out = static_cast<std::uint16_t>(ch - 'A');
  return true;
}

bool get16(const std::uint8_t* p, std::uint16_t& v) noexcept {
  v = 0;
  for (int i = 0; i < 4; ++i) {
    std::uint16_t n;
    if (!nibble(p[i], n)) return false;
    v = static_cast<std::uint16_t>(v | (n << (4 * i)));
  }
  return true;
}

void frame(const std::uint16_t v[3], std::uint8_t flags, FalconPacket& out) noexcept {
  out[0] = '<';
  for (int i = 0; i < 3; ++i) put16(v[i], &out[1 + 4 * i]);
  out[13] = static_cast<std::uint8_t>('A' + (flags & 0xF));
  out[14] = static_cast<std::uint8_t>('A' + (flags >> 4));
  out[15] = '>';
}

bool unframe(const FalconPacket& in, std::uint16_t v[3], std::uint8_t& flags) noexcept {
  if (in[0] != '<' || in[15] != '>') return false;
  for (int i = 0; i < 3; ++i)
    if (!get16(&in[1 + 4 * i], v[i])) return false;
  std::uint16_t lo, hi;
  if (!nibble(in[13], lo) || !nibble(in[14], hi)) return false;
  flags = static_cast<std::uint8_t>(lo | (hi << 4));
  return true;
}

} // namespace

void encode_command(const FalconCommand& c, FalconPacket& out) noexcept {
  std::uint16_t v[3];
  for (int i = 0; i < 3; ++i)
    v[i] = static_cast<std::uint16_t>(
        std::clamp<std::int16_t>(c.motor[i], -falcon_motor_limit, falcon_motor_limit));
  frame(v, static_cast<std::uint8_t>((c.homing_mode ? 1 : 0) | ((c.leds & 0x7) << 1)), out);
}

bool decode_command(const FalconPacket& in, FalconCommand& c) noexcept {
  std::uint16_t v[3];
  std::uint8_t flags;
  if (!unframe(in, v, flags)) return false;
  for (int i = 0; i < 3; ++i) c.motor[i] = static_cast<std::int16_t>(v[i]);
  c.homing_mode = flags & 1;
  c.leds = (flags >> 1) & 0x7;
  return true;
}

void encode_report(const FalconReport& r, FalconPacket& out) noexcept {
  std::uint16_t v[3];
  for (int i = 0; i < 3; ++i) v[i] = static_cast<std::uint16_t>(r.encoder[i]);
  frame(v, static_cast<std::uint8_t>((r.homed & 0x7) | ((r.buttons & 0xF) << 4)), out);
}

bool decode_report(const FalconPacket& in, FalconReport& r) noexcept {
  std::uint16_t v[3];
  std::uint8_t flags;
  if (!unframe(in, v, flags)) return false;
  for (int i = 0; i < 3; ++i) r.encoder[i] = static_cast<std::int16_t>(v[i]);
  r.homed = flags & 0x7;
  r.buttons = flags >> 4;
  return true;
}

} // namespace hb
