#pragma once
// The paper's codec (sections 4.4, 6.1.3): a 2D Haar wavelet per n x n sub-block face (a
// tile, padded to N = the next power of two by repeating its edge), on t and on the two
// octahedral normal coordinates, with coefficients quantised on a per-tile step and the
// ones that round to zero dropped (thresholding).
//  - Hit/miss is kept exactly in a per-tile mask (the paper stores a far value for misses,
//    which a transform smears into the hits next to a silhouette); misses are filled with
//    the mean of the tile's hits before the transform, so they cost few coefficients.
//  - Unnormalised (averaging) Haar: a value is the DC term plus, per level, +-H +-V +-D of
//    its group. Coefficients are integers in units of the tile's step, so a single value is
//    an exact integer sum of 1 + 3 log2 N coefficients: random access without a tile decode.
//  - Per tile the encoder halves the step until every hit is within the bound (checked on
//    the decoded values, so the bound holds whatever the rounding does).
//  - Record: 16-byte header (mode, widths, step exponents, bit offsets of the u and v
//    sections), the hit mask when mixed, then per channel a non-zero bitmap of N^2 bits and
//    the non-zero coefficients (zigzag, fixed width); a coefficient is found by popcount.
#include "codec/bit_io.h"
#include "codec/table_payload.h"
#include "prefetch.h"
#include <algorithm>
#include <cmath>

namespace hb {

/// Encodes a raw table into a Haar payload; t error <= t_step / 2, octahedral coordinate
/// error <= n_step / 2 for every hit.
std::vector<std::uint8_t> encode_haar_table(const Sample* raw, const BoxParams& params, float t_step, float n_step);

/// Read-only view of a Haar payload.
class HaarTable {
public:
  static constexpr std::size_t kHeaderBytes = 16;

  HaarTable() = default;
  /// Validates the payload's header (O(1)); throws hb::InvalidInput.
  HaarTable(const std::uint8_t* payload, std::size_t bytes, const BoxParams& params);

  void prefetch(std::size_t tile, int, int) const noexcept { hb::prefetch(index_ + tile); }

  /// Random access to one sample; false for a miss. Corrupt records read as misses.
  bool fetch(std::size_t tile, int a, int b, float& t, float& u, float& v) const noexcept {
    std::uint32_t offset;
    std::memcpy(&offset, index_ + tile, 4);
    if (offset >= data_bytes_) return false;
    const std::uint8_t* rec = data_ + offset;
    const unsigned mode = rec[0];
    if (mode == 0) return false;
    const unsigned idx = unsigned(a) * unsigned(N_) + unsigned(b);
    const std::uint8_t* bits = rec + kHeaderBytes;
    if (mode == 2) {
      if (!((bits[idx >> 3] >> (idx & 7u)) & 1u)) return false;
      bits += mask_bytes_;
    }
    const auto off_u = get_pod<std::uint32_t>(rec + 8), off_v = get_pod<std::uint32_t>(rec + 12);
    if (off_u > max_section_bits_ || off_v > max_section_bits_) return false;
    // std::min / max, not fmin / fmax (library calls on x86-64): the same for these values,
    // which are never NaN or -0 (an integer times a positive step).
    t = std::max(0.f, float(path_sum(bits, rec[1] & 31u, a, b)) * step(t_step_, rec[4]));
    u = std::min(1.f, std::max(-1.f, float(path_sum(bits + off_u / 8, rec[2] & 31u, a, b)) * step(n_step_, rec[5])));
    v = std::min(1.f, std::max(-1.f, float(path_sum(bits + off_v / 8, rec[3] & 31u, a, b)) * step(n_step_, rec[6])));
    return true;
  }

  /// The 2 x 2 quad at (a0, b0) of one tile, in the query's order (a0, b0), (a0 + 1, b0),
  /// (a0 + 1, b0 + 1), (a0, b0 + 1): t[k], u[k], v[k] equal fetch()'s values bit for bit;
  /// a miss gets {kMissT, 0, 0}. Returns the hit mask (bit k: sample k is a hit). Faster than
  /// four fetch() calls: the header is read once, the coefficients the four paths share (all
  /// levels above the one where a0 and a0 + 1, or b0 and b0 + 1, part) are read once, and
  /// bitmap ranks come from per-word prefix counts made once per quad. Precondition:
  /// 0 <= a0, b0 <= n - 2. Corrupt records read as misses, never out of bounds.
  unsigned fetch_quad(std::size_t tile, int a0, int b0, float* t, float* u, float* v) const noexcept;
  /// fetch_quad() counts bitmap ranks with the popcnt instruction when the CPU has it (the
  /// default), else portably; `false` forces the portable count (tests, benchmarks). The
  /// values are the same either way.
  void use_hardware_popcount(bool on) noexcept;

  DecodedSample decode(std::size_t tile, int a, int b) const noexcept {
    DecodedSample s{kMissT, 0.f, 0.f};
    if (!fetch(tile, a, b, s.t, s.u, s.v)) s = {kMissT, 0.f, 0.f};
    return s;
  }

  /// Full decode of a tile by the integer inverse transform (n x n, row a major). Not for
  /// the hot path: allocates (may throw std::bad_alloc).
  void decode_tile(std::size_t tile, DecodedSample* out) const;

  /// Coefficient index of each term of value (a, b), and its sign; returns the count.
  static int path(int N, int a, int b, unsigned* index, int* sign) noexcept {
    int count = 0;
    index[count] = 0;
    sign[count++] = 1;
    for (int h = N / 2, l = 0; h >= 1; h /= 2, ++l) {
      const int ga = a >> (l + 1), gb = b >> (l + 1);
      const int sa = ((a >> l) & 1) ? -1 : 1, sb = ((b >> l) & 1) ? -1 : 1;
      index[count] = unsigned(ga * N + h + gb);
      sign[count++] = sb;
      index[count] = unsigned((h + ga) * N + gb);
      sign[count++] = sa;
      index[count] = unsigned((h + ga) * N + h + gb);
      sign[count++] = sa * sb;
    }
    return count;
  }

  /// A tile's step: base * 2^-exponent (exponent byte 0..63; exact, equal to std::ldexp).
  static float step(float base, std::uint8_t exponent) noexcept {
    return base * kInversePowersOfTwo[exponent & 63u];
  }

private:
  static constexpr float kInversePowersOfTwo[64] = {
      0x1p-0f,  0x1p-1f,  0x1p-2f,  0x1p-3f,  0x1p-4f,  0x1p-5f,  0x1p-6f,  0x1p-7f,  0x1p-8f,  0x1p-9f,  0x1p-10f,
      0x1p-11f, 0x1p-12f, 0x1p-13f, 0x1p-14f, 0x1p-15f, 0x1p-16f, 0x1p-17f, 0x1p-18f, 0x1p-19f, 0x1p-20f, 0x1p-21f,
      0x1p-22f, 0x1p-23f, 0x1p-24f, 0x1p-25f, 0x1p-26f, 0x1p-27f, 0x1p-28f, 0x1p-29f, 0x1p-30f, 0x1p-31f, 0x1p-32f,
      0x1p-33f, 0x1p-34f, 0x1p-35f, 0x1p-36f, 0x1p-37f, 0x1p-38f, 0x1p-39f, 0x1p-40f, 0x1p-41f, 0x1p-42f, 0x1p-43f,
      0x1p-44f, 0x1p-45f, 0x1p-46f, 0x1p-47f, 0x1p-48f, 0x1p-49f, 0x1p-50f, 0x1p-51f, 0x1p-52f, 0x1p-53f, 0x1p-54f,
      0x1p-55f, 0x1p-56f, 0x1p-57f, 0x1p-58f, 0x1p-59f, 0x1p-60f, 0x1p-61f, 0x1p-62f, 0x1p-63f};
  // Sum of the signed coefficients on the path of (a, b) in one channel section.
  std::int64_t path_sum(const std::uint8_t* section, unsigned k, int a, int b) const noexcept {
    const std::uint8_t* values = section + bitmap_bytes_;
    std::int64_t sum = 0;
    auto term = [&](unsigned idx) -> std::int64_t {
      const std::uint64_t word = get_pod<std::uint64_t>(section + (idx >> 6) * 8);
      if (!((word >> (idx & 63u)) & 1u)) return 0;
      unsigned rank = unsigned(popcount64(word & ((std::uint64_t(1) << (idx & 63u)) - 1u)));
      for (unsigned w = 0; w < (idx >> 6); ++w) rank += unsigned(popcount64(get_pod<std::uint64_t>(section + w * 8)));
      const std::uint64_t z = read_bits(values, std::uint64_t(rank) * k, k);
      return std::int64_t(z >> 1) ^ -std::int64_t(z & 1u);
    };
    sum += term(0);
    for (int h = N_ / 2, l = 0; h >= 1; h /= 2, ++l) {
      const int ga = a >> (l + 1), gb = b >> (l + 1);
      const bool sa = (a >> l) & 1, sb = (b >> l) & 1;
      const std::int64_t H = term(unsigned(ga * N_ + h + gb));
      const std::int64_t V = term(unsigned((h + ga) * N_ + gb));
      const std::int64_t D = term(unsigned((h + ga) * N_ + h + gb));
      sum += (sb ? -H : H) + (sa ? -V : V) + ((sa != sb) ? -D : D);
    }
    return sum;
  }

  template <bool kHardwarePopcount>
  unsigned fetch_quad_with(std::size_t tile, int a0, int b0, float* t, float* u, float* v) const noexcept;
  unsigned fetch_quad_popcnt(std::size_t tile, int a0, int b0, float* t, float* u, float* v) const noexcept;

  const std::uint32_t* index_ = nullptr;
  const std::uint8_t* data_ = nullptr;
  std::size_t data_bytes_ = 0;
  float t_step_ = 1.f, n_step_ = 1.f;
  int n_ = 2, N_ = 2;
  std::size_t mask_bytes_ = 0, bitmap_bytes_ = 0;
  std::uint32_t max_section_bits_ = 0;
  bool hardware_popcount_ = false;
};

} // namespace hb
