#include "evaluation/query_timing.h"
#include "evaluation/comparison.h"
#include <algorithm>
#include <chrono>

namespace hb {

double median_query_ns(const ContactQuery& query, const std::vector<Segment>& probes,
                       const ForceLaw& law, int rounds, std::size_t batch) {
  if (probes.empty() || batch == 0) return 0.0;
  std::vector<double> per_batch;
  volatile float sink = 0.f;  // keeps the optimiser from dropping the queries
  for (int r = 0; r < rounds; ++r) {
    for (std::size_t begin = 0; begin < probes.size(); begin += batch) {
      const std::size_t end = std::min(probes.size(), begin + batch);
      float acc = 0.f;
      const auto t0 = std::chrono::steady_clock::now();
      for (std::size_t i = begin; i < end; ++i) acc += query.query(probes[i], law).depth;
      const auto t1 = std::chrono::steady_clock::now();
      sink = sink + acc;
      per_batch.push_back(std::chrono::duration<double, std::nano>(t1 - t0).count() / double(end - begin));
    }
  }
  return quantile(per_batch, 0.5);
}

namespace {
// Nanoseconds per query of one batch.
double batch_ns(const ContactQuery& q, const Segment* probes, std::size_t count, const ForceLaw& law, bool many,
                std::vector<Contact>& out) {
  volatile float sink = 0.f;
  float acc = 0.f;
  const auto t0 = std::chrono::steady_clock::now();
  if (many) {
    q.query_many(probes, count, law, out.data());
    for (std::size_t i = 0; i < count; ++i) acc += out[i].depth;
  } else {
    for (std::size_t i = 0; i < count; ++i) acc += q.query(probes[i], law).depth;
  }
  const auto t1 = std::chrono::steady_clock::now();
  sink = sink + acc;
  return std::chrono::duration<double, std::nano>(t1 - t0).count() / double(count);
}
} // namespace

PairedTiming paired_query_ns(const ContactQuery& a, const ContactQuery& b, const std::vector<Segment>& probes,
                             const ForceLaw& law, bool many, int rounds, std::size_t batch) {
  PairedTiming t;
  if (probes.empty() || batch == 0) return t;
  std::vector<double> per_a, per_b;
  std::vector<Contact> out(std::min(batch, probes.size()));
  for (int r = 0; r < rounds; ++r)
    for (std::size_t begin = 0; begin < probes.size(); begin += batch) {
      const std::size_t count = std::min(probes.size(), begin + batch) - begin;
      // Alternate which goes first, so neither always runs on the other's warm cache.
      const bool a_first = ((begin / batch) + std::size_t(r)) % 2 == 0;
      if (a_first) per_a.push_back(batch_ns(a, probes.data() + begin, count, law, many, out));
      per_b.push_back(batch_ns(b, probes.data() + begin, count, law, many, out));
      if (!a_first) per_a.push_back(batch_ns(a, probes.data() + begin, count, law, many, out));
    }
  t.a_ns = quantile(per_a, 0.5);
  t.b_ns = quantile(per_b, 0.5);
  return t;
}

double median_query_many_ns(const ContactQuery& query, const std::vector<Segment>& probes,
                            const ForceLaw& law, int rounds, std::size_t batch) {
  if (probes.empty() || batch == 0) return 0.0;
  std::vector<double> per_batch;
  std::vector<Contact> out(std::min(batch, probes.size()));
  volatile float sink = 0.f;
  for (int r = 0; r < rounds; ++r) {
    for (std::size_t begin = 0; begin < probes.size(); begin += batch) {
      const std::size_t count = std::min(probes.size(), begin + batch) - begin;
      const auto t0 = std::chrono::steady_clock::now();
      query.query_many(probes.data() + begin, count, law, out.data());
      float acc = 0.f;
      for (std::size_t i = 0; i < count; ++i) acc += out[i].depth;
      const auto t1 = std::chrono::steady_clock::now();
      sink = sink + acc;
      per_batch.push_back(std::chrono::duration<double, std::nano>(t1 - t0).count() / double(count));
    }
  }
  return quantile(per_batch, 0.5);
}

QueryLatency single_query_latency(const ContactQuery& query, const std::vector<Segment>& probes,
                                  const ForceLaw& law, int rounds) {
  QueryLatency out;
  if (probes.empty() || rounds < 1) return out;
  using clock = std::chrono::steady_clock;
  std::vector<double> clock_pairs(1001);
  for (double& c : clock_pairs) {
    const auto t0 = clock::now();
    const auto t1 = clock::now();
    c = std::chrono::duration<double, std::nano>(t1 - t0).count();
  }
  out.clock_ns = quantile(clock_pairs, 0.5);
  std::vector<double> ns;
  ns.reserve(probes.size() * std::size_t(rounds));
  volatile float sink = 0.f;
  for (int r = 0; r < rounds; ++r)
    for (const Segment& s : probes) {
      const auto t0 = clock::now();
      const float depth = query.query(s, law).depth;
      const auto t1 = clock::now();
      sink = sink + depth;
      ns.push_back(std::max(0.0, std::chrono::duration<double, std::nano>(t1 - t0).count() - out.clock_ns));
    }
  out.queries = ns.size();
  out.p50_ns = quantile(ns, 0.5);
  out.p99_ns = quantile(ns, 0.99);
  out.p999_ns = quantile(ns, 0.999);
  out.max_ns = *std::max_element(ns.begin(), ns.end());
  // Each probe's median over the rounds (ns is round-major: round r's probe i at r P + i).
  const std::size_t count = probes.size();
  std::vector<double> per_probe(count), round_ns(static_cast<std::size_t>(rounds));
  for (std::size_t i = 0; i < count; ++i) {
    for (int r = 0; r < rounds; ++r) round_ns[std::size_t(r)] = ns[std::size_t(r) * count + i];
    const auto mid = round_ns.begin() + (rounds - 1) / 2;  // the lower median of an even count
    std::nth_element(round_ns.begin(), mid, round_ns.end());
    per_probe[i] = *mid;
  }
  out.probe_p50_ns = quantile(per_probe, 0.5);
  out.probe_p99_ns = quantile(per_probe, 0.99);
  out.probe_p999_ns = quantile(per_probe, 0.999);
  out.probe_max_ns = *std::max_element(per_probe.begin(), per_probe.end());
  return out;
}

} // namespace hb
