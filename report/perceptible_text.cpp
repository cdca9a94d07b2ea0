#include "perceptible_text.h"
#include "figure_text.h"
#include "evaluation/probe_sampling.h"

namespace hb {

std::string perceptible_headline(const ComparisonStats& s) {
  return "perceptibly different: " + sig(double(s.perceptible), 6) + " of " + sig(double(s.samples), 6) + " probes (" +
         percent(s.perceptible_share) + ")";
}

std::string light_touch_words() {
  const ProbeOptions o = light_touch_probe_options(0);
  return "within " + sig(o.cone_degrees) + " deg of the normal, tips up to " + sig(o.max_depth_fraction * 100.0) +
         " % of the diagonal deep";
}

std::string thresholds_text(const PerceptualThresholds& t) {
  return "max(" + sig(t.weber * 100.0) + " % |F|, " + sig(t.floor_n) + " N), " + sig(t.angle_deg) + " deg at >= " +
         sig(t.angle_min_force_n) + " N";
}

std::string perceptible_lines(const ComparisonStats& s) {
  return "  perceptibly different " + sig(double(s.perceptible), 6) + " of " + sig(double(s.samples), 6) + " probes (" +
         percent(s.perceptible_share) + "): " + sig(double(s.perceptible_magnitude), 6) + " magnitude, " +
         sig(double(s.perceptible_direction), 6) + " direction, " + sig(double(s.perceptible_contact), 6) +
         " contact\n  force difference      median " + sig(s.force_difference_median_n) + " N, p95 " +
         sig(s.force_difference_p95_n) + " N, max " + sig(s.force_difference_max_n) + " N (threshold " +
         thresholds_text(s.thresholds) + "; exact's median force " + sig(s.exact_force_median_n) + " N)\n";
}

} // namespace hb
