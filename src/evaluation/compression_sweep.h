#pragma once
// The compression curve (paper Figure 11): for each codec and error bound, the compression
// ratio against the errors it causes, for `hapticbox compress-sweep`, reports and charts.
#include "codec/codec.h"
#include "evaluation/comparison.h"
#include "scene/box_scene.h"
#include "progress.h"
#include <vector>

namespace hb {

/// Options of compression_sweep.
struct CompressionSweepOptions {
  std::vector<CodecId> codecs{CodecId::haar, CodecId::block};
  /// Error bounds relative to the box diagonal, each in [1e-5, 0.1].
  std::vector<float> max_errors{1e-4f, 2e-4f, 5e-4f, 1e-3f, 2e-3f, 5e-3f, 1e-2f, 2e-2f};
  int normal_bits = 9;  ///< as CodecOptions::normal_bits.
  /// Probes for the query-level errors (may be empty: those columns stay zero). Answers of
  /// the compressed scene are compared with those of the uncompressed scene (the
  /// compression's own error) and, when `exact` is given, with the exact answer.
  std::vector<Segment> probes;
  const ContactQuery* exact = nullptr;
  ForceLaw law;                 ///< the workspace's (hb::Workspace::law).
  PerceptualJudge judge;        ///< what a hand tells apart (the perceptible shares below).
  ProgressCallback progress;  ///< fraction of the points done.
};

/// One point of the curve (all boxes of the scene together).
struct CompressionSweepPoint {
  CodecId codec = CodecId::none;
  float max_error = 0.f;                  ///< the bound requested (0 for none).
  double ratio = 1.0;                     ///< raw bytes / compressed bytes.
  std::uint64_t bytes = 0;
  double t_error_mean = 0, t_error_max = 0;             ///< relative to the box diagonal.
  double normal_error_mean_deg = 0, normal_error_max_deg = 0;
  double force_error_vs_raw_median = 0, force_error_vs_raw_p95 = 0;  ///< |F1 - Fraw| / |Fraw|.
  double contact_agreement_vs_raw = 1;
  double contact_agreement = 0, force_error_median = 0; ///< against `exact`, when given.
  /// Share of probes perceptibly different (hb::perceive) from the raw box, and from `exact`
  /// when given: the paper's Figure 11 in what a hand feels.
  double perceptible_vs_raw = 0, perceptible_vs_exact = 0;
};

/// Runs the sweep on a scene with raw tables (the first point of each curve is the raw
/// scene itself, codec none). Throws hb::InvalidInput when a box is already compressed.
std::vector<CompressionSweepPoint> compression_sweep(const BoxScene& raw, const CompressionSweepOptions& options);

} // namespace hb
