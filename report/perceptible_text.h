#pragma once
// The headline accuracy figure in words: how many probes a hand would tell apart from exact
// (hb::perceive), by which test, and the force differences against the threshold. `eval`,
// `bench`, `sweep`, the report and the window print it through these.
#include "evaluation/comparison.h"
#include <string>

namespace hb {

/// "perceptibly different: 3 of 20,000 probes (0.015 %)" (the headline, one phrase).
std::string perceptible_headline(const ComparisonStats& s);

/// What eval's light touches are (light_touch_probe_options): "within 85 deg of the normal,
/// tips up to 0.5 % of the diagonal deep".
std::string light_touch_words();

/// The thresholds in words: "max(10 % |F|, 0.04 N), 25 deg at >= 0.2 N".
std::string thresholds_text(const PerceptualThresholds& t);

/// Two aligned lines for a text summary (each ends with a newline):
/// "  perceptibly different  3 of 20,000 probes (0.015 %): 2 magnitude, 1 contact, 0 direction"
/// "  force difference      median 0.0012 N, p95 0.0051 N, max 0.31 N (threshold max(10 % |F|, 0.04 N); exact's median 1.2 N)"
std::string perceptible_lines(const ComparisonStats& s);

} // namespace hb
