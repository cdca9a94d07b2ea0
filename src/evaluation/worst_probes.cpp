// 1. rank the both-contact probes by relative force error, keep the largest;
// 2. rank the disagreements by the depth of the contact one answer claims, keep the deepest;
// 3. describe each: depths and forces, the incidence angle, and the cause in one sentence.
#include "evaluation/worst_probes.h"
#include <algorithm>
#include <cmath>
#include <cstdio>

namespace hb {

namespace {

std::string number(double v, int digits = 2) {
  char buf[48];
  std::snprintf(buf, sizeof buf, "%.*g", digits, v);
  return buf;
}

double incidence(const Segment& s, const Vec3& normal) {
  const Vec3 d = s.end - s.start;
  const float len = d.norm(), n = normal.norm();
  if (!(len > 0.f) || !(n > 0.f)) return 0.0;
  const double c = std::clamp(double(-d.dot(normal)) / (double(len) * double(n)), -1.0, 1.0);
  return std::acos(c) * 180.0 / M_PI;
}

WorstProbe describe(const ProbeRecord& r, std::size_t index, float diagonal, WorstProbe::Kind kind,
                    const WorstProbeOptions& o) {
  WorstProbe w;
  w.kind = kind;
  w.index = index;
  w.segment = r.segment;
  w.exact_force_n = r.exact.force.norm();
  w.approx_force_n = r.approx.force.norm();
  w.force_difference_n = (r.approx.force - r.exact.force).norm();
  w.exact_depth_fraction = r.exact.contact ? double(r.exact.depth) / diagonal : 0.0;
  w.approx_depth_fraction = r.approx.contact ? double(r.approx.depth) / diagonal : 0.0;
  w.incidence_deg = incidence(r.segment, kind == WorstProbe::Kind::false_contact ? r.approx.normal : r.exact.normal);
  const bool grazing = w.incidence_deg > o.grazing_deg;
  const std::string angle = number(w.incidence_deg, 2) + " deg from the normal";
  switch (kind) {
  case WorstProbe::Kind::force_error: {
    w.relative_error = relative_force_error(r.exact, r.approx);
    const bool shallow = w.exact_depth_fraction < o.shallow_fraction;
    if (shallow || grazing)
      w.cause = std::string(shallow && grazing ? "near-grazing, shallow contact"
                            : shallow          ? "shallow contact"
                                               : "near-grazing contact") +
                " (" + angle + ", exact depth " + number(100.0 * w.exact_depth_fraction) +
                " % of the diagonal): the exact force is only " + number(w.exact_force_n) + " N, so a " +
                number(w.force_difference_n) + " N difference is a large fraction";
    else
      w.cause = "the box's surface differs here (" + angle + ", depth " + number(100.0 * w.approx_depth_fraction) +
                " % against exact " + number(100.0 * w.exact_depth_fraction) + " % of the diagonal)";
    break;
  }
  case WorstProbe::Kind::false_contact:
    w.cause = "the box reports a contact " + number(100.0 * w.approx_depth_fraction) +
              " % of the diagonal deep where the exact surface has none" + (grazing ? " (near-grazing, " + angle + ")" : "");
    break;
  case WorstProbe::Kind::missed_contact:
    w.cause = "the box misses a contact " + number(100.0 * w.exact_depth_fraction) + " % of the diagonal deep" +
              (grazing ? " (near-grazing, " + angle + ")" : " (" + angle + ")");
    break;
  }
  return w;
}

} // namespace

std::vector<WorstProbe> worst_probes(const std::vector<ProbeRecord>& records, float diagonal,
                                     const WorstProbeOptions& options) {
  std::vector<WorstProbe> out;
  if (!(diagonal > 0.f)) return out;
  std::vector<std::pair<double, std::size_t>> errors, disagreements;
  for (std::size_t i = 0; i < records.size(); ++i) {
    const ProbeRecord& r = records[i];
    if (r.exact.contact && r.approx.contact) errors.emplace_back(relative_force_error(r.exact, r.approx), i);
    else if (r.exact.contact != r.approx.contact)
      disagreements.emplace_back(double(r.exact.contact ? r.exact.depth : r.approx.depth), i);
  }
  auto top = [](std::vector<std::pair<double, std::size_t>>& v, std::size_t k) {
    k = std::min(k, v.size());
    std::partial_sort(v.begin(), v.begin() + std::ptrdiff_t(k), v.end(),
                      [](const auto& a, const auto& b) { return a.first > b.first || (a.first == b.first && a.second < b.second); });
    v.resize(k);
  };
  top(errors, options.force_errors);
  top(disagreements, options.disagreements);
  for (const auto& [e, i] : errors) out.push_back(describe(records[i], i, diagonal, WorstProbe::Kind::force_error, options));
  for (const auto& [d, i] : disagreements)
    out.push_back(describe(records[i], i, diagonal,
                           records[i].exact.contact ? WorstProbe::Kind::missed_contact : WorstProbe::Kind::false_contact,
                           options));
  return out;
}

const char* to_string(WorstProbe::Kind kind) noexcept {
  switch (kind) {
  case WorstProbe::Kind::force_error: return "force error";
  case WorstProbe::Kind::false_contact: return "false contact";
  case WorstProbe::Kind::missed_contact: return "missed contact";
  }
  return "?";
}

} // namespace hb
