#include "perception/perceptible.h"
#include "errors.h"
#include "spec_parse.h"
#include <algorithm>
#include <cmath>
#include <sstream>

namespace hb {

PerceptualThresholds parse_thresholds(const std::string& spec) {
  const std::string all = spec_trim(spec);
  if (all.empty() || all == "nominal" || all == "default") return {};
  if (all == "strict") return PerceptualThresholds::strict();
  PerceptualThresholds t;
  std::stringstream ss(all);
  std::string item;
  const std::string keys = " (keys: w, f0, theta, fmin; or 'nominal', 'strict')";
  while (std::getline(ss, item, ',')) {
    const auto eq = item.find('=');
    if (eq == std::string::npos) throw InvalidInput("--perceptual: '" + item + "' is not key=value" + keys);
    const std::string key = spec_trim(item.substr(0, eq)), value = item.substr(eq + 1);
    if (key == "w")
      t.weber = spec_number(value, "--perceptual w (percent)", 0.0, 1000.0) / 100.0;
    else if (key == "f0")
      t.floor_n = spec_number(value, "--perceptual f0 (N)", 0.0, 100.0);
    else if (key == "theta")
      t.angle_deg = spec_number(value, "--perceptual theta (degrees)", 0.0, 180.0);
    else if (key == "fmin")
      t.angle_min_force_n = spec_number(value, "--perceptual fmin (N)", 0.0, 100.0);
    else
      throw InvalidInput("--perceptual: unknown key '" + key + "'" + keys);
  }
  return t;
}

std::string thresholds_spec(const PerceptualThresholds& t) {
  return "w=" + spec_format(t.weber * 100.0) + ",f0=" + spec_format(t.floor_n) + ",theta=" +
         spec_format(t.angle_deg) + ",fmin=" + spec_format(t.angle_min_force_n);
}

PerceivedDifference perceive(const Contact& exact, const Contact& approx, const PerceptualThresholds& t,
                             double max_force_n) noexcept {
  PerceivedDifference p;
  const auto felt = [&](const Contact& c) {
    if (!c.contact) return 0.0;
    const double f = double(c.force.norm());
    if (!std::isfinite(f)) return max_force_n > 0 ? max_force_n : 1e30;
    return max_force_n > 0 ? std::min(f, max_force_n) : f;
  };
  const double f0 = felt(exact), f1 = felt(approx);
  p.magnitude_difference_n = std::abs(f1 - f0);
  p.magnitude_threshold_n = std::max(t.weber * f0, t.floor_n);
  const double floor = p.magnitude_threshold_n > 0 ? p.magnitude_threshold_n : 1e-30;
  p.ratio = p.magnitude_difference_n / floor;
  if (exact.contact != approx.contact) {
    if (std::max(f0, f1) > t.floor_n) p.by |= kPerceivedContact;
  } else if (p.magnitude_difference_n > p.magnitude_threshold_n) {
    p.by |= kPerceivedMagnitude;
  }
  if (exact.contact && approx.contact && f0 > 0 && f1 > 0) {
    const double c = double(exact.force.dot(approx.force)) / (double(exact.force.norm()) * double(approx.force.norm()));
    p.angle_deg = std::acos(std::clamp(std::isfinite(c) ? c : -1.0, -1.0, 1.0)) * 180.0 / 3.14159265358979323846;
    if (f0 >= t.angle_min_force_n && f1 >= t.angle_min_force_n && p.angle_deg > t.angle_deg) {
      p.by |= kPerceivedDirection;
      p.ratio = std::max(p.ratio, t.angle_deg > 0 ? p.angle_deg / t.angle_deg : 1e30);
    }
  }
  return p;
}

std::string perceived_by_name(std::uint8_t by) {
  if (by == kPerceivedNone) return "none";
  std::string s;
  const auto add = [&](std::uint8_t bit, const char* name) {
    if (!(by & bit)) return;
    if (!s.empty()) s += "+";
    s += name;
  };
  add(kPerceivedMagnitude, "magnitude");
  add(kPerceivedDirection, "direction");
  add(kPerceivedContact, "contact");
  return s;
}

} // namespace hb
