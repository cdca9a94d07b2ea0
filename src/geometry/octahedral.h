#pragma once
// Octahedral encoding of unit vectors (Cigolle et al. 2014, "A Survey of Efficient
// Representations for Independent Unit Vectors"): two signed 16-bit values in 32 bits,
// worst-case angular error about 0.003 degrees.
#include "math/vec3.h"
#include <algorithm>
#include <cmath>
#include <cstdint>

namespace hb {

inline float oct_sign(float v) noexcept { return v >= 0.f ? 1.f : -1.f; }

/// Encodes a unit vector (the zero vector encodes as +Z).
inline std::uint32_t encode_octahedral32(const Vec3& n) noexcept {
  const float s = std::fabs(n.x()) + std::fabs(n.y()) + std::fabs(n.z());
  float u = 0.f, v = 0.f;
  if (s > 0.f) {
    u = n.x() / s;
    v = n.y() / s;
    if (n.z() < 0.f) {
      const float pu = u, pv = v;
      u = (1.f - std::fabs(pv)) * oct_sign(pu);
      v = (1.f - std::fabs(pu)) * oct_sign(pv);
    }
  }
  const auto q = [](float x) {
    return static_cast<std::uint16_t>(static_cast<std::int16_t>(std::lround(x * 32767.f)));
  };
  return std::uint32_t(q(u)) | (std::uint32_t(q(v)) << 16);
}

/// The octahedral coordinates u, v in [-1, 1] of a 32-bit code.
inline void oct_coordinates(std::uint32_t code, float& u, float& v) noexcept {
  u = float(static_cast<std::int16_t>(code & 0xffffu)) * (1.f / 32767.f);
  v = float(static_cast<std::int16_t>(code >> 16)) * (1.f / 32767.f);
}

/// As decode_octahedral32_unnormalized, from octahedral coordinates u, v in [-1, 1].
inline Vec3 oct_decode_unnormalized(float u, float v) noexcept {
  Vec3 n(u, v, 1.f - std::fabs(u) - std::fabs(v));
  const float t = std::max(-n.z(), 0.f);  // not fmax (a libm call); z is never NaN
  n.x() += n.x() >= 0.f ? -t : t;
  n.y() += n.y() >= 0.f ? -t : t;
  return n;
}

/// Decodes to a vector along the encoded direction whose length lies in [1/sqrt(3), 1] and
/// varies smoothly with the direction: blend such vectors of nearby directions and
/// normalise once (what interpolation does), instead of normalising each.
inline Vec3 decode_octahedral32_unnormalized(std::uint32_t code) noexcept {
  float u, v;
  oct_coordinates(code, u, v);
  return oct_decode_unnormalized(u, v);
}

/// Decodes to a unit vector.
inline Vec3 decode_octahedral32(std::uint32_t code) noexcept {
  return decode_octahedral32_unnormalized(code).normalized();
}

} // namespace hb
