#pragma once
// Timing queries on one core, for `bench`, `sweep` and reports. Timing is measured here and
// reported, never asserted in tests.
#include "contact/contact.h"
#include <vector>

namespace hb {

/// Median nanoseconds per query of `query` over `probes` on the calling thread: the probes
/// are run in batches of `batch` queries, `rounds` times over, and the median of the
/// per-batch averages is returned (robust to a noisy shared machine).
double median_query_ns(const ContactQuery& query, const std::vector<Segment>& probes,
                       const ForceLaw& law, int rounds = 5, std::size_t batch = 1000);

/// As median_query_ns, but each batch is answered by one query_many() call (for a haptic
/// box: the fetches of a group of queries overlap).
double median_query_many_ns(const ContactQuery& query, const std::vector<Segment>& probes,
                            const ForceLaw& law, int rounds = 5, std::size_t batch = 1000);

/// Two answerers timed against each other on the calling thread, as fairly as a shared
/// machine allows: their batches alternate (a, b, a, b, ...), so a burst of load falls on
/// both, and each side's median per-batch average is returned. One query at a time
/// (`many` false) or query_many() per batch.
struct PairedTiming {
  double a_ns = 0.0, b_ns = 0.0;
  /// a's time over b's (above 1: a is slower).
  double ratio() const noexcept { return b_ns > 0.0 ? a_ns / b_ns : 0.0; }
};
PairedTiming paired_query_ns(const ContactQuery& a, const ContactQuery& b, const std::vector<Segment>& probes,
                             const ForceLaw& law, bool many = false, int rounds = 5, std::size_t batch = 1000);

/// Latency of single queries: every query of every round timed on its own (a steady-clock
/// read on each side, the clock's own median cost subtracted), then quantiles over all of
/// them. What a 1 kHz loop must budget for is the tail, not the median.
struct QueryLatency {
  double p50_ns = 0.0, p99_ns = 0.0, p999_ns = 0.0, max_ns = 0.0;
  /// The same quantiles over each probe's median time across the rounds: the tail the probes
  /// themselves cause (long walks, crowded cells, a deep BVH descent), with the machine's
  /// one-off stalls (an interrupt, a neighbour's burst on a shared VM) filtered out, since
  /// they seldom hit one probe in most rounds. With one or two rounds, each probe's lower time.
  /// Pooled minus per-probe is what the machine added.
  double probe_p50_ns = 0.0, probe_p99_ns = 0.0, probe_p999_ns = 0.0, probe_max_ns = 0.0;
  double clock_ns = 0.0;        ///< median cost of one clock read pair (subtracted above).
  std::size_t queries = 0;      ///< timed queries (probes x rounds).
};
QueryLatency single_query_latency(const ContactQuery& query, const std::vector<Segment>& probes,
                                  const ForceLaw& law, int rounds = 5);

} // namespace hb
