#pragma once
// Comparing an approximated answer with the exact one over a set of probes (paper 6.1.2).
#include "contact/contact.h"
#include "parallel/communicator.h"
#include <vector>

namespace hb {

/// Both answers for one probe.
struct ProbeRecord {
  Segment segment;
  Contact exact;
  Contact approx;
};

/// Error statistics. Force and angle errors are over the probes where both answers are in
/// contact; contact agreement over all probes.
struct ComparisonStats {
  std::size_t samples = 0;
  std::size_t exact_contacts = 0;
  std::size_t both_contacts = 0;
  double contact_agreement = 0.0;   ///< fraction of probes where contact flags agree.
  std::size_t false_contacts = 0;   ///< approx contact where exact has none.
  std::size_t missed_contacts = 0;  ///< exact contact the approximation missed.
  double force_error_median = 0.0;  ///< relative |F1 - F0| / |F0|.
  double force_error_p95 = 0.0;
  double force_error_max = 0.0;
  double angle_error_median_deg = 0.0;  ///< angle between the force directions.
  double angle_error_p99_deg = 0.0;
  double depth_rms_over_diag = 0.0;     ///< RMS of depth differences over the diagonal.
  std::vector<double> force_errors;     ///< per both-contact probe, in probe order.
};

/// Relative force error |F1 - F0| / |F0| (0 when both forces are zero).
double relative_force_error(const Contact& exact, const Contact& approx) noexcept;

/// Angle in degrees between the two normals.
double angle_error_degrees(const Contact& exact, const Contact& approx) noexcept;

/// Runs both queries on every probe (in parallel) and fills `records` when given.
/// With a `communicator` of several ranks (every rank calls this with the same probes and
/// queries answering alike), the probes are dealt to the ranks in chunks (hb::DealtChunks),
/// both answers of each probe travel to rank 0 (41 bytes a probe, gathered once), which
/// assembles them in probe order and summarizes: the figures are those of one process. Every
/// rank returns the statistics; `records` is filled on rank 0 only (left empty elsewhere).
/// `work`, when given, receives on rank 0 what each rank did (probes, seconds, bytes sent).
ComparisonStats compare_queries(const ContactQuery& approx, const ContactQuery& exact,
                                const std::vector<Segment>& probes, const ForceLaw& law,
                                float diagonal, std::vector<ProbeRecord>* records = nullptr,
                                Communicator* communicator = nullptr, std::vector<RankWork>* work = nullptr);

/// Statistics of given records (the same figures as compare_queries).
ComparisonStats summarize(const std::vector<ProbeRecord>& records, float diagonal);

/// q-quantile (q in [0, 1]) by linear interpolation; 0 for an empty input.
double quantile(std::vector<double> values, double q);

} // namespace hb
