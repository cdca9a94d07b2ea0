// Haar codec encoder and full decoder (the format is described in haar_codec.h).
//  1. Per tile (in parallel chunks): pad to N x N by edge repetition, fill misses with the
//     mean of the hits, forward-transform t, u and v (doubles).
//  2. Per channel: for step exponent s = 0, 1, ...: quantise every coefficient to an integer
//     multiple of step 2^-s, reconstruct every hit exactly as the decoder does, and stop at
//     the first s whose worst hit is within the bound.
//  3. Write the record; all-miss tiles share a 1-byte record at data offset 0.
#include "codec/haar_codec.h"
#include "errors.h"
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

namespace hb {
namespace {

int pow2_at_least(int n) {
  int N = 1;
  while (N < n) N *= 2;
  return N;
}
std::size_t bitmap_bytes_for(int N) { return (std::size_t(N) * std::size_t(N) + 63u) / 64u * 8u; }
std::size_t max_record_bytes(int N) {
  return HaarTable::kHeaderBytes + bitmap_bytes_for(N) + 3u * (bitmap_bytes_for(N) + std::size_t(N) * std::size_t(N) * 4u) + 16u;
}

void forward_haar(std::vector<double>& x, int N) {
  std::vector<double> tmp(x.size());
  for (int s = N; s > 1; s /= 2) {
    const int h = s / 2;
    for (int i = 0; i < h; ++i)
      for (int j = 0; j < h; ++j) {
        const double x00 = x[(2 * i) * N + 2 * j], x01 = x[(2 * i) * N + 2 * j + 1];
        const double x10 = x[(2 * i + 1) * N + 2 * j], x11 = x[(2 * i + 1) * N + 2 * j + 1];
        tmp[i * N + j] = (x00 + x01 + x10 + x11) / 4;
        tmp[i * N + h + j] = (x00 - x01 + x10 - x11) / 4;        // H: along b
        tmp[(h + i) * N + j] = (x00 + x01 - x10 - x11) / 4;      // V: along a
        tmp[(h + i) * N + h + j] = (x00 - x01 - x10 + x11) / 4;  // D
      }
    for (int i = 0; i < s; ++i)
      for (int j = 0; j < s; ++j) x[i * N + j] = tmp[i * N + j];
  }
}

// Integer inverse transform in place (exact).
void inverse_haar(std::vector<std::int64_t>& c, int N) {
  std::vector<std::int64_t> tmp(c.size());
  for (int s = 2; s <= N; s *= 2) {
    const int h = s / 2;
    for (int i = 0; i < h; ++i)
      for (int j = 0; j < h; ++j) {
        const std::int64_t A = c[i * N + j], H = c[i * N + h + j], V = c[(h + i) * N + j], D = c[(h + i) * N + h + j];
        tmp[(2 * i) * N + 2 * j] = A + H + V + D;
        tmp[(2 * i) * N + 2 * j + 1] = A - H + V - D;
        tmp[(2 * i + 1) * N + 2 * j] = A + H - V - D;
        tmp[(2 * i + 1) * N + 2 * j + 1] = A - H - V + D;
      }
    for (int i = 0; i < s; ++i)
      for (int j = 0; j < s; ++j) c[i * N + j] = tmp[i * N + j];
  }
}

struct ChannelCode {
  std::vector<std::int64_t> q;  // quantised coefficients
  int exponent = 0;
  unsigned k = 0;
};

// Finds the coarsest step (base * 2^-s) that keeps every hit within `bound` of its value.
ChannelCode quantise_channel(const std::vector<double>& coeffs, const std::vector<double>& values,
                             const std::vector<char>& hit, int N, int n, float base, double bound, bool clamp_unit,
                             bool clamp_zero) {
  ChannelCode code;
  code.q.resize(coeffs.size());
  std::vector<std::int64_t> rec;
  for (int s = 0; s < 40; ++s) {
    const float step = HaarTable::step(base, std::uint8_t(s));
    for (std::size_t i = 0; i < coeffs.size(); ++i) code.q[i] = std::llround(coeffs[i] / double(step));
    rec = code.q;
    inverse_haar(rec, N);
    bool ok = true;
    for (int a = 0; a < n && ok; ++a)
      for (int b = 0; b < n; ++b) {
        if (!hit[a * n + b]) continue;
        float v = float(rec[a * N + b]) * step;
        if (clamp_unit) v = std::fmin(1.f, std::fmax(-1.f, v));
        if (clamp_zero) v = std::fmax(0.f, v);
        if (std::fabs(double(v) - values[a * N + b]) > bound) {
          ok = false;
          break;
        }
      }
    if (ok) {
      code.exponent = s;
      std::uint64_t zmax = 0;
      for (auto c : code.q) zmax = std::max(zmax, (std::uint64_t(c) << 1) ^ std::uint64_t(c >> 63));
      code.k = bits_for(zmax);
      if (code.k > 31) throw InvalidInput("haar codec: coefficient range too wide for the error bound");
      return code;
    }
  }
  throw InvalidInput("haar codec: could not meet the error bound");
}

void write_channel(std::vector<std::uint8_t>& out, const ChannelCode& code, int N) {
  const std::size_t bm = bitmap_bytes_for(N);
  const std::size_t at = out.size();
  out.resize(at + bm, 0);
  for (std::size_t i = 0; i < code.q.size(); ++i)
    if (code.q[i] != 0) out[at + i / 8] |= std::uint8_t(1u << (i % 8));
  BitWriter w(out);
  for (auto c : code.q)
    if (c != 0) w.put((std::uint64_t(c) << 1) ^ std::uint64_t(c >> 63), code.k);
}

bool encode_tile(const Sample* tile, int n, int N, float t_step, float n_step, std::vector<std::uint8_t>& out) {
  std::vector<char> hit(std::size_t(n) * std::size_t(n));
  double st = 0, su = 0, sv = 0;
  int hits = 0;
  for (int i = 0; i < n * n; ++i) {
    hit[i] = tile[i].t >= 0.f;
    if (!hit[i]) continue;
    ++hits;
    st += tile[i].t;
    su += float(std::int16_t(tile[i].normal & 0xffffu)) / 32767.f;
    sv += float(std::int16_t(tile[i].normal >> 16)) / 32767.f;
  }
  if (hits == 0) return false;
  std::vector<double> t(std::size_t(N) * N), u(t.size()), v(t.size());
  for (int a = 0; a < N; ++a)
    for (int b = 0; b < N; ++b) {
      const int sa = std::min(a, n - 1), sb = std::min(b, n - 1);
      const Sample& s = tile[sa * n + sb];
      if (s.t >= 0.f) {
        t[a * N + b] = s.t;
        u[a * N + b] = float(std::int16_t(s.normal & 0xffffu)) / 32767.f;
        v[a * N + b] = float(std::int16_t(s.normal >> 16)) / 32767.f;
      } else {
        t[a * N + b] = st / hits;
        u[a * N + b] = su / hits;
        v[a * N + b] = sv / hits;
      }
    }
  const std::vector<double> t_values = t, u_values = u, v_values = v;
  forward_haar(t, N);
  forward_haar(u, N);
  forward_haar(v, N);
  const ChannelCode ct = quantise_channel(t, t_values, hit, N, n, t_step, 0.5 * t_step, false, true);
  const ChannelCode cu = quantise_channel(u, u_values, hit, N, n, n_step, 0.5 * n_step, true, false);
  const ChannelCode cv = quantise_channel(v, v_values, hit, N, n, n_step, 0.5 * n_step, true, false);
  const bool mixed = hits != n * n;
  const std::size_t at = out.size();
  out.push_back(mixed ? 2 : 1);
  out.push_back(std::uint8_t(ct.k));
  out.push_back(std::uint8_t(cu.k));
  out.push_back(std::uint8_t(cv.k));
  out.push_back(std::uint8_t(ct.exponent));
  out.push_back(std::uint8_t(cu.exponent));
  out.push_back(std::uint8_t(cv.exponent));
  out.push_back(0);
  put_pod(out, std::uint32_t(0));
  put_pod(out, std::uint32_t(0));
  if (mixed) {
    const std::size_t m = out.size();
    out.resize(m + bitmap_bytes_for(N), 0);
    for (int a = 0; a < n; ++a)
      for (int b = 0; b < n; ++b)
        if (hit[a * n + b]) out[m + std::size_t(a * N + b) / 8] |= std::uint8_t(1u << ((a * N + b) % 8));
  }
  const std::size_t sections = out.size();
  write_channel(out, ct, N);
  const auto off_u = std::uint32_t((out.size() - sections) * 8);
  write_channel(out, cu, N);
  const auto off_v = std::uint32_t((out.size() - sections) * 8);
  write_channel(out, cv, N);
  std::memcpy(out.data() + at + 8, &off_u, 4);
  std::memcpy(out.data() + at + 12, &off_v, 4);
  return true;
}

} // namespace

std::vector<std::uint8_t> encode_haar_table(const Sample* raw, const BoxParams& params, float t_step, float n_step) {
  const int n = params.n, N = pow2_at_least(n);
  const std::size_t tiles = params.tile_count();
  const std::size_t per_tile = std::size_t(n) * std::size_t(n);
  constexpr std::size_t kChunk = 512;
  const std::size_t chunks = (tiles + kChunk - 1) / kChunk;
  std::vector<std::vector<std::uint8_t>> chunk_data(chunks);
  std::vector<std::uint32_t> index(tiles, 0);
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, chunks), [&](const tbb::blocked_range<std::size_t>& r) {
    for (std::size_t c = r.begin(); c != r.end(); ++c)
      for (std::size_t tile = c * kChunk; tile < std::min(tiles, (c + 1) * kChunk); ++tile) {
        const std::size_t at = chunk_data[c].size();
        index[tile] = encode_tile(raw + tile * per_tile, n, N, t_step, n_step, chunk_data[c]) ? std::uint32_t(at) : kMissEntry;
      }
  });
  const std::vector<std::uint8_t> data = join_chunk_records(chunk_data, index, kChunk, "haar");
  return assemble_payload(CodecId::haar, params, t_step, n_step, index, data, max_record_bytes(N));
}

HaarTable::HaarTable(const std::uint8_t* payload, std::size_t bytes, const BoxParams& params) {
  const int N = pow2_at_least(params.n);
  const PayloadHeader h = validate_payload(payload, bytes, CodecId::haar, params, params.tile_count(), max_record_bytes(N));
  index_ = reinterpret_cast<const std::uint32_t*>(payload + h.index_offset);
  data_ = payload + h.data_offset;
  data_bytes_ = std::size_t(h.data_bytes);
  t_step_ = h.t_step;
  n_step_ = h.n_step;
  n_ = params.n;
  N_ = N;
  mask_bytes_ = bitmap_bytes_for(N);
  bitmap_bytes_ = bitmap_bytes_for(N);
  max_section_bits_ = std::uint32_t(8u * 2u * (bitmap_bytes_ + std::size_t(N) * std::size_t(N) * 4u));
  use_hardware_popcount(true);
}

namespace {

// Quad fetch: bitmaps of up to 64 words (N <= 64) keep their prefix ranks on the stack.
constexpr std::size_t kQuadMaxWords = 64;

// The quad fetch is compiled twice: with the popcnt instruction (a function of target
// "popcnt", chosen at run time when the CPU has it) and with the portable SWAR count (the
// build targets baseline x86-64). Its helpers are always inlined so that they take the
// target of the function they are inlined into.
#define HB_QUAD_INLINE inline __attribute__((always_inline))

template <bool kHardware> HB_QUAD_INLINE unsigned quad_popcount(std::uint64_t x) noexcept {
  if constexpr (kHardware)
    return unsigned(__builtin_popcountll(x));
  else
    return popcount64(x);
}

// One channel section of a record, with the rank of the first bit of each bitmap word.
template <bool kHardware> struct QuadChannel {
  const std::uint8_t* bitmap;
  const std::uint8_t* values;
  unsigned k;
  std::uint64_t value_mask;
  std::uint32_t prefix[kQuadMaxWords];

  HB_QUAD_INLINE void init(const std::uint8_t* section, std::size_t bitmap_bytes, unsigned width) noexcept {
    bitmap = section;
    values = section + bitmap_bytes;
    k = width;
    value_mask = (std::uint64_t(1) << width) - 1u;
    std::uint32_t rank = 0;
    for (std::size_t w = 0; w < bitmap_bytes / 8; ++w) {
      prefix[w] = rank;
      rank += quad_popcount<kHardware>(get_pod<std::uint64_t>(section + w * 8));
    }
  }
  // Coefficient idx (0 when its bitmap bit is clear). Branch-free: whether a coefficient
  // was thresholded away is data, unpredictable, and the read at the rank of a clear bit
  // stays inside the record (rank <= idx < N^2, the bound fetch() relies on too).
  HB_QUAD_INLINE std::int64_t term(unsigned idx) const noexcept {
    const std::uint64_t word = get_pod<std::uint64_t>(bitmap + (idx >> 6) * 8);
    const unsigned bit = idx & 63u;
    const std::uint64_t pos = std::uint64_t(prefix[idx >> 6] + quad_popcount<kHardware>(word & ((std::uint64_t(1) << bit) - 1u))) * k;
    const std::uint64_t z = (get_pod<std::uint64_t>(values + (pos >> 3)) >> (pos & 7u)) & value_mask;
    const std::int64_t present = -std::int64_t((word >> bit) & 1u);
    return (std::int64_t(z >> 1) ^ -std::int64_t(z & 1u)) & present;
  }
};

HB_QUAD_INLINE std::int64_t negate_if(std::int64_t x, std::int64_t mask) noexcept { return (x ^ mask) - mask; }

// Signed sum of one group's H, V and D for a value whose bits at this level are sa, sb
// (masks: all ones for 1), as in HaarTable::path_sum.
HB_QUAD_INLINE std::int64_t group_term(std::int64_t H, std::int64_t V, std::int64_t D, std::int64_t sa, std::int64_t sb) noexcept {
  return negate_if(H, sb) + negate_if(V, sa) + negate_if(D, sa ^ sb);
}

// One channel's sums of the quad (a0, b0), (a1, b0), (a1, b1), (a0, b1), a1 = a0 + 1,
// b1 = b0 + 1. Above level `cut` (the highest level where a0 and a1, or b0 and b1, differ
// in their bit) the four paths share group and signs: one sum. At and below it, only the
// distinct groups are read (a0 and a1 fall in two groups below the level of a0's carry).
template <bool kHardware>
HB_QUAD_INLINE void quad_channel_sums(const QuadChannel<kHardware>& ch, unsigned N, unsigned a0, unsigned b0, unsigned cut,
                              std::int64_t* s) noexcept {
  const unsigned a1 = a0 + 1, b1 = b0 + 1;
  std::int64_t common = ch.term(0);
  s[0] = s[1] = s[2] = s[3] = 0;
  for (unsigned h = N / 2, l = 0; h >= 1; h /= 2, ++l) {
    // H of group (ga, gb) at ga * N + h + gb; V at (h + ga) * N + gb; D at (h + ga) * N + h + gb.
    const unsigned v_offset = h * N - h, d_offset = h * N;
    const unsigned ga0 = a0 >> (l + 1), gb0 = b0 >> (l + 1);
    const unsigned first = ga0 * N + h + gb0;
    const std::int64_t H = ch.term(first), V = ch.term(first + v_offset), D = ch.term(first + d_offset);
    const std::int64_t sa0 = -std::int64_t((a0 >> l) & 1u), sb0 = -std::int64_t((b0 >> l) & 1u);
    if (l > cut) {
      common += group_term(H, V, D, sa0, sb0);
      continue;
    }
    const std::int64_t sa1 = -std::int64_t((a1 >> l) & 1u), sb1 = -std::int64_t((b1 >> l) & 1u);
    const unsigned ga1 = a1 >> (l + 1), gb1 = b1 >> (l + 1);
    s[0] += group_term(H, V, D, sa0, sb0);
    std::int64_t Ha = H, Va = V, Da = D;  // group (ga1, gb0)
    if (ga1 != ga0) {
      const unsigned f = ga1 * N + h + gb0;
      Ha = ch.term(f), Va = ch.term(f + v_offset), Da = ch.term(f + d_offset);
    }
    s[1] += group_term(Ha, Va, Da, sa1, sb0);
    std::int64_t Hb = H, Vb = V, Db = D;  // group (ga0, gb1)
    if (gb1 != gb0) {
      const unsigned f = ga0 * N + h + gb1;
      Hb = ch.term(f), Vb = ch.term(f + v_offset), Db = ch.term(f + d_offset);
    }
    s[3] += group_term(Hb, Vb, Db, sa0, sb1);
    if (ga1 != ga0 && gb1 != gb0) {  // group (ga1, gb1)
      const unsigned f = ga1 * N + h + gb1;
      s[2] += group_term(ch.term(f), ch.term(f + v_offset), ch.term(f + d_offset), sa1, sb1);
    } else if (ga1 != ga0) {
      s[2] += group_term(Ha, Va, Da, sa1, sb1);
    } else {
      s[2] += group_term(Hb, Vb, Db, sa1, sb1);
    }
  }
  for (int k = 0; k < 4; ++k) s[k] += common;
}

} // namespace

template <bool kHardware>
HB_QUAD_INLINE unsigned HaarTable::fetch_quad_with(std::size_t tile, int a0, int b0, float* t, float* u, float* v) const noexcept {
  for (int k = 0; k < 4; ++k) t[k] = kMissT, u[k] = 0.f, v[k] = 0.f;
  std::uint32_t offset;
  std::memcpy(&offset, index_ + tile, 4);
  if (offset >= data_bytes_) return 0;
  const std::uint8_t* rec = data_ + offset;
  const unsigned mode = rec[0];
  if (mode == 0) return 0;
  const unsigned A0 = unsigned(a0), B0 = unsigned(b0), N = unsigned(N_);
  const unsigned sample[4] = {A0 * N + B0, (A0 + 1) * N + B0, (A0 + 1) * N + B0 + 1, A0 * N + B0 + 1};
  const std::uint8_t* bits = rec + kHeaderBytes;
  unsigned hits = 15u;
  if (mode == 2) {
    hits = 0;
    for (int k = 0; k < 4; ++k) hits |= ((bits[sample[k] >> 3] >> (sample[k] & 7u)) & 1u) << k;
    bits += mask_bytes_;
  }
  if (hits == 0) return 0;
  const auto off_u = get_pod<std::uint32_t>(rec + 8), off_v = get_pod<std::uint32_t>(rec + 12);
  if (off_u > max_section_bits_ || off_v > max_section_bits_) return 0;
  if (bitmap_bytes_ / 8 > kQuadMaxWords) {
    // Tiles above 64 x 64 (n > 64): sample by sample.
    const int qa[4] = {a0, a0 + 1, a0 + 1, a0}, qb[4] = {b0, b0, b0 + 1, b0 + 1};
    for (int k = 0; k < 4; ++k)
      if ((hits >> k) & 1u) fetch(tile, qa[k], qb[k], t[k], u[k], v[k]);
    return hits;
  }
  // The level where a0 and a0 + 1 part is the count of a0's trailing ones (a0 <= N - 2).
  const unsigned cut = unsigned(std::max(__builtin_ctz(~A0), __builtin_ctz(~B0)));
  const std::uint8_t* sections[3] = {bits, bits + off_u / 8, bits + off_v / 8};
  std::int64_t sum[3][4];
  for (int c = 0; c < 3; ++c) {
    QuadChannel<kHardware> ch;
    ch.init(sections[c], bitmap_bytes_, rec[1 + c] & 31u);
    quad_channel_sums(ch, N, A0, B0, cut, sum[c]);
  }
  const float qt = step(t_step_, rec[4]), qu = step(n_step_, rec[5]), qv = step(n_step_, rec[6]);
  for (int k = 0; k < 4; ++k) {
    if (!((hits >> k) & 1u)) continue;
    // As fetch(): std::min / max on values that are never NaN or -0.
    t[k] = std::max(0.f, float(sum[0][k]) * qt);
    u[k] = std::min(1.f, std::max(-1.f, float(sum[1][k]) * qu));
    v[k] = std::min(1.f, std::max(-1.f, float(sum[2][k]) * qv));
  }
  return hits;
}

__attribute__((target("popcnt"))) unsigned HaarTable::fetch_quad_popcnt(std::size_t tile, int a0, int b0, float* t,
                                                                       float* u, float* v) const noexcept {
  return fetch_quad_with<true>(tile, a0, b0, t, u, v);
}

unsigned HaarTable::fetch_quad(std::size_t tile, int a0, int b0, float* t, float* u, float* v) const noexcept {
  if (hardware_popcount_) return fetch_quad_popcnt(tile, a0, b0, t, u, v);
  return fetch_quad_with<false>(tile, a0, b0, t, u, v);
}

void HaarTable::use_hardware_popcount(bool on) noexcept { hardware_popcount_ = on && __builtin_cpu_supports("popcnt"); }

#undef HB_QUAD_INLINE

void HaarTable::decode_tile(std::size_t tile, DecodedSample* out) const {
  for (int i = 0; i < n_ * n_; ++i) out[i] = {kMissT, 0.f, 0.f};
  std::uint32_t offset;
  std::memcpy(&offset, index_ + tile, 4);
  if (offset >= data_bytes_) return;
  const std::uint8_t* rec = data_ + offset;
  if (rec[0] == 0) return;
  const std::uint8_t* bits = rec + kHeaderBytes;
  const std::uint8_t* mask = nullptr;
  if (rec[0] == 2) {
    mask = bits;
    bits += mask_bytes_;
  }
  const auto off_u = get_pod<std::uint32_t>(rec + 8), off_v = get_pod<std::uint32_t>(rec + 12);
  if (off_u > max_section_bits_ || off_v > max_section_bits_) return;
  const std::size_t NN = std::size_t(N_) * std::size_t(N_);
  std::vector<std::int64_t> c[3];  // not the hot path: a full decode may allocate
  const std::uint8_t* sections[3] = {bits, bits + off_u / 8, bits + off_v / 8};
  for (int ch = 0; ch < 3; ++ch) {
    const unsigned k = rec[1 + ch] & 31u;
    c[ch].assign(NN, 0);
    std::uint64_t pos = 0;
    for (std::size_t i = 0; i < NN; ++i)
      if ((sections[ch][i / 8] >> (i % 8)) & 1u) {
        const std::uint64_t z = read_bits(sections[ch] + bitmap_bytes_, pos, k);
        pos += k;
        c[ch][i] = std::int64_t(z >> 1) ^ -std::int64_t(z & 1u);
      }
    inverse_haar(c[ch], N_);
  }
  const float qt = step(t_step_, rec[4]), qu = step(n_step_, rec[5]), qv = step(n_step_, rec[6]);
  for (int a = 0; a < n_; ++a)
    for (int b = 0; b < n_; ++b) {
      const std::size_t i = std::size_t(a) * std::size_t(N_) + std::size_t(b);
      if (mask && !((mask[i / 8] >> (i % 8)) & 1u)) continue;
      out[a * n_ + b] = {std::fmax(0.f, float(c[0][i]) * qt), std::fmin(1.f, std::fmax(-1.f, float(c[1][i]) * qu)),
                         std::fmin(1.f, std::fmax(-1.f, float(c[2][i]) * qv))};
    }
}

} // namespace hb
