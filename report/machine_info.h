#pragma once
// Where and when a figure was measured: stamped on reports so an engineer can file them.
#include <string>

namespace hb {

/// "host (CPU model, N cores)" from the host name and /proc/cpuinfo ("unknown CPU" elsewhere).
std::string machine_description();

/// The current UTC time, ISO 8601 to the second: "YYYY-MM-DDThh:mm:ssZ".
std::string utc_now_iso();

} // namespace hb
