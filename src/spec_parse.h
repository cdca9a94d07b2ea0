#pragma once
// Reading "key=value,key=value" specs (an error budget, perceptual thresholds): trimming and
// range-checked numbers whose errors name the key and the bad text.
#include "errors.h"
#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <sstream>
#include <string>

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

} // namespace hb
