// Table views and compression with error control.
//  1. The lattice steps follow from the options: t_step = 2 x bound x diagonal (shaved by a
//     few float ulps so rounding cannot push a value past the bound), n_step = 2 / (2^bits - 1).
//  2. --ratio: bisection on log(bound) over [1e-5, 0.1] (compressed size decreases with the
//     bound), 14 encodes at most, keeping the tightest bound that reaches the ratio.
//  3. The result is measured against the raw table (measure_table), in parallel.
#include "codec/sample_table.h"
#include "errors.h"
#include "geometry/octahedral.h"
#include <tbb/blocked_range.h>
#include <tbb/parallel_reduce.h>
#include <cmath>

namespace hb {

SampleTable::SampleTable(CodecId codec, const std::uint8_t* payload, std::size_t bytes, const BoxParams& params)
    : codec_(codec), params_(params), payload_(payload), payload_bytes_(bytes) {
  switch (codec) {
  case CodecId::block: block_ = BlockTable(payload, bytes, params); break;
  case CodecId::haar: haar_ = HaarTable(payload, bytes, params); break;
  default: throw InvalidInput("compressed payload: unknown codec id " + std::to_string(std::uint32_t(codec)));
  }
}

std::size_t SampleTable::bytes() const noexcept {
  return raw_ ? params_.sample_count() * sizeof(Sample) : payload_bytes_;
}

DecodedSample SampleTable::decode(std::size_t tile, int a, int b) const noexcept {
  switch (codec_) {
  case CodecId::block: return block_.decode(tile, a, b);
  case CodecId::haar: return haar_.decode(tile, a, b);
  default: break;
  }
  const Sample& s = raw_[tile * std::size_t(params_.n) * std::size_t(params_.n) + std::size_t(a) * std::size_t(params_.n) + std::size_t(b)];
  if (s.t < 0.f) return {kMissT, 0.f, 0.f};
  return {s.t, float(std::int16_t(s.normal & 0xffffu)) / 32767.f, float(std::int16_t(s.normal >> 16)) / 32767.f};
}

void SampleTable::decode_tile(std::size_t tile, DecodedSample* out) const {
  switch (codec_) {
  case CodecId::block: block_.decode_tile(tile, out); return;
  case CodecId::haar: haar_.decode_tile(tile, out); return;
  default: break;
  }
  for (int a = 0; a < params_.n; ++a)
    for (int b = 0; b < params_.n; ++b) out[a * params_.n + b] = decode(tile, a, b);
}

const char* codec_name(CodecId id) noexcept {
  switch (id) {
  case CodecId::none: return "none";
  case CodecId::haar: return "haar";
  case CodecId::block: return "block";
  }
  return "unknown";
}

CodecId parse_codec(const std::string& name) {
  if (name == "none" || name == "raw") return CodecId::none;
  if (name == "haar") return CodecId::haar;
  if (name == "block" || name == "bc") return CodecId::block;
  throw InvalidInput("unknown codec '" + name + "' (expected none, haar or block)");
}

namespace {

std::vector<std::uint8_t> encode(const Sample* raw, const BoxParams& params, float diagonal, CodecId codec,
                                 float max_error, int normal_bits) {
  // Shave the half step by 8 float ulps of the largest t (2 x diagonal): decoded values are
  // float products, and their rounding must not push a value past the bound.
  const double ulp = 2.0 * double(diagonal) * std::ldexp(1.0, -23);
  const float t_step = float(2.0 * (double(max_error) * double(diagonal) - 8.0 * ulp));
  const float n_step = 2.f / float((1 << normal_bits) - 1);
  if (!(t_step > 0.f)) throw InvalidInput("compress: the box diagonal must be positive");
  return codec == CodecId::haar ? encode_haar_table(raw, params, t_step, n_step)
                                : encode_block_table(raw, params, t_step, n_step);
}

} // namespace

CompressedTable compress_table(const Sample* raw, const BoxParams& params, float diagonal, const CodecOptions& o) {
  if (o.codec != CodecId::haar && o.codec != CodecId::block)
    throw InvalidInput(std::string("compress: codec '") + codec_name(o.codec) + "' does not compress");
  if (o.normal_bits < 6 || o.normal_bits > 14)
    throw InvalidInput("compress: normal bits must be in [6, 14], got " + std::to_string(o.normal_bits));
  if (o.ratio != 0.f && !(o.ratio >= 1.f))
    throw InvalidInput("compress: the ratio must be >= 1, got " + std::to_string(o.ratio));
  if (o.ratio == 0.f && !(o.max_error >= 1e-5f && o.max_error <= 0.1f))
    throw InvalidInput("compress: the error bound must be in [1e-5, 0.1], got " + std::to_string(o.max_error));
  const double raw_bytes = double(params.sample_count()) * sizeof(Sample);
  CompressedTable out;
  out.codec = o.codec;
  float bound = o.max_error;
  if (o.ratio > 0.f) {
    double lo = std::log(1e-5), hi = std::log(0.1);
    std::vector<std::uint8_t> best = encode(raw, params, diagonal, o.codec, float(std::exp(hi)), o.normal_bits);
    bound = float(std::exp(hi));
    if (raw_bytes / double(best.size()) >= o.ratio) {
      for (int it = 0; it < 13; ++it) {
        const double mid = 0.5 * (lo + hi);
        std::vector<std::uint8_t> p = encode(raw, params, diagonal, o.codec, float(std::exp(mid)), o.normal_bits);
        if (raw_bytes / double(p.size()) >= o.ratio) {
          hi = mid;
          best = std::move(p);
          bound = float(std::exp(mid));
        } else {
          lo = mid;
        }
      }
    }
    out.payload = std::move(best);
  } else {
    out.payload = encode(raw, params, diagonal, o.codec, bound, o.normal_bits);
  }
  const SampleTable view(o.codec, out.payload.data(), out.payload.size(), params);
  out.stats = measure_table(raw, view, params, diagonal);
  out.stats.max_error_bound = bound;
  return out;
}

CodecStats measure_table(const Sample* raw, const SampleTable& table, const BoxParams& params, float diagonal) {
  struct Acc {
    double t_sum = 0, t_max = 0, a_sum = 0, a_max = 0;
    std::uint64_t hits = 0, flips = 0;
  };
  const std::size_t per_tile = std::size_t(params.n) * std::size_t(params.n);
  const Acc acc = tbb::parallel_reduce(
      tbb::blocked_range<std::size_t>(0, params.tile_count(), 256), Acc{},
      [&](const tbb::blocked_range<std::size_t>& r, Acc a) {
        std::vector<DecodedSample> dec(per_tile);
        for (std::size_t tile = r.begin(); tile != r.end(); ++tile) {
          table.decode_tile(tile, dec.data());
          for (std::size_t i = 0; i < per_tile; ++i) {
            const Sample& s = raw[tile * per_tile + i];
            const bool hit0 = s.t >= 0.f, hit1 = dec[i].t >= 0.f;
            if (hit0 != hit1) ++a.flips;
            if (!hit0 || !hit1) continue;
            ++a.hits;
            const double e = std::fabs(double(dec[i].t) - double(s.t)) / double(diagonal);
            a.t_sum += e;
            a.t_max = std::max(a.t_max, e);
            const Vec3 n0 = decode_octahedral32(s.normal);
            const Vec3 n1 = oct_decode_unnormalized(dec[i].u, dec[i].v).normalized();
            const double ang = std::acos(std::min(1.0, std::max(-1.0, double(n0.dot(n1))))) * 180.0 / M_PI;
            a.a_sum += ang;
            a.a_max = std::max(a.a_max, ang);
          }
        }
        return a;
      },
      [](Acc x, const Acc& y) {
        x.t_sum += y.t_sum;
        x.t_max = std::max(x.t_max, y.t_max);
        x.a_sum += y.a_sum;
        x.a_max = std::max(x.a_max, y.a_max);
        x.hits += y.hits;
        x.flips += y.flips;
        return x;
      });
  CodecStats s;
  s.raw_bytes = params.sample_count() * sizeof(Sample);
  s.bytes = table.bytes();
  s.t_error_mean = acc.hits ? float(acc.t_sum / double(acc.hits)) : 0.f;
  s.t_error_max = float(acc.t_max);
  s.normal_error_mean_deg = acc.hits ? float(acc.a_sum / double(acc.hits)) : 0.f;
  s.normal_error_max_deg = float(acc.a_max);
  s.hit_miss_flips = acc.flips;
  return s;
}

} // namespace hb
