#pragma once
// A box's sample table in any codec: the raw records or a view of a compressed payload.
// The query dispatches on codec() once and then works on the concrete view (no virtual call
// per sample); decode()/decode_tile() dispatch per call and serve tests and statistics.
#include "codec/block_codec.h"
#include "codec/haar_codec.h"

namespace hb {

class SampleTable {
public:
  SampleTable() = default;
  /// Raw table of params.sample_count() records (owned elsewhere).
  SampleTable(const Sample* raw, const BoxParams& params) : params_(params), raw_(raw) {}
  /// Compressed payload (owned elsewhere): validates its header, O(1); throws hb::InvalidInput.
  SampleTable(CodecId codec, const std::uint8_t* payload, std::size_t bytes, const BoxParams& params);

  CodecId codec() const noexcept { return codec_; }
  const Sample* raw() const noexcept { return raw_; }
  const BlockTable& block() const noexcept { return block_; }
  const HaarTable& haar() const noexcept { return haar_; }
  /// Bytes of the stored form (the raw records or the whole payload).
  std::size_t bytes() const noexcept;
  const void* data() const noexcept { return raw_ ? static_cast<const void*>(raw_) : payload_; }

  /// Random access to sample (a, b) of tile (position * 12 + sub * 3 + sface).
  DecodedSample decode(std::size_t tile, int a, int b) const noexcept;
  /// Whole tile, n x n, row a major (sequential decoders; Haar allocates, may throw
  /// std::bad_alloc).
  void decode_tile(std::size_t tile, DecodedSample* out) const;

private:
  CodecId codec_ = CodecId::none;
  BoxParams params_;
  const Sample* raw_ = nullptr;
  const std::uint8_t* payload_ = nullptr;
  std::size_t payload_bytes_ = 0;
  BlockTable block_;
  HaarTable haar_;
};

/// A compressed table that owns its payload, with what the compression achieved.
struct CompressedTable {
  CodecId codec = CodecId::none;
  std::vector<std::uint8_t> payload;
  CodecStats stats;
};

/// Compresses a raw table (params.sample_count() records) with options.codec, honouring
/// options.max_error relative to `diagonal` (or searching the bound for options.ratio), and
/// measures the result (CodecStats). CodecId::none is rejected (nothing to compress).
/// Throws hb::InvalidInput for out-of-range options.
CompressedTable compress_table(const Sample* raw, const BoxParams& params, float diagonal, const CodecOptions& options);

/// Measures `table` against the raw one (over hits: t error / diagonal, normal angle;
/// hit/miss flips over all samples). Fills all of CodecStats except max_error_bound.
CodecStats measure_table(const Sample* raw, const SampleTable& table, const BoxParams& params, float diagonal);

} // namespace hb
