#pragma once
// Reading "key=value,key=value" specs (an error budget, perceptual thresholds, a volume's
// surface): trimming, range-checked numbers whose errors name the key and the bad text, and
// the grammar "[head,]key=value,key,..." that every front end's spec options share.
#include "errors.h"
#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <functional>
#include <sstream>
#include <string>
#include <vector>

namespace hb {

inline std::string spec_trim(const std::string& s) {
  const auto a = s.find_first_not_of(" \t"), b = s.find_last_not_of(" \t");
  return a == std::string::npos ? std::string() : s.substr(a, b - a + 1);
}

/// A finite number in [lo, hi], or throws hb::InvalidInput naming `what`.
inline double spec_number(const std::string& text, const std::string& what, double lo, double hi) {
  const std::string t = spec_trim(text);
  char* end = nullptr;
  errno = 0;
  const double v = std::strtod(t.c_str(), &end);
  if (t.empty() || end != t.c_str() + t.size() || errno != 0 || !std::isfinite(v) || v < lo || v > hi) {
    std::ostringstream os;
    os << what << ": '" << text << "' is not a number in [" << lo << ", " << hi << "]";
    throw InvalidInput(os.str());
  }
  return v;
}

/// A number as a spec prints it (6 significant digits).
inline std::string spec_format(double v) {
  std::ostringstream os;
  os.precision(6);
  os << v;
  return os.str();
}

/// One key of a spec ("block,ratio=20,strict"): its name and what it sets from its value (""
/// for a bare key); `what` names the option and key for error messages.
struct SpecKey {
  std::string key;
  std::function<void(const std::string& value, const std::string& what)> set;
};

/// Parses "[head,]key=value,key,..." given to `option`: each item sets its key (any order, any
/// subset); `head` (when not null) receives a first item that is not one of the keys. Throws
/// hb::InvalidInput naming the option and the unknown key (with the known ones); a key's own
/// errors are its setter's.
inline void parse_spec_keys(const std::string& option, const std::string& spec, const std::vector<SpecKey>& keys,
                            std::string* head = nullptr) {
  const auto known = [&] {
    std::string k;
    for (const SpecKey& key : keys) k += (k.empty() ? "" : ", ") + key.key;
    return k;
  };
  std::stringstream ss(spec);
  std::string item;
  bool first = true;
  while (std::getline(ss, item, ',')) {
    item = spec_trim(item);
    const auto eq = item.find('=');
    const std::string key = spec_trim(item.substr(0, eq)), value = eq == std::string::npos ? "" : item.substr(eq + 1);
    const auto it = std::find_if(keys.begin(), keys.end(), [&](const SpecKey& k) { return k.key == key; });
    if (it == keys.end() && first && head) {
      *head = item;
      first = false;
      continue;
    }
    first = false;
    if (item.empty()) continue;
    if (it == keys.end()) throw InvalidInput(option + ": unknown key '" + key + "' (keys: " + known() + ")");
    it->set(value, option + " " + key);
  }
}

} // namespace hb
