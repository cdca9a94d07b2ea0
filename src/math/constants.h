#pragma once
// Mathematical constants the core shares (one definition, so files of one target never clash).

namespace hb {

inline constexpr double kPi = 3.14159265358979323846;

}  // namespace hb
