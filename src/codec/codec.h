#pragma once
// Table codecs: identifiers, options and error statistics shared by the Haar codec (the
// paper's, sections 4.4 and 6.1.3) and the block codec (ours). See sample_table.h for the
// entry point that compresses a baked table and measures what it achieved (compress_table).
#include <cstdint>
#include <string>

namespace hb {

/// How a box's sample table is stored. The numeric values are written into .hbox files.
enum class CodecId : std::uint32_t {
  none = 0,   ///< raw 8-byte Sample records (float t, 32-bit octahedral normal).
  haar = 1,   ///< the paper's codec: per n x n sub-block face, a 2D Haar transform of t and of
              ///< the octahedral normal coordinates, quantised and thresholded; exact hit mask.
  block = 2,  ///< ours: 8 x 8 blocks with an exact hit mask, plane-predicted lattice residuals
              ///< of t and of the octahedral normal at a fixed bit width per block.
};

/// "none", "haar", "block".
const char* codec_name(CodecId id) noexcept;
/// Parses a codec name; throws hb::InvalidInput naming the accepted values.
CodecId parse_codec(const std::string& name);

/// Options of compress_table.
struct CodecOptions {
  CodecId codec = CodecId::block;
  /// Bound on |t1 - t0| / box diagonal for every hit sample, in [1e-5, 0.1]. Used unless
  /// `ratio` > 0. Default 0.0005 (0.05% of the diagonal).
  float max_error = 0.0005f;
  /// When > 0: find the smallest error bound in [1e-5, 0.1] whose ratio reaches this (>= 1);
  /// the bound found is reported in CodecStats::max_error_bound. If even the loosest bound
  /// (0.1) misses the ratio, that bound is used and the achieved ratio reported.
  float ratio = 0.f;
  /// Octahedral normal precision in bits per coordinate, in [6, 14]. Every hit's normal
  /// coordinates are within half a step of 2 / (2^normal_bits - 1) of the baked ones.
  /// Default 9 (an 18-bit normal: 0.16 degree mean, 0.5 degree worst case): measured on the
  /// bumpy sphere it costs no force accuracy against 10 bits (the query's own normal error is
  /// about 1 degree) and saves 10% of the size; 8 bits starts to show in the force error.
  int normal_bits = 9;
};

/// What a compression achieved, measured against the uncompressed table over hit samples.
/// Stored in box files so that `hapticbox info` can show it without the raw table.
struct CodecStats {
  std::uint64_t raw_bytes = 0;         ///< 8 bytes a sample.
  std::uint64_t bytes = 0;             ///< compressed payload, index and headers included.
  float max_error_bound = 0.f;         ///< the bound that was honoured (relative to diagonal).
  float t_error_mean = 0.f;            ///< mean |t1 - t0| / box diagonal over hit samples.
  float t_error_max = 0.f;             ///< max of the same.
  float normal_error_mean_deg = 0.f;   ///< mean angle between decoded and baked normals.
  float normal_error_max_deg = 0.f;
  std::uint64_t hit_miss_flips = 0;    ///< samples whose hit/miss changed (always 0).
  double ratio() const { return bytes ? double(raw_bytes) / double(bytes) : 0.0; }
};

/// One decoded sample: t (negative: a miss) and the octahedral normal coordinates in
/// [-1, 1] (decode with oct_decode_unnormalized).
struct DecodedSample {
  float t;
  float u, v;
};

} // namespace hb
