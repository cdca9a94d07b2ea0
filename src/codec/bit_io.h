#pragma once
// Little-endian bit streams for the codecs. Readers load 8 bytes at a time, so every
// payload is followed by at least 8 bytes of padding (kBitReadPadding).
#include <cstdint>
#include <cstring>
#include <vector>

namespace hb {

constexpr std::size_t kBitReadPadding = 8;

/// Reads `bits` (0..56) bits starting at bit `pos` of `data`, least significant first.
inline std::uint64_t read_bits(const std::uint8_t* data, std::uint64_t pos, unsigned bits) noexcept {
  std::uint64_t word;
  std::memcpy(&word, data + (pos >> 3), sizeof(word));
  word >>= (pos & 7u);
  return bits >= 64 ? word : (word & ((std::uint64_t(1) << bits) - 1u));
}

/// Appends bits to a byte vector, least significant first.
class BitWriter {
public:
  explicit BitWriter(std::vector<std::uint8_t>& out) : out_(out) {}
  void put(std::uint64_t value, unsigned bits) {
    for (unsigned i = 0; i < bits; ++i) {
      if ((pos_ & 7u) == 0) out_.push_back(0);
      if ((value >> i) & 1u) out_.back() |= std::uint8_t(1u << (pos_ & 7u));
      ++pos_;
    }
  }
  std::uint64_t bit_position() const { return pos_; }

private:
  std::vector<std::uint8_t>& out_;
  std::uint64_t pos_ = 0;
};

/// Population count. SWAR instead of __builtin_popcountll: without -mpopcnt (the build
/// targets baseline x86-64) the builtin is a library call, several times slower.
inline unsigned popcount64(std::uint64_t x) noexcept {
  x = x - ((x >> 1) & 0x5555555555555555ull);
  x = (x & 0x3333333333333333ull) + ((x >> 2) & 0x3333333333333333ull);
  x = (x + (x >> 4)) & 0x0f0f0f0f0f0f0f0full;
  return unsigned((x * 0x0101010101010101ull) >> 56);
}

/// Population count of the low 8 bits (SWAR, as popcount64()).
inline unsigned popcount8(unsigned x) noexcept {
  x &= 0xffu;
  x = x - ((x >> 1) & 0x55u);
  x = (x & 0x33u) + ((x >> 2) & 0x33u);
  return (x + (x >> 4)) & 0x0fu;
}

/// Number of bits needed to store values 0..v.
inline unsigned bits_for(std::uint64_t v) noexcept {
  unsigned b = 0;
  while (v) {
    ++b;
    v >>= 1;
  }
  return b;
}

template <typename T> void put_pod(std::vector<std::uint8_t>& out, const T& v) {
  const auto* p = reinterpret_cast<const std::uint8_t*>(&v);
  out.insert(out.end(), p, p + sizeof(T));
}
template <typename T> T get_pod(const std::uint8_t* p) noexcept {
  T v;
  std::memcpy(&v, p, sizeof(T));
  return v;
}

} // namespace hb
