#pragma once
// Whether a person holding the device could feel the difference between two answers to the
// same probe (../docs/perception.md has the sources): force magnitude beyond the force JND or
// the absolute detection threshold, direction beyond the direction discrimination threshold
// while both forces are firm, or a contact on one side only that is itself above threshold.
#include "contact/contact.h"
#include <cstdint>
#include <string>

namespace hb {

/// The thresholds of a perceptible difference. Defaults ("nominal"): w = 10% (force JND at the
/// index finger on a haptic display, Allin, Matsuoka & Klatzky 2002; 8-13% during arm motion,
/// Feyzabadi et al. 2013), F0 = 0.04 N (minimum perceivable force on a commercial interface,
/// Feyzabadi et al. 2013; index fingertip 33.5 mN, King, Donlin & Hannaford 2010), theta = 25
/// deg (force direction without congruent graphics, Barbagli et al. 2006), F_min = 0.2 N.
struct PerceptualThresholds {
  double weber = 0.10;           ///< w: magnitude difference allowed, fraction of |F_exact|.
  double floor_n = 0.04;         ///< F0: magnitude difference always allowed, N.
  double angle_deg = 25.0;       ///< theta: direction difference allowed, degrees.
  double angle_min_force_n = 0.2;///< F_min: directions judged only when both forces reach it.

  /// The strict preset: w 7% (Pang, Tan & Durlach 1991), F0 0.03 N (King et al. 2010),
  /// theta 18 deg (with congruent graphics, Barbagli et al. 2006).
  static PerceptualThresholds strict() noexcept { return {0.07, 0.03, 18.0, 0.2}; }
};

/// Parses "nominal", "strict", or "w=10,f0=0.04,theta=25,fmin=0.2" (percent, N, degrees, N;
/// any subset over the nominal values). Throws hb::InvalidInput naming the bad key or value.
PerceptualThresholds parse_thresholds(const std::string& spec);
/// The spec parse_thresholds reads back (every key).
std::string thresholds_spec(const PerceptualThresholds& t);

/// Why a difference is perceptible (bits; 0: it is not).
enum PerceivedBy : std::uint8_t {
  kPerceivedNone = 0,
  kPerceivedMagnitude = 1,  ///< | |F1| - |F0| | > max(w |F0|, F0).
  kPerceivedDirection = 2,  ///< angle > theta with |F0|, |F1| >= F_min.
  kPerceivedContact = 4,    ///< one side has contact with |F| > F0, the other none.
};

/// The judgement of one probe: the answers' forces (N; clamped to `max_force_n` as the
/// device renders them) and which thresholds the difference passes.
struct PerceivedDifference {
  std::uint8_t by = kPerceivedNone;
  double magnitude_difference_n = 0;  ///< | |F_approx| - |F_exact| |, N.
  double magnitude_threshold_n = 0;   ///< max(w |F_exact|, F0), N.
  double angle_deg = 0;               ///< between the forces (0 unless both are in contact).
  bool perceptible() const noexcept { return by != kPerceivedNone; }
  /// The difference over its threshold: | |F1| - |F0| | / max(w |F0|, F0) (a contact on one
  /// side only is its force over F0), or the angle over theta when the direction test fails
  /// and that is larger; above 1 the difference is perceptible.
  double ratio = 0;
};

/// Judges `approx` against `exact` (forces already computed by the workspace's law).
/// `max_force_n` <= 0: no clamp.
PerceivedDifference perceive(const Contact& exact, const Contact& approx, const PerceptualThresholds& t,
                             double max_force_n = 0) noexcept;

/// "magnitude", "direction", "contact", joined by "+"; "none" for 0.
std::string perceived_by_name(std::uint8_t by);

} // namespace hb
