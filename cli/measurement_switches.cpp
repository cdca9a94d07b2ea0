#include "measurement_switches.h"
#include "spec_option.h"
#include "spec_parse.h"
#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <sstream>
#include <utility>

namespace hb::cli {

namespace {
struct Measurements {
  std::vector<std::pair<std::string, std::string>> given;
};
const Measurements& measurements() {
  static const Measurements m = [] {
    Measurements out;
    const char* env = std::getenv("HB_MEASURE");
    if (!env) return out;
    std::stringstream ss(env);
    std::string item;
    while (std::getline(ss, item, ',')) {
      item = spec_trim(item);
      if (item.empty()) continue;
      const auto eq = item.find('=');
      const std::string name = item.substr(0, eq);
      const auto& names = measurement_names();
      if (std::find(names.begin(), names.end(), name) == names.end()) {
        std::string k;
        for (const auto& n : names) k += (k.empty() ? "" : ", ") + n;
        throw UsageError("HB_MEASURE: unknown switch '" + name + "' (switches: " + k + ")");
      }
      out.given.emplace_back(name, eq == std::string::npos ? "" : item.substr(eq + 1));
    }
    return out;
  }();
  return m;
}
} // namespace

void check_measurements() { (void)measurements(); }

std::function<void(const char*, double)> decompose_times() {
  if (!measurement("decompose-times")) return {};
  return [](const char* phase, double seconds) { std::fprintf(stderr, "decompose %s at %.2f s\n", phase, seconds); };
}

std::string measurement_choice(const std::string& name, const std::string& fallback,
                               const std::vector<std::string>& allowed) {
  const auto v = measurement(name);
  if (!v) return fallback;
  if (std::find(allowed.begin(), allowed.end(), *v) == allowed.end()) {
    std::string k;
    for (const auto& a : allowed) k += (k.empty() ? "" : " or ") + a;
    throw UsageError("HB_MEASURE " + name + ": '" + *v + "' is not " + k);
  }
  return *v;
}

const std::vector<std::string>& measurement_names() {
  // bake: the searches and shading checks kept for before/after figures and the triangle ids
  // kept for --route boxes; bench: tables without huge pages; servo: the loop without priming
  // or with another busy-wait; stability: the other depth law and safety response;
  // decompose-times: each phase of an automatic decomposition on stderr.
  static const std::vector<std::string> names = {"full-search", "keep-ids",  "simplify-shading", "simplify-shading-check",
                                                 "no-huge-pages", "no-prime", "spin-us",  "depth-law",
                                                 "safety",        "decompose-times"};
  return names;
}

std::optional<std::string> measurement(const std::string& name) {
  for (const auto& g : measurements().given)
    if (g.first == name) return g.second;
  return std::nullopt;
}

} // namespace hb::cli
