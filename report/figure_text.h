#pragma once
// Figures as people read them: significant digits rather than raw precision ("0.0015 %", not
// "0.00 %"; "151 MB", not "150.995 MB"; "18.9 M", not "18874368"). The CLI, the report and
// the window format every figure they print through these, so the same number reads the same.
#include <cstdint>
#include <string>

namespace hb {

/// `value` with `digits` significant digits (>= 1), trailing zeros dropped, thousands
/// separated by commas from 10,000 up: sig(0.0015234) = "0.00152", sig(150.995) = "151",
/// sig(15011.68) = "15,000", sig(0) = "0". NaN -> "n/a", infinities -> "inf" / "-inf".
std::string sig(double value, int digits = 3);

/// A fraction as a percentage with `digits` significant digits: percent(0.000015) = "0.0015 %".
std::string percent(double fraction, int digits = 3);

/// A fraction close to 1 (an agreement) as a percentage that keeps its distance from 100 %
/// visible: two significant digits of the shortfall, so 0.99515 -> "99.52 %", 0.9 -> "90 %",
/// 1 -> "100 %".
std::string agreement_percent(double fraction);

/// Bytes in decimal units, 3 significant digits: "151 MB", "3.3 kB", "512 B".
std::string bytes_text(std::uint64_t bytes);

/// A count in k (thousands), M (millions) or G above 10,000, 3 significant digits:
/// count_text(18874368) = "18.9 M", count_text(5000) = "5000".
std::string count_text(double count);

/// A duration with its unit chosen for 1-999: "1.23 s", "450 ms", "3.1 us", "310 ns".
std::string duration_text(double seconds);

/// How the box's time compares with exact's on the same probes (box first): as fast within 5 %
/// either way; not measured when either time is not positive. Every speed verdict the CLI, the
/// report and the window state comes from this one rule.
enum class SpeedComparison { not_measured, faster, as_fast, slower };
SpeedComparison compare_speed(double box_seconds, double exact_seconds);

/// compare_speed in words: "N.Nx faster than exact" / "N.Nx slower than exact" / "as fast as
/// exact (N.Nx)" / "not measured".
std::string speed_verdict(double box_seconds, double exact_seconds);

} // namespace hb
