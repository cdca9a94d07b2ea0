#include "spec_option.h"
#include "errors.h"
#include "evaluation/segments_csv.h"
#include <cstdio>

namespace hb::cli {

CLI::Validator finite_range(double lo, double hi) {
  const auto show = [](double v) {
    char text[32];
    std::snprintf(text, sizeof text, "%g", v);
    return std::string(text);
  };
  const std::string range = "[" + show(lo) + ", " + show(hi) + "]";
  return CLI::Validator(
      [lo, hi, range](std::string& text) -> std::string {
        float v = 0.f;
        if (!parse_finite_float(text, v)) return "'" + text + "' is not a finite number";
        if (!(double(v) >= lo && double(v) <= hi)) return "'" + text + "' is outside " + range;
        return {};
      },
      "FINITE in " + range);
}

double spec_number_or_usage(const std::string& text, const std::string& what, double lo, double hi) {
  try {
    return spec_number(text, what, lo, hi);
  } catch (const InvalidInput& e) {
    throw UsageError(e.what());
  }
}

SpecKey flag_key(const std::string& key, bool& field) {
  return {key, [&field](const std::string& v, const std::string& what) {
            if (v.empty() || v == "1" || v == "on" || v == "yes") field = true;
            else if (v == "0" || v == "off" || v == "no") field = false;
            else throw UsageError(what + ": '" + v + "' is not on or off");
          }};
}

void parse_spec(const std::string& option, const std::string& spec, const std::vector<SpecKey>& keys,
                std::string* head) {
  try {
    hb::parse_spec_keys(option, spec, keys, head);
  } catch (const InvalidInput& e) {
    throw UsageError(e.what());
  }
}

} // namespace hb::cli
