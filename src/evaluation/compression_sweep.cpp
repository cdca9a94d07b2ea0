// Compression sweep.
//  1. The raw scene is point 0 (codec none): ratio 1, no table error; its query answers are
//     the reference for "vs raw" and, with an exact query, its errors are the floor.
//  2. For every codec and bound: compress every box (compress_table measures the table
//     errors), build the scene, and compare its answers on the probes.
#include "evaluation/compression_sweep.h"
#include "errors.h"
#include "evaluation/comparison.h"

namespace hb {
namespace {

void add_query_errors(CompressionSweepPoint& p, const BoxScene& scene, const BoxScene& raw,
                      const CompressionSweepOptions& o) {
  if (o.probes.empty()) return;
  const float diag = raw.parts().source.diagonal > 0.f ? raw.parts().source.diagonal : 1.f;
  const ComparisonStats vs_raw = compare_queries(scene, raw, o.probes, o.law, diag, nullptr, nullptr, nullptr, o.judge);
  p.contact_agreement_vs_raw = vs_raw.contact_agreement;
  p.force_error_vs_raw_median = vs_raw.force_error_median;
  p.force_error_vs_raw_p95 = vs_raw.force_error_p95;
  p.perceptible_vs_raw = vs_raw.perceptible_share;
  if (o.exact) {
    const ComparisonStats vs_exact = compare_queries(scene, *o.exact, o.probes, o.law, diag, nullptr, nullptr, nullptr, o.judge);
    p.contact_agreement = vs_exact.contact_agreement;
    p.force_error_median = vs_exact.force_error_median;
    p.perceptible_vs_exact = vs_exact.perceptible_share;
  }
}

} // namespace

std::vector<CompressionSweepPoint> compression_sweep(const BoxScene& raw, const CompressionSweepOptions& o) {
  if (!has_tables(raw.parts()))
    throw InvalidInput("compression sweep: the scene's boxes are frames without tables (answered by exact Embree)");
  for (const HapticBox& box : raw.parts().boxes)
    if (box.codec() != CodecId::none)
      throw InvalidInput(std::string("compression sweep: needs uncompressed tables, the scene holds a '") +
                         codec_name(box.codec()) + "' table");
  std::vector<CompressionSweepPoint> points;
  const std::size_t total = 1 + o.codecs.size() * o.max_errors.size();
  auto report = [&] {
    if (o.progress && !o.progress(double(points.size()) / double(total))) throw Cancelled("compression sweep cancelled");
  };
  CompressionSweepPoint base;
  for (const HapticBox& box : raw.parts().boxes) base.bytes += box.table_bytes();
  add_query_errors(base, raw, raw, o);
  points.push_back(base);
  report();
  for (CodecId codec : o.codecs) {
    if (codec == CodecId::none) continue;
    for (float bound : o.max_errors) {
      CodecOptions co;
      co.codec = codec;
      co.max_error = bound;
      co.normal_bits = o.normal_bits;
      std::vector<HapticBox> boxes;
      CompressionSweepPoint p;
      p.codec = codec;
      p.max_error = bound;
      std::uint64_t raw_bytes = 0, hits_weight = 0;
      for (const HapticBox& box : raw.parts().boxes) {
        boxes.push_back(box.compressed(co));
        const CodecStats& s = boxes.back().codec_stats();
        raw_bytes += s.raw_bytes;
        p.bytes += s.bytes;
        // Weighted by table size: boxes of one scene share the densities.
        p.t_error_mean += s.t_error_mean * double(s.raw_bytes);
        p.normal_error_mean_deg += s.normal_error_mean_deg * double(s.raw_bytes);
        hits_weight += s.raw_bytes;
        p.t_error_max = std::max<double>(p.t_error_max, s.t_error_max);
        p.normal_error_max_deg = std::max<double>(p.normal_error_max_deg, s.normal_error_max_deg);
      }
      p.t_error_mean /= double(hits_weight);
      p.normal_error_mean_deg /= double(hits_weight);
      p.ratio = double(raw_bytes) / double(p.bytes);
      const BoxScene scene(SceneParts{std::move(boxes), raw.parts().source});
      add_query_errors(p, scene, raw, o);
      points.push_back(p);
      report();
    }
  }
  return points;
}

} // namespace hb
