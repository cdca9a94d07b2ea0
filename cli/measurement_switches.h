#pragma once
// Measurement-only switches (before/after comparisons, not a user's options): read from the
// environment variable HB_MEASURE, one place, as "name[=value],..." (e.g.
// HB_MEASURE=full-search,spin-us=0).
#include <functional>
#include <optional>
#include <string>
#include <vector>

namespace hb::cli {

/// The value of the switch `name` (empty string for a bare one); empty optional: not given.
/// The names are listed in measurement_names(); an unknown one is a usage error.
std::optional<std::string> measurement(const std::string& name);
const std::vector<std::string>& measurement_names();
/// A measurement switch's value among `allowed` (`fallback` when not given); a value outside
/// them is a usage error naming it.
std::string measurement_choice(const std::string& name, const std::string& fallback,
                               const std::vector<std::string>& allowed);
/// The automatic decomposition's phase callback of HB_MEASURE=decompose-times (each phase's
/// end on stderr), or an empty one.
std::function<void(const char*, double)> decompose_times();
/// Reads HB_MEASURE now (main, before parsing): an unknown switch fails every command alike.
void check_measurements();

} // namespace hb::cli
