// Block codec encoder and sequential decoder (the format is described in block_codec.h).
//  1. Tiles are encoded in parallel chunks (TBB); each chunk appends its block records to its
//     own buffer; the chunks are then concatenated and the offsets rebased.
//  2. All-miss blocks share one 1-byte record at data offset 0.
//  3. Per block and channel, values are put on the lattice (round(value / step)), and two
//     predictors are tried: none, and the least-squares plane rounded to quarter steps; the
//     one with the narrower residual range wins (ties: none).
#include "codec/block_codec.h"
#include "errors.h"
#include "geometry/octahedral.h"
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <limits>

namespace hb {
namespace {

struct ChannelFit {
  std::int32_t base = 0, ga = 0, gb = 0;
  unsigned k = 0;
};

ChannelFit fit_channel(const std::int32_t* q, const int* la, const int* lb, int count, int grad_limit) {
  auto evaluate = [&](std::int32_t ga, std::int32_t gb) {
    ChannelFit f;
    f.ga = ga;
    f.gb = gb;
    std::int64_t lo = std::numeric_limits<std::int64_t>::max(), hi = std::numeric_limits<std::int64_t>::min();
    for (int i = 0; i < count; ++i) {
      const std::int64_t r = std::int64_t(q[i]) - BlockTable::predict(ga, gb, la[i], lb[i]);
      lo = std::min(lo, r);
      hi = std::max(hi, r);
    }
    f.base = std::int32_t(lo);
    f.k = bits_for(std::uint64_t(hi - lo));
    return f;
  };
  ChannelFit best = evaluate(0, 0);
  if (count < 3 || best.k == 0) return best;
  double ma = 0, mb = 0, mq = 0;
  for (int i = 0; i < count; ++i) {
    ma += la[i];
    mb += lb[i];
    mq += q[i];
  }
  ma /= count;
  mb /= count;
  mq /= count;
  double saa = 0, sbb = 0, sab = 0, saq = 0, sbq = 0;
  for (int i = 0; i < count; ++i) {
    const double da = la[i] - ma, db = lb[i] - mb, dq = q[i] - mq;
    saa += da * da;
    sbb += db * db;
    sab += da * db;
    saq += da * dq;
    sbq += db * dq;
  }
  double ga = 0, gb = 0;
  const double det = saa * sbb - sab * sab;
  if (det > 1e-9) {
    ga = (saq * sbb - sbq * sab) / det;
    gb = (sbq * saa - saq * sab) / det;
  } else if (saa > 1e-9) {
    ga = saq / saa;
  } else if (sbb > 1e-9) {
    gb = sbq / sbb;
  }
  auto clamp_grad = [&](double g) {
    return std::int32_t(std::max<double>(-grad_limit, std::min<double>(grad_limit, std::lround(4.0 * g))));
  };
  const ChannelFit plane = evaluate(clamp_grad(ga), clamp_grad(gb));
  if (plane.k < best.k) best = plane;
  return best;
}

// Encodes one block of one tile into `out`; returns false for an all-miss block (nothing written).
bool encode_block(const Sample* tile, int n, int ba, int bb, float t_step, float n_step, std::vector<std::uint8_t>& out) {
  constexpr int B = BlockTable::kBlock;
  std::int32_t qt[64], qu[64], qv[64];
  int la[64], lb[64];
  std::uint64_t mask = 0;
  int count = 0, valid = 0;
  for (int a = 0; a < B && ba * B + a < n; ++a)
    for (int b = 0; b < B && bb * B + b < n; ++b) {
      ++valid;
      const Sample& s = tile[(ba * B + a) * n + (bb * B + b)];
      if (s.t < 0.f) continue;
      mask |= std::uint64_t(1) << (a * B + b);
      // Octahedral coordinates straight from the 16-bit code.
      const float u = float(std::int16_t(s.normal & 0xffffu)) / 32767.f;
      const float v = float(std::int16_t(s.normal >> 16)) / 32767.f;
      qt[count] = std::int32_t(std::lround(double(s.t) / double(t_step)));
      qu[count] = std::int32_t(std::lround(u / n_step));
      qv[count] = std::int32_t(std::lround(v / n_step));
      la[count] = a;
      lb[count] = b;
      ++count;
    }
  if (count == 0) return false;
  const ChannelFit ft = fit_channel(qt, la, lb, count, 32767);
  const ChannelFit fu = fit_channel(qu, la, lb, count, 127);
  const ChannelFit fv = fit_channel(qv, la, lb, count, 127);
  if (ft.k > 24 || fu.k > 15 || fv.k > 15 || ft.base < -(1 << 30) || ft.base > (1 << 30) ||
      fu.base < -32768 || fu.base > 32767 || fv.base < -32768 || fv.base > 32767)
    throw InvalidInput("block codec: value range too wide for the error bound (bound too small)");
  const std::uint8_t mode = count == valid ? 1 : 2;
  out.push_back(mode);
  out.push_back(std::uint8_t(ft.k));
  out.push_back(std::uint8_t(fu.k | (fv.k << 4)));
  out.push_back(0);
  put_pod(out, std::int32_t(ft.base));
  put_pod(out, std::int16_t(ft.ga));
  put_pod(out, std::int16_t(ft.gb));
  put_pod(out, std::int16_t(fu.base));
  put_pod(out, std::int16_t(fv.base));
  out.push_back(std::uint8_t(std::int8_t(fu.ga)));
  out.push_back(std::uint8_t(std::int8_t(fu.gb)));
  out.push_back(std::uint8_t(std::int8_t(fv.ga)));
  out.push_back(std::uint8_t(std::int8_t(fv.gb)));
  if (mode == 2) put_pod(out, mask);
  BitWriter w(out);
  for (int i = 0; i < count; ++i) {
    const auto rt = std::uint64_t(qt[i] - BlockTable::predict(ft.ga, ft.gb, la[i], lb[i]) - ft.base);
    const auto ru = std::uint64_t(qu[i] - BlockTable::predict(fu.ga, fu.gb, la[i], lb[i]) - fu.base);
    const auto rv = std::uint64_t(qv[i] - BlockTable::predict(fv.ga, fv.gb, la[i], lb[i]) - fv.base);
    w.put(rt | (ru << ft.k) | (rv << (ft.k + fu.k)), ft.k + fu.k + fv.k);
  }
  return true;
}

} // namespace

std::vector<std::uint8_t> encode_block_table(const Sample* raw, const BoxParams& params, float t_step, float n_step) {
  const int n = params.n;
  const int nb = (n + BlockTable::kBlock - 1) / BlockTable::kBlock;
  const std::size_t tiles = params.tile_count();
  const std::size_t per_tile = std::size_t(n) * std::size_t(n);
  const std::size_t blocks_per_tile = std::size_t(nb) * std::size_t(nb);
  constexpr std::size_t kChunk = 512;
  const std::size_t chunks = (tiles + kChunk - 1) / kChunk;
  std::vector<std::vector<std::uint8_t>> chunk_data(chunks);
  std::vector<std::uint32_t> index(tiles * blocks_per_tile, 0);
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, chunks), [&](const tbb::blocked_range<std::size_t>& r) {
    for (std::size_t c = r.begin(); c != r.end(); ++c) {
      auto& out = chunk_data[c];
      for (std::size_t tile = c * kChunk; tile < std::min(tiles, (c + 1) * kChunk); ++tile)
        for (int ba = 0; ba < nb; ++ba)
          for (int bb = 0; bb < nb; ++bb) {
            const std::size_t at = out.size();
            const bool hit = encode_block(raw + tile * per_tile, n, ba, bb, t_step, n_step, out);
            if (out.size() > 0xffffffffu) throw InvalidInput("block codec: compressed table larger than 4 GiB");
            index[tile * blocks_per_tile + std::size_t(ba) * std::size_t(nb) + std::size_t(bb)] =
                hit ? std::uint32_t(at) : kMissEntry;
          }
    }
  });
  const std::vector<std::uint8_t> data = join_chunk_records(chunk_data, index, kChunk * blocks_per_tile, "block");
  return assemble_payload(CodecId::block, params, t_step, n_step, index, data);
}

BlockTable::BlockTable(const std::uint8_t* payload, std::size_t bytes, const BoxParams& params) {
  const int nb = (params.n + kBlock - 1) / kBlock;
  const PayloadHeader h =
      validate_payload(payload, bytes, CodecId::block, params, params.tile_count() * std::size_t(nb) * std::size_t(nb));
  index_ = reinterpret_cast<const std::uint32_t*>(payload + h.index_offset);
  data_ = payload + h.data_offset;
  data_bytes_ = std::size_t(h.data_bytes);
  t_step_ = h.t_step;
  n_step_ = h.n_step;
  n_ = params.n;
  nb_ = nb;
}

unsigned BlockTable::fetch_quad_split(const std::uint8_t* const rec[4], int a0, int b0, float* t, float* u,
                                      float* v) const noexcept {
  unsigned hits = 0;
  for (int k = 0; k < 4; ++k) {
    float tk = kMissT, uk = 0.f, vk = 0.f;
    const bool hit = fetch_from(rec[k], a0 + (k == 1 || k == 2), b0 + (k >= 2), tk, uk, vk);
    t[k] = hit ? tk : kMissT;
    u[k] = hit ? uk : 0.f;
    v[k] = hit ? vk : 0.f;
    hits |= unsigned(hit) << k;
  }
  return hits;
}

void BlockTable::decode_tile(std::size_t tile, DecodedSample* out) const noexcept {
  // Sequential: walk each block's residual stream in order instead of ranking each sample.
  for (int i = 0; i < n_ * n_; ++i) out[i] = {kMissT, 0.f, 0.f};
  for (int ba = 0; ba < nb_; ++ba)
    for (int bb = 0; bb < nb_; ++bb) {
      std::uint32_t offset;
      std::memcpy(&offset, index_ + (tile * std::size_t(nb_) + std::size_t(ba)) * std::size_t(nb_) + std::size_t(bb), 4);
      if (!has_record(offset)) continue;
      const std::uint8_t* rec = data_ + offset;
      if (rec[0] == 0) continue;
      const std::uint8_t* bits = rec + kHeaderBytes;
      std::uint64_t mask = ~std::uint64_t(0);
      if (rec[0] == 2) {
        mask = get_pod<std::uint64_t>(bits);
        bits += 8;
      }
      const unsigned kt = rec[1] & 31u, ku = rec[2] & 15u, kv = rec[2] >> 4, width = kt + ku + kv;
      const auto t_base = get_pod<std::int32_t>(rec + 4);
      const auto t_ga = get_pod<std::int16_t>(rec + 8), t_gb = get_pod<std::int16_t>(rec + 10);
      const auto u_base = get_pod<std::int16_t>(rec + 12), v_base = get_pod<std::int16_t>(rec + 14);
      const auto u_ga = std::int8_t(rec[16]), u_gb = std::int8_t(rec[17]);
      const auto v_ga = std::int8_t(rec[18]), v_gb = std::int8_t(rec[19]);
      std::uint64_t pos = 0;
      for (int la = 0; la < kBlock && ba * kBlock + la < n_; ++la)
        for (int lb = 0; lb < kBlock && bb * kBlock + lb < n_; ++lb) {
          if (!((mask >> (la * kBlock + lb)) & 1u)) continue;
          const std::uint64_t word = read_bits(bits, pos, width);
          pos += width;
          DecodedSample& s = out[(ba * kBlock + la) * n_ + bb * kBlock + lb];
          const auto rt = std::int32_t(word & ((std::uint64_t(1) << kt) - 1u));
          const auto ru = std::int32_t((word >> kt) & ((std::uint64_t(1) << ku) - 1u));
          const auto rv = std::int32_t((word >> (kt + ku)) & ((std::uint64_t(1) << kv) - 1u));
          s.t = float(t_base + predict(t_ga, t_gb, la, lb) + rt) * t_step_;
          s.u = std::fmin(1.f, std::fmax(-1.f, float(u_base + predict(u_ga, u_gb, la, lb) + ru) * n_step_));
          s.v = std::fmin(1.f, std::fmax(-1.f, float(v_base + predict(v_ga, v_gb, la, lb) + rv) * n_step_));
          if (s.t < 0.f) s = {kMissT, 0.f, 0.f};
        }
    }
}

} // namespace hb
