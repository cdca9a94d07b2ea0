#include "evaluation/comparison.h"
#include "evaluation/probe_sampling.h"
#include "parallel/byte_buffer.h"
#include "parallel/work_split.h"
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <algorithm>
#include <chrono>
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

ComparisonStats summarize(const std::vector<ProbeRecord>& records, float diagonal, const PerceptualJudge& judge) {
  ComparisonStats s;
  s.samples = records.size();
  s.thresholds = judge.thresholds;
  s.max_force_n = judge.max_force_n;
  std::vector<double> angles, exact_forces;
  double depth_sq = 0.0;
  std::size_t agree = 0;
  for (const ProbeRecord& r : records) {
    if (r.exact.contact || r.approx.contact) {
      const PerceivedDifference p = perceive(r.exact, r.approx, judge.thresholds, judge.max_force_n);
      s.force_differences_n.push_back(p.magnitude_difference_n);
      if (r.exact.contact) {
        const double f = double(r.exact.force.norm());
        exact_forces.push_back(judge.max_force_n > 0 ? std::min(f, judge.max_force_n) : f);
      }
      if (p.perceptible()) ++s.perceptible;
      if (p.by & kPerceivedMagnitude) ++s.perceptible_magnitude;
      if (p.by & kPerceivedDirection) ++s.perceptible_direction;
      if (p.by & kPerceivedContact) ++s.perceptible_contact;
    }
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
  s.perceptible_share = s.samples ? double(s.perceptible) / double(s.samples) : 0.0;
  s.force_difference_median_n = quantile(s.force_differences_n, 0.5);
  s.force_difference_p95_n = quantile(s.force_differences_n, 0.95);
  s.force_difference_max_n =
      s.force_differences_n.empty() ? 0.0 : *std::max_element(s.force_differences_n.begin(), s.force_differences_n.end());
  s.exact_force_median_n = quantile(exact_forces, 0.5);
  s.force_error_median = quantile(s.force_errors, 0.5);
  s.force_error_p95 = quantile(s.force_errors, 0.95);
  s.force_error_max = s.force_errors.empty() ? 0.0 : *std::max_element(s.force_errors.begin(), s.force_errors.end());
  s.angle_error_median_deg = quantile(angles, 0.5);
  s.angle_error_p99_deg = quantile(angles, 0.99);
  s.depth_rms_over_diag =
      (s.both_contacts && diagonal > 0.f) ? std::sqrt(depth_sq / double(s.both_contacts)) / double(diagonal) : 0.0;
  return s;
}

namespace {

// Answers probes [first, last) into local[first, last): the approximation through query_many
// in runs (the same answers as query(), with the table fetches of a group of probes
// overlapped), the exact reference one by one.
void answer_range(const ContactQuery& approx, const ContactQuery& exact, const std::vector<Segment>& probes,
                  const ForceLaw& law, std::size_t first_probe, std::size_t last_probe, std::vector<ProbeRecord>& local) {
  tbb::parallel_for(tbb::blocked_range<std::size_t>(first_probe, last_probe, 256),
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
}

void put_contact(ByteWriter& w, const Contact& c) {
  w.put(std::uint8_t(c.contact));
  w.put(c.depth);
  w.put(c.point);
  w.put(c.normal);
  w.put(c.force);
}
Contact get_contact(ByteReader& r) {
  Contact c;
  c.contact = r.get<std::uint8_t>() != 0;
  c.depth = r.get<float>();
  c.point = r.get<Vec3>();
  c.normal = r.get<Vec3>();
  c.force = r.get<Vec3>();
  return c;
}

Bytes pack_stats(const ComparisonStats& s) {
  ByteWriter w;
  w.put(std::uint64_t(s.samples));
  w.put(std::uint64_t(s.exact_contacts));
  w.put(std::uint64_t(s.both_contacts));
  w.put(s.contact_agreement);
  w.put(std::uint64_t(s.false_contacts));
  w.put(std::uint64_t(s.missed_contacts));
  w.put(s.force_error_median);
  w.put(s.force_error_p95);
  w.put(s.force_error_max);
  w.put(s.angle_error_median_deg);
  w.put(s.angle_error_p99_deg);
  w.put(s.depth_rms_over_diag);
  w.put_vector(s.force_errors);
  for (std::size_t v : {s.perceptible, s.perceptible_magnitude, s.perceptible_direction, s.perceptible_contact})
    w.put(std::uint64_t(v));
  for (double v : {s.perceptible_share, s.force_difference_median_n, s.force_difference_p95_n, s.force_difference_max_n,
                   s.exact_force_median_n, s.thresholds.weber, s.thresholds.floor_n, s.thresholds.angle_deg,
                   s.thresholds.angle_min_force_n, s.max_force_n})
    w.put(v);
  w.put_vector(s.force_differences_n);
  return std::move(w.bytes());
}
ComparisonStats unpack_stats(const Bytes& b) {
  ByteReader r(b, "compare_queries");
  ComparisonStats s;
  s.samples = r.get<std::uint64_t>();
  s.exact_contacts = r.get<std::uint64_t>();
  s.both_contacts = r.get<std::uint64_t>();
  s.contact_agreement = r.get<double>();
  s.false_contacts = r.get<std::uint64_t>();
  s.missed_contacts = r.get<std::uint64_t>();
  s.force_error_median = r.get<double>();
  s.force_error_p95 = r.get<double>();
  s.force_error_max = r.get<double>();
  s.angle_error_median_deg = r.get<double>();
  s.angle_error_p99_deg = r.get<double>();
  s.depth_rms_over_diag = r.get<double>();
  s.force_errors = r.get_vector<double>();
  for (std::size_t* v : {&s.perceptible, &s.perceptible_magnitude, &s.perceptible_direction, &s.perceptible_contact})
    *v = std::size_t(r.get<std::uint64_t>());
  for (double* v : {&s.perceptible_share, &s.force_difference_median_n, &s.force_difference_p95_n,
                    &s.force_difference_max_n, &s.exact_force_median_n, &s.thresholds.weber, &s.thresholds.floor_n,
                    &s.thresholds.angle_deg, &s.thresholds.angle_min_force_n, &s.max_force_n})
    *v = r.get<double>();
  s.force_differences_n = r.get_vector<double>();
  return s;
}

} // namespace

ComparisonStats compare_queries(const ContactQuery& approx, const ContactQuery& exact,
                                const std::vector<Segment>& probes, const ForceLaw& law,
                                float diagonal, std::vector<ProbeRecord>* records,
                                Communicator* communicator, std::vector<RankWork>* work,
                                const PerceptualJudge& judge) {
  Communicator& comm = communicator_or_serial(communicator);
  const auto start = std::chrono::steady_clock::now();
  std::vector<ProbeRecord> local(probes.size());
  if (comm.size() == 1) {
    answer_range(approx, exact, probes, law, 0, probes.size(), local);
    ComparisonStats s = summarize(local, diagonal, judge);
    if (records) *records = std::move(local);
    if (work)
      *work = {{0, probes.size(), std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count(), 0}};
    return s;
  }
  // 1. This rank's chunks of probes, answered on all its cores.
  const DealtChunks deal{probes.size(), deal_chunk_size(probes.size(), comm.size(), 64, 64), comm.size()};
  ByteWriter w;
  w.reserve(deal.items_of(comm.rank()) * 2 * (1 + 4 + 36) + 64);
  deal.for_each_of(comm.rank(), [&](std::size_t first, std::size_t last) {
    answer_range(approx, exact, probes, law, first, last, local);
    for (std::size_t i = first; i < last; ++i) {
      put_contact(w, local[i].exact);
      put_contact(w, local[i].approx);
    }
  });
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  const std::uint64_t bytes = comm.rank() == 0 ? 0 : w.bytes().size();
  // 2. Rank 0 places every rank's answers at their probes, in probe order.
  const std::vector<Bytes> parts = comm.gather(w.bytes());
  ByteWriter mine;
  mine.put(RankWork{comm.rank(), deal.items_of(comm.rank()), seconds, bytes});
  const std::vector<Bytes> works = comm.gather(mine.bytes());
  Bytes summary;
  if (comm.is_root()) {
    for (int r = 1; r < comm.size(); ++r) {
      ByteReader reader(parts[std::size_t(r)], "compare_queries: rank " + std::to_string(r));
      deal.for_each_of(r, [&](std::size_t first, std::size_t last) {
        for (std::size_t i = first; i < last; ++i) {
          local[i].segment = probes[i];
          local[i].exact = get_contact(reader);
          local[i].approx = get_contact(reader);
        }
      });
    }
    if (work) {
      work->clear();
      for (const Bytes& b : works) {
        ByteReader reader(b, "compare_queries");
        work->push_back(reader.get<RankWork>());
      }
    }
    ComparisonStats s = summarize(local, diagonal, judge);
    summary = pack_stats(s);
  }
  // 3. The statistics on every rank.
  comm.broadcast(summary);
  if (records) {
    if (comm.is_root()) *records = std::move(local);
    else records->clear();
  }
  return unpack_stats(summary);
}

ComparisonStats compare_light_touches(const ContactQuery& approx, const ContactQuery& exact, const TriangleMesh& mesh,
                                      std::size_t count, std::uint64_t seed, const ForceLaw& law, float diagonal,
                                      Communicator* communicator, const PerceptualJudge& judge) {
  return compare_queries(approx, exact, sample_probes(mesh, count, light_touch_probe_options(seed)), law, diagonal,
                         nullptr, communicator, nullptr, judge);
}

} // namespace hb
