#pragma once
// Comparing an approximated answer with the exact one over a set of probes (paper 6.1.2).
#include "contact/contact.h"
#include "perception/perceptible.h"
#include "mesh/triangle_mesh.h"
#include "parallel/communicator.h"
#include <cstdint>
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

  /// The headline figure: probes whose difference a hand would feel (hb::perceive at the
  /// judge's thresholds, forces as the workspace's law computed them), and by which test
  /// (a probe may pass several).
  std::size_t perceptible = 0;
  double perceptible_share = 0.0;       ///< perceptible / samples.
  std::size_t perceptible_magnitude = 0, perceptible_direction = 0, perceptible_contact = 0;
  /// | |F_approx| - |F_exact| | in N over the probes where either answer has contact
  /// (median, p95, max), and exact's median force there: the scale the thresholds apply to.
  double force_difference_median_n = 0.0, force_difference_p95_n = 0.0, force_difference_max_n = 0.0;
  double exact_force_median_n = 0.0;
  std::vector<double> force_differences_n;  ///< per probe with a contact on either side, in probe order.
  PerceptualThresholds thresholds;      ///< what the probes were judged against.
  double max_force_n = 0.0;             ///< forces clamped to this (the device's), 0 for none.
};

/// How differences are judged: the thresholds and the device's force limit (forces are felt
/// clamped to it).
struct PerceptualJudge {
  PerceptualThresholds thresholds;
  double max_force_n = 8.0;
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
                                Communicator* communicator = nullptr, std::vector<RankWork>* work = nullptr,
                                const PerceptualJudge& judge = PerceptualJudge{});

/// eval's second figure: compare_queries on `count` light touches at any angle
/// (sample_probes with light_touch_probe_options(seed)), no records. `eval` and the report
/// both ask it.
ComparisonStats compare_light_touches(const ContactQuery& approx, const ContactQuery& exact, const TriangleMesh& mesh,
                                      std::size_t count, std::uint64_t seed, const ForceLaw& law, float diagonal,
                                      Communicator* communicator = nullptr,
                                      const PerceptualJudge& judge = PerceptualJudge{});

/// Statistics of given records (the same figures as compare_queries).
ComparisonStats summarize(const std::vector<ProbeRecord>& records, float diagonal,
                          const PerceptualJudge& judge = PerceptualJudge{});

/// q-quantile (q in [0, 1]) by linear interpolation; 0 for an empty input.
double quantile(std::vector<double> values, double q);

} // namespace hb
