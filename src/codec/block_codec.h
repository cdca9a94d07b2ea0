#pragma once
// The block codec (ours). Why not a transform: t jumps between hit and miss at silhouettes
// and a transform smears those jumps over a whole tile; here the hit mask is exact and only
// hits are quantised, in the spirit of BC4/BC5 texture blocks.
//  - Each n x n sub-block face of each position point (a tile) is cut into 8 x 8 blocks
//    (the last row/column of blocks is partial when n is not a multiple of 8).
//  - A block stores a mode (all miss, all hit, mixed + a 64-bit hit mask), and per channel
//    (t, octahedral u, v) an integer plane predictor on a lattice (base + quarter-step
//    gradients) and one residual of fixed width per hit sample.
//  - Values sit on a lattice of step t_step (2 x the error bound) and n_step, so the error of
//    every hit is at most half a step: the bound holds by construction.
//  - Random access: index[block] -> record; rank of the sample among hits by popcount; one
//    unaligned 64-bit read. No table, tile or block decode.
#include "codec/bit_io.h"
#include "codec/table_payload.h"
#include <algorithm>
#include <cmath>

namespace hb {

/// Encodes a raw table (params.sample_count() samples) into a block-codec payload.
/// `t_step` in model units, `n_step` in octahedral units. Throws hb::InvalidInput when the
/// result does not fit 4 GiB.
std::vector<std::uint8_t> encode_block_table(const Sample* raw, const BoxParams& params, float t_step,
                                             float n_step);

/// Read-only view of a block-codec payload (owned elsewhere). Copyable, cheap.
class BlockTable {
public:
  static constexpr int kBlock = 8;
  static constexpr std::size_t kHeaderBytes = 20;

  BlockTable() = default;
  /// Validates the payload's header (O(1)); throws hb::InvalidInput.
  BlockTable(const std::uint8_t* payload, std::size_t bytes, const BoxParams& params);

  /// Starts loading the record holding sample (a, b) of `tile`.
  void prefetch(std::size_t tile, int a, int b) const noexcept {
    const std::uint32_t* e = index_ + block_of(tile, a, b);
    __builtin_prefetch(e);
  }

  /// Random access to sample (a, b) of `tile` (= position * 12 + sub * 3 + sface). Returns
  /// false for a miss. A corrupt record reads as a miss, never out of bounds.
  bool fetch(std::size_t tile, int a, int b, float& t, float& u, float& v) const noexcept {
    return fetch_from(record(block_of(tile, a, b)), a, b, t, u, v);
  }

  /// The block holding sample (a, b) of `tile`.
  std::size_t block_of(std::size_t tile, int a, int b) const noexcept {
    return (tile * std::size_t(nb_) + std::size_t(a >> 3)) * std::size_t(nb_) + std::size_t(b >> 3);
  }
  /// A block's record (a corrupt offset gives the shared all-miss record).
  const std::uint8_t* record(std::size_t block) const noexcept {
    std::uint32_t offset;
    std::memcpy(&offset, index_ + block, 4);
    return data_ + (offset < data_bytes_ ? offset : 0u);
  }
  /// fetch() from a record found with record(block_of(tile, a, b)): lets a caller start
  /// the record's load early (two-phase prefetch).
  bool fetch_from(const std::uint8_t* rec, int a, int b, float& t, float& u, float& v) const noexcept {
    const unsigned mode = rec[0];
    if (mode == 0) return false;
    const int la = a & (kBlock - 1), lb = b & (kBlock - 1);
    const unsigned li = unsigned(la * kBlock + lb);
    unsigned rank;
    const std::uint8_t* bits = rec + kHeaderBytes;
    if (mode == 2) {
      const auto mask = get_pod<std::uint64_t>(rec + kHeaderBytes);
      if (!((mask >> li) & 1u)) return false;
      rank = unsigned(popcount64(mask & ((std::uint64_t(1) << li) - 1u)));
      bits += 8;
    } else {
      const int bw = std::min(kBlock, n_ - (b & ~(kBlock - 1)));
      rank = unsigned(la * bw + lb);
    }
    const unsigned kt = rec[1] & 31u, ku = rec[2] & 15u, kv = rec[2] >> 4;
    const unsigned width = kt + ku + kv;
    const std::uint64_t word = read_bits(bits, std::uint64_t(rank) * width, width);
    const auto rt = std::int32_t(word & ((std::uint64_t(1) << kt) - 1u));
    const auto ru = std::int32_t((word >> kt) & ((std::uint64_t(1) << ku) - 1u));
    const auto rv = std::int32_t((word >> (kt + ku)) & ((std::uint64_t(1) << kv) - 1u));
    const auto t_base = get_pod<std::int32_t>(rec + 4);
    const auto t_ga = get_pod<std::int16_t>(rec + 8), t_gb = get_pod<std::int16_t>(rec + 10);
    const auto u_base = get_pod<std::int16_t>(rec + 12), v_base = get_pod<std::int16_t>(rec + 14);
    const auto u_ga = std::int8_t(rec[16]), u_gb = std::int8_t(rec[17]);
    const auto v_ga = std::int8_t(rec[18]), v_gb = std::int8_t(rec[19]);
    t = float(t_base + predict(t_ga, t_gb, la, lb) + rt) * t_step_;
    // std::min / max, not fmin / fmax (library calls on x86-64): the same for these values,
    // which are never NaN or -0 (an integer times a positive step).
    u = std::min(1.f, std::max(-1.f, float(u_base + predict(u_ga, u_gb, la, lb) + ru) * n_step_));
    v = std::min(1.f, std::max(-1.f, float(v_base + predict(v_ga, v_gb, la, lb) + rv) * n_step_));
    return t >= 0.f;
  }

  DecodedSample decode(std::size_t tile, int a, int b) const noexcept {
    DecodedSample s{kMissT, 0.f, 0.f};
    if (!fetch(tile, a, b, s.t, s.u, s.v)) s = {kMissT, 0.f, 0.f};
    return s;
  }

  /// Sequential decode of a whole tile (n x n, row a major), for tests and statistics:
  /// walks each block's record once instead of random access.
  void decode_tile(std::size_t tile, DecodedSample* out) const noexcept;

  /// The integer plane predictor: floor((ga * la + gb * lb) / 4) (an arithmetic shift:
  /// GCC and Clang define >> on negative values so, and C++20 requires it).
  static std::int32_t predict(std::int32_t ga, std::int32_t gb, int la, int lb) noexcept {
    return (ga * la + gb * lb) >> 2;
  }

private:
  const std::uint32_t* index_ = nullptr;
  const std::uint8_t* data_ = nullptr;
  std::size_t data_bytes_ = 0;
  float t_step_ = 1.f, n_step_ = 1.f;
  int n_ = 2, nb_ = 1;
};

} // namespace hb
