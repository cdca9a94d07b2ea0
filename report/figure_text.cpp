#include "figure_text.h"
#include <algorithm>
#include <cmath>
#include <cstdio>

namespace hb {

namespace {

std::string group_thousands(const std::string& text) {
  // text: optional '-', digits, optional fraction.
  const std::size_t start = text[0] == '-' ? 1 : 0;
  std::size_t dot = text.find('.');
  if (dot == std::string::npos) dot = text.size();
  if (dot - start < 5) return text;  // below 10,000: no separator
  std::string out = text.substr(0, start);
  const std::string digits = text.substr(start, dot - start);
  for (std::size_t i = 0; i < digits.size(); ++i) {
    if (i > 0 && (digits.size() - i) % 3 == 0) out += ',';
    out += digits[i];
  }
  return out + text.substr(dot);
}

} // namespace

std::string sig(double value, int digits) {
  if (std::isnan(value)) return "n/a";
  if (std::isinf(value)) return value > 0 ? "inf" : "-inf";
  if (digits < 1) digits = 1;
  if (value == 0.0) return "0";
  // Round to `digits` significant digits, then print with just the decimals that carries.
  const int magnitude = int(std::floor(std::log10(std::fabs(value))));
  const double scale = std::pow(10.0, digits - 1 - magnitude);
  double rounded = std::round(value * scale) / scale;
  const int rounded_magnitude = rounded == 0.0 ? magnitude : int(std::floor(std::log10(std::fabs(rounded))));
  int decimals = std::max(0, digits - 1 - rounded_magnitude);
  char buf[64];
  if (rounded_magnitude < -12 || rounded_magnitude > 15) {
    std::snprintf(buf, sizeof buf, "%.*g", digits, value);
    return buf;
  }
  std::snprintf(buf, sizeof buf, "%.*f", decimals, rounded);
  std::string text = buf;
  if (text.find('.') != std::string::npos) {
    while (text.back() == '0') text.pop_back();
    if (text.back() == '.') text.pop_back();
  }
  if (text == "-0") text = "0";
  return group_thousands(text);
}

std::string percent(double fraction, int digits) { return sig(100.0 * fraction, digits) + " %"; }

std::string agreement_percent(double fraction) {
  if (std::isnan(fraction)) return "n/a";
  const double shortfall = 100.0 * (1.0 - fraction);
  if (shortfall <= 0.0) return sig(100.0 * fraction, 4) + " %";
  // Enough decimals for two significant digits of the shortfall (at least 0, at most 6).
  const int decimals = std::clamp(1 - int(std::floor(std::log10(shortfall))), 0, 6);
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.*f", decimals, 100.0 * fraction);
  std::string text = buf;
  if (text.find('.') != std::string::npos) {
    while (text.back() == '0') text.pop_back();
    if (text.back() == '.') text.pop_back();
  }
  return text + " %";
}

std::string bytes_text(std::uint64_t bytes) {
  const double b = double(bytes);
  if (b >= 1e12) return sig(b / 1e12) + " TB";
  if (b >= 1e9) return sig(b / 1e9) + " GB";
  if (b >= 1e6) return sig(b / 1e6) + " MB";
  if (b >= 1e3) return sig(b / 1e3) + " kB";
  return std::to_string(bytes) + " B";
}

std::string count_text(double count) {
  const double a = std::fabs(count);
  if (a >= 1e9) return sig(count / 1e9) + " G";
  if (a >= 1e6) return sig(count / 1e6) + " M";
  if (a >= 1e4) return sig(count / 1e3) + " k";
  return sig(count, 4);
}

std::string duration_text(double seconds) {
  if (std::isnan(seconds)) return "n/a";
  const double a = std::fabs(seconds);
  if (a >= 1.0 || a == 0.0) return sig(seconds) + " s";
  if (a >= 1e-3) return sig(seconds * 1e3) + " ms";
  if (a >= 1e-6) return sig(seconds * 1e6) + " us";
  return sig(seconds * 1e9) + " ns";
}

SpeedComparison compare_speed(double box_seconds, double exact_seconds) {
  if (!(box_seconds > 0.0) || !(exact_seconds > 0.0)) return SpeedComparison::not_measured;
  const double ratio = exact_seconds / box_seconds;
  if (ratio >= 0.95 && ratio <= 1.0 / 0.95) return SpeedComparison::as_fast;
  return ratio > 1.0 ? SpeedComparison::faster : SpeedComparison::slower;
}

std::string speed_verdict(double box_seconds, double exact_seconds) {
  const double ratio = exact_seconds / box_seconds;
  switch (compare_speed(box_seconds, exact_seconds)) {
    case SpeedComparison::not_measured: return "not measured";
    case SpeedComparison::as_fast: return "as fast as exact (" + sig(ratio, 2) + "x)";
    case SpeedComparison::faster: return sig(ratio, 2) + "x faster than exact";
    case SpeedComparison::slower: break;
  }
  return sig(1.0 / ratio, 2) + "x slower than exact";
}

} // namespace hb
