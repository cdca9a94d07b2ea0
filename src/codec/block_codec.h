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
#include "prefetch.h"
#include <algorithm>
#include <emmintrin.h>
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
  static constexpr std::uint8_t kAllMissRecord[1] = {0};

  BlockTable() = default;
  /// Validates the payload's header (O(1)); throws hb::InvalidInput.
  BlockTable(const std::uint8_t* payload, std::size_t bytes, const BoxParams& params);

  /// What tells this table from another (its index's address: a kept decode, DecodedQuads,
  /// is this table's only while the payload lives, as the scene that owns both).
  const void* identity() const noexcept { return index_; }

  /// Starts loading the record holding sample (a, b) of `tile`.
  void prefetch(std::size_t tile, int a, int b) const noexcept {
    const std::uint32_t* e = index_ + block_of(tile, a, b);
    hb::prefetch(e);
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
  /// A block's record. Offset 0 (the shared all-miss record) and a corrupt offset, one whose
  /// record header would not fit in the data, give a static all-miss record: every record
  /// handed out then has its header in the data, and the longest record a header can
  /// describe (20 + 8 + 488 bytes) ends inside the padding that follows the data.
  const std::uint8_t* record(std::size_t block) const noexcept {
    std::uint32_t offset;
    std::memcpy(&offset, index_ + block, 4);
    return has_record(offset) ? data_ + offset : kAllMissRecord;
  }
  bool has_record(std::uint32_t offset) const noexcept {
    return offset != 0 && std::size_t(offset) + kHeaderBytes <= data_bytes_;
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
    // 64-bit sums: a corrupt record must not overflow (UBSan, found by the sanitizer suite);
    // every sum a valid record makes is the same integer, so the same float.
    t = float(std::int64_t(t_base) + predict(t_ga, t_gb, la, lb) + rt) * t_step_;
    // std::min / max, not fmin / fmax (library calls on x86-64): the same for these values,
    // which are never NaN or -0 (an integer times a positive step).
    u = std::min(1.f, std::max(-1.f, float(std::int64_t(u_base) + predict(u_ga, u_gb, la, lb) + ru) * n_step_));
    v = std::min(1.f, std::max(-1.f, float(std::int64_t(v_base) + predict(v_ga, v_gb, la, lb) + rv) * n_step_));
    return t >= 0.f;
  }

  /// The records of the 2 x 2 quad at (a0, b0) of `tile`, in the query's order (a0, b0),
  /// (a0 + 1, b0), (a0 + 1, b0 + 1), (a0, b0 + 1): rec[k] = record(block_of(tile, a_k, b_k)).
  /// Precondition: 0 <= a0, b0 <= n - 2.
  void quad_records(std::size_t tile, int a0, int b0, const std::uint8_t* rec[4]) const noexcept {
    // a0 and a0 + 1 (b0 and b0 + 1) share a block unless a0 (b0) ends one.
    const std::size_t block = block_of(tile, a0, b0);
    const std::size_t da = (a0 & (kBlock - 1)) == kBlock - 1 ? std::size_t(nb_) : 0u;
    const std::size_t db = (b0 & (kBlock - 1)) == kBlock - 1 ? 1u : 0u;
    rec[0] = record(block);
    rec[1] = record(block + da);
    rec[2] = record(block + da + db);
    rec[3] = record(block + db);
  }

  /// The 2 x 2 quad at (a0, b0) from its records (quad_records(); found early by a caller that
  /// overlaps the loads of several quads): t[k], u[k], v[k] equal fetch_from()'s values bit for
  /// bit; a miss gets {kMissT, 0, 0}. Returns the hit mask (bit k: sample k is a hit). When the
  /// quad lies in one 8 x 8 block (49 quads in 64) the record's header is read once, the
  /// four ranks come from one prefix count plus one 8-bit count, and the plane predictors
  /// step by their gradients; a quad across blocks reads each block's header once.
  /// Precondition: 0 <= a0, b0 <= n - 2. Corrupt records read as misses or garbage values,
  /// never out of bounds.
  unsigned fetch_quad_from(const std::uint8_t* const rec[4], int a0, int b0, float* t, float* u,
                           float* v) const noexcept {
    __m128 tv, uv, vv;
    const __m128 hit = quad_lanes(rec, a0, b0, tv, uv, vv);
    _mm_storeu_ps(t, _mm_or_ps(_mm_and_ps(hit, tv), _mm_andnot_ps(hit, _mm_set1_ps(kMissT))));
    _mm_storeu_ps(u, _mm_and_ps(hit, uv));
    _mm_storeu_ps(v, _mm_and_ps(hit, vv));
    return unsigned(_mm_movemask_ps(hit));
  }
  /// fetch_quad_from() in SSE2 lanes (lane k: sample k): the hit mask (all ones for a hit),
  /// and t, u, v, whose lanes are meaningful for hits only (the caller masks them).
  __m128 quad_lanes(const std::uint8_t* const rec[4], int a0, int b0, __m128& tv, __m128& uv, __m128& vv) const noexcept {
    const int la = a0 & (kBlock - 1), lb = b0 & (kBlock - 1);
    if (__builtin_expect(la == kBlock - 1 || lb == kBlock - 1, 0)) {
      alignas(16) float t[4], u[4], v[4];
      const unsigned hits = fetch_quad_split(rec, a0, b0, t, u, v);
      tv = _mm_load_ps(t), uv = _mm_load_ps(u), vv = _mm_load_ps(v);
      const __m128i lane_bit = _mm_setr_epi32(1, 2, 4, 8);
      return _mm_castsi128_ps(_mm_cmpeq_epi32(_mm_and_si128(_mm_set1_epi32(int(hits)), lane_bit), lane_bit));
    }
    const std::uint8_t* r = rec[0];
    const unsigned mode = r[0];
    if (mode == 0) {
      tv = uv = vv = _mm_setzero_ps();
      return _mm_setzero_ps();
    }
    unsigned rank0, rank1, hits;
    const std::uint8_t* bits = r + kHeaderBytes;
    if (mode == 2) {
      const auto mask = get_pod<std::uint64_t>(bits);
      bits += 8;
      const unsigned li = unsigned(la * kBlock + lb);  // <= 54: the quad's bits are li, li + 1, li + 8, li + 9
      const auto row = unsigned(mask >> li) & 0x3ffu;
      rank0 = popcount64(mask & ((std::uint64_t(1) << li) - 1u));
      rank1 = rank0 + popcount8(row & 0xffu);
      hits = (row & 1u) | ((row >> 7) & 2u) | ((row >> 7) & 4u) | ((row << 2) & 8u);
    } else {
      const int bw = std::min(kBlock, n_ - (b0 & ~(kBlock - 1)));
      rank0 = unsigned(la * bw + lb);
      rank1 = rank0 + unsigned(bw);
      hits = 15u;
    }
    const unsigned rank[4] = {rank0, rank1, rank1 + ((hits >> 1) & 1u), rank0 + (hits & 1u)};
    const unsigned kt = r[1] & 31u, ku = r[2] & 15u, kv = r[2] >> 4;
    const unsigned width = kt + ku + kv;
    const auto t_base = get_pod<std::int32_t>(r + 4);
    const std::int32_t t_ga = get_pod<std::int16_t>(r + 8), t_gb = get_pod<std::int16_t>(r + 10);
    const std::int32_t u_base = get_pod<std::int16_t>(r + 12), v_base = get_pod<std::int16_t>(r + 14);
    const std::int32_t u_ga = std::int8_t(r[16]), u_gb = std::int8_t(r[17]);
    const std::int32_t v_ga = std::int8_t(r[18]), v_gb = std::int8_t(r[19]);
    // The four samples side by side in SSE2 lanes (lane k: sample k), with fetch_from()'s
    // operations: integer sums (wrapping, as the scalar ones), cvtdq2ps = float(int), mulps,
    // maxps / minps = std::max / std::min in fetch_from()'s operand order (NaN included).
    const auto word = [&](unsigned rank) {  // the sample's residuals from bit 0 (masked below)
      const std::uint64_t pos = std::uint64_t(rank) * width;
      return std::int64_t(get_pod<std::uint64_t>(bits + (pos >> 3)) >> (pos & 7u));
    };
    const __m128i w01 = _mm_set_epi64x(word(rank[1]), word(rank[0]));
    const __m128i w23 = _mm_set_epi64x(word(rank[3]), word(rank[2]));
    const auto low32 = [](__m128i x, __m128i y) {  // the low halves of the 64-bit lanes of x, y
      return _mm_castps_si128(_mm_shuffle_ps(_mm_castsi128_ps(x), _mm_castsi128_ps(y), _MM_SHUFFLE(2, 0, 2, 0)));
    };
    const __m128i cu = _mm_cvtsi32_si128(int(kt)), cv = _mm_cvtsi32_si128(int(kt + ku));
    const __m128i rt = _mm_and_si128(low32(w01, w23), _mm_set1_epi32(int((std::uint64_t(1) << kt) - 1u)));
    const __m128i ru = _mm_and_si128(low32(_mm_srl_epi64(w01, cu), _mm_srl_epi64(w23, cu)), _mm_set1_epi32((1 << ku) - 1));
    const __m128i rv = _mm_and_si128(low32(_mm_srl_epi64(w01, cv), _mm_srl_epi64(w23, cv)), _mm_set1_epi32((1 << kv) - 1));
    // predict(g_a, g_b, la + da, lb + db) = (g_a * la + g_b * lb + g_a * da + g_b * db) >> 2.
    const auto channel = [&](std::int32_t base, std::int32_t ga, std::int32_t gb, __m128i res) {
      const __m128i p = _mm_srai_epi32(_mm_add_epi32(_mm_set1_epi32(ga * la + gb * lb), _mm_setr_epi32(0, ga, ga + gb, gb)), 2);
      return _mm_cvtepi32_ps(_mm_add_epi32(_mm_add_epi32(_mm_set1_epi32(base), p), res));
    };
    const __m128 one = _mm_set1_ps(1.f), minus_one = _mm_set1_ps(-1.f);
    tv = _mm_mul_ps(channel(t_base, t_ga, t_gb, rt), _mm_set1_ps(t_step_));
    uv = _mm_min_ps(_mm_max_ps(_mm_mul_ps(channel(u_base, u_ga, u_gb, ru), _mm_set1_ps(n_step_)), minus_one), one);
    vv = _mm_min_ps(_mm_max_ps(_mm_mul_ps(channel(v_base, v_ga, v_gb, rv), _mm_set1_ps(n_step_)), minus_one), one);
    const __m128i lane_bit = _mm_setr_epi32(1, 2, 4, 8);
    const __m128 in_mask = _mm_castsi128_ps(_mm_cmpeq_epi32(_mm_and_si128(_mm_set1_epi32(int(hits)), lane_bit), lane_bit));
    return _mm_and_ps(in_mask, _mm_cmpge_ps(tv, _mm_setzero_ps()));
  }
  /// fetch_quad_from() on the quad's records.
  unsigned fetch_quad(std::size_t tile, int a0, int b0, float* t, float* u, float* v) const noexcept {
    const std::uint8_t* rec[4];
    quad_records(tile, a0, b0, rec);
    return fetch_quad_from(rec, a0, b0, t, u, v);
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
  // fetch_quad_from() for a quad across blocks (a0 or b0 ends a block).
  unsigned fetch_quad_split(const std::uint8_t* const rec[4], int a0, int b0, float* t, float* u, float* v) const noexcept;

  const std::uint32_t* index_ = nullptr;
  const std::uint8_t* data_ = nullptr;
  std::size_t data_bytes_ = 0;
  float t_step_ = 1.f, n_step_ = 1.f;
  int n_ = 2, nb_ = 1;
};

} // namespace hb
