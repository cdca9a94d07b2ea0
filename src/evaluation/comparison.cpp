#include "evaluation/comparison.h"
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <algorithm>
#include <cmath>

namespace hb {

double relative_force_error(const Contact& exact, const Contact& approx) noexcept {
  const double f0 = exact.force.norm();
  const double diff = (approx.force - exact.force).norm();
  if (f0 <= 0.0) return diff > 0.0 ? 1.0 : 0.0;
  return diff / f0;
}

double angle_error_degrees(const Contact& exact, const Contact& approx) noexcept {
  const double c = std::clamp(double(exact.normal.dot(approx.normal)), -1.0, 1.0);
  return std::acos(c) * 180.0 / M_PI;
}

double quantile(std::vector<double> values, double q) {
  if (values.empty()) return 0.0;
  std::sort(values.begin(), values.end());
  const double pos = std::clamp(q, 0.0, 1.0) * double(values.size() - 1);
  const std::size_t lo = std::size_t(pos);
  const std::size_t hi = std::min(lo + 1, values.size() - 1);
  return values[lo] + (values[hi] - values[lo]) * (pos - double(lo));
}

ComparisonStats summarize(const std::vector<ProbeRecord>& records, float diagonal) {
  ComparisonStats s;
  s.samples = records.size();
  std::vector<double> angles;
  double depth_sq = 0.0;
  std::size_t agree = 0;
  for (const ProbeRecord& r : records) {
    if (r.exact.contact) ++s.exact_contacts;
    if (r.exact.contact == r.approx.contact) ++agree;
    if (r.approx.contact && !r.exact.contact) ++s.false_contacts;
    if (!r.approx.contact && r.exact.contact) ++s.missed_contacts;
    if (r.exact.contact && r.approx.contact) {
      ++s.both_contacts;
      s.force_errors.push_back(relative_force_error(r.exact, r.approx));
      angles.push_back(angle_error_degrees(r.exact, r.approx));
      const double dd = double(r.approx.depth) - double(r.exact.depth);
      depth_sq += dd * dd;
    }
  }
  s.contact_agreement = s.samples ? double(agree) / double(s.samples) : 0.0;
  s.force_error_median = quantile(s.force_errors, 0.5);
  s.force_error_p95 = quantile(s.force_errors, 0.95);
  s.force_error_max = s.force_errors.empty() ? 0.0 : *std::max_element(s.force_errors.begin(), s.force_errors.end());
  s.angle_error_median_deg = quantile(angles, 0.5);
  s.angle_error_p99_deg = quantile(angles, 0.99);
  s.depth_rms_over_diag =
      (s.both_contacts && diagonal > 0.f) ? std::sqrt(depth_sq / double(s.both_contacts)) / double(diagonal) : 0.0;
  return s;
}

ComparisonStats compare_queries(const ContactQuery& approx, const ContactQuery& exact,
                                const std::vector<Segment>& probes, const ForceLaw& law,
                                float diagonal, std::vector<ProbeRecord>* records) {
  std::vector<ProbeRecord> local(probes.size());
  // The approximation answers runs of probes through query_many (the same answers as
  // query(), with the table fetches of a group of probes overlapped).
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, probes.size(), 256),
                    [&](const tbb::blocked_range<std::size_t>& range) {
                      constexpr std::size_t kRun = 64;
                      Contact approx_out[kRun];
                      for (std::size_t first = range.begin(); first < range.end(); first += kRun) {
                        const std::size_t count = std::min(kRun, range.end() - first);
                        approx.query_many(probes.data() + first, count, law, approx_out);
                        for (std::size_t k = 0; k < count; ++k) {
                          ProbeRecord& r = local[first + k];
                          r.segment = probes[first + k];
                          r.exact = exact.query(r.segment, law);
                          r.approx = approx_out[k];
                        }
                      }
                    });
  ComparisonStats s = summarize(local, diagonal);
  if (records) *records = std::move(local);
  return s;
}

} // namespace hb
