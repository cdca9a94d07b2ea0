#pragma once
// The uncompressed sample record and the sampling densities of a haptic box, shared by the
// box, the bake and the codecs.
#include <cstddef>
#include <cstdint>

namespace hb {

/// Sampling densities (paper Figure 9: "m n").
struct BoxParams {
  int m = 32;  ///< position points per PBB face edge (m x m per face, edges included), >= 2.
  int n = 16;  ///< directional points per sub-block face edge (n x n, edges included), >= 2.
  std::size_t samples_per_position() const { return 12u * std::size_t(n) * std::size_t(n); }
  std::size_t position_count() const { return 6u * std::size_t(m) * std::size_t(m); }
  std::size_t sample_count() const { return position_count() * samples_per_position(); }
  /// Tiles: one n x n sub-block face at one position point (the unit the codecs work on).
  std::size_t tile_count() const { return position_count() * 12u; }
};

/// One directional sample: distance `t` from the position point to the first hit of the
/// piece along the sample's direction, and the shaded normal there in 32-bit octahedral
/// encoding. A ray that misses the piece stores `t = kMissT` (negative) and no normal;
/// see HapticBox::query for why interpolation behaves well next to misses.
struct Sample {
  float t;
  std::uint32_t normal;
};
static_assert(sizeof(Sample) == 8, "Sample is an 8-byte record");
constexpr float kMissT = -1.f;

} // namespace hb
