// hb_bench_codec: single-value decode and query time, raw against compressed tables, and the
// batched raw query at each SIMD level.
// The box: $HB_BENCH_BOX (an uncompressed .hbox; probes from its source mesh), or a bumpy
// sphere (20,480 triangles) baked at m=32 n=16. Both codecs at $HB_BENCH_ERROR (default
// 1e-3 of the box diagonal). Decode: random samples over the whole table (DRAM-bound) and
// samples within a few tiles (cache-resident: the decoder's own cost).
#include "codec/sample_table.h"
#include "evaluation/probe_sampling.h"
#include "geometry/octahedral.h"
#include "scene/bake.h"
#include "store/box_file.h"
#include "mesh/generators.h"
#include "mesh/mesh_io.h"
#include <benchmark/benchmark.h>
#include <algorithm>
#include <cstdlib>
#include <iostream>
#include <memory>
#include <random>

namespace {

struct Setup {
  hb::TriangleMesh mesh;
  std::unique_ptr<hb::HapticBox> raw, block, haar;
  std::vector<hb::Segment> probes;
  struct Pick {
    std::size_t tile;
    int a, b;
  };
  std::vector<Pick> random_picks, cached_picks;
};

const Setup& setup() {
  static const Setup s = [] {
    Setup s;
    const char* box_path = std::getenv("HB_BENCH_BOX");
    if (box_path) {
      const hb::BoxScene scene = hb::load_box_file(box_path);
      s.raw = std::make_unique<hb::HapticBox>(scene.parts().boxes.front());
      s.mesh = hb::read_mesh(scene.parts().source.mesh_path);
    } else {
      hb::BumpySphereOptions o;
      o.subdivisions = 5;
      s.mesh = hb::make_bumpy_sphere(o);
      hb::BakeOptions b;
      b.params = {32, 16};
      s.raw = std::make_unique<hb::HapticBox>(hb::bake_box(s.mesh, {}, b));
    }
    const char* err = std::getenv("HB_BENCH_ERROR");
    hb::CodecOptions co;
    co.max_error = err ? float(std::atof(err)) : 1e-3f;
    co.codec = hb::CodecId::block;
    s.block = std::make_unique<hb::HapticBox>(s.raw->compressed(co));
    co.codec = hb::CodecId::haar;
    s.haar = std::make_unique<hb::HapticBox>(s.raw->compressed(co));
    for (const auto* box : {s.block.get(), s.haar.get()}) {
      const hb::CodecStats& cs = box->codec_stats();
      std::cerr << hb::codec_name(box->codec()) << ": ratio " << cs.ratio() << ", t error mean " << cs.t_error_mean
                << " max " << cs.t_error_max << ", normal mean " << cs.normal_error_mean_deg << " deg max "
                << cs.normal_error_max_deg << " deg\n";
    }
    s.probes = hb::sample_probes(s.mesh, 20000);
    const hb::BoxParams& p = s.raw->params();
    std::mt19937_64 rng(7);
    for (int i = 0; i < 1 << 16; ++i)
      s.random_picks.push_back({std::size_t(rng() % p.tile_count()), int(rng() % unsigned(p.n)), int(rng() % unsigned(p.n))});
    // A few tiles with hits, so the decoder's arithmetic is measured, not the misses' early exit.
    for (std::size_t tile = p.tile_count() / 2; s.cached_picks.size() < 1024 && tile < p.tile_count(); ++tile)
      for (int a = 0; a < p.n; ++a)
        for (int b = 0; b < p.n; ++b)
          if (s.raw->samples().decode(tile, a, b).t >= 0.f) s.cached_picks.push_back({tile, a, b});
    std::shuffle(s.cached_picks.begin(), s.cached_picks.end(), rng);
    return s;
  }();
  return s;
}

template <class Fetch> void run_decode(benchmark::State& state, const std::vector<Setup::Pick>& picks, Fetch fetch) {
  std::size_t i = 0;
  float acc = 0.f;
  for (auto _ : state) {
    const auto& p = picks[i];
    float t, u, v;
    if (fetch(p.tile, p.a, p.b, t, u, v)) acc += t + u + v;
    if (++i == picks.size()) i = 0;
  }
  benchmark::DoNotOptimize(acc);
}

// Decoding a raw sample = reading it and its octahedral coordinates.
bool raw_fetch(const hb::HapticBox& box, std::size_t tile, int a, int b, float& t, float& u, float& v) {
  const std::size_t n = std::size_t(box.params().n);
  const hb::Sample& s = box.table()[(tile * n + std::size_t(a)) * n + std::size_t(b)];
  t = s.t;
  u = float(std::int16_t(s.normal & 0xffffu)) * (1.f / 32767.f);
  v = float(std::int16_t(s.normal >> 16)) * (1.f / 32767.f);
  return t >= 0.f;
}

void decode_bench(benchmark::State& state, hb::CodecId codec, bool cached) {
  const Setup& s = setup();
  const auto& picks = cached ? s.cached_picks : s.random_picks;
  switch (codec) {
  case hb::CodecId::block:
    run_decode(state, picks, [&](std::size_t tile, int a, int b, float& t, float& u, float& v) {
      return s.block->samples().block().fetch(tile, a, b, t, u, v);
    });
    break;
  case hb::CodecId::haar:
    run_decode(state, picks, [&](std::size_t tile, int a, int b, float& t, float& u, float& v) {
      return s.haar->samples().haar().fetch(tile, a, b, t, u, v);
    });
    break;
  default:
    run_decode(state, picks, [&](std::size_t tile, int a, int b, float& t, float& u, float& v) {
      return raw_fetch(*s.raw, tile, a, b, t, u, v);
    });
  }
}

void query_bench(benchmark::State& state, hb::CodecId codec) {
  const Setup& s = setup();
  const hb::HapticBox& box = codec == hb::CodecId::block ? *s.block : codec == hb::CodecId::haar ? *s.haar : *s.raw;
  std::size_t i = 0;
  float acc = 0.f;
  const hb::ForceLaw law;
  for (auto _ : state) {
    acc += box.query(s.probes[i], law).depth;
    if (++i == s.probes.size()) i = 0;
  }
  benchmark::DoNotOptimize(acc);
}

// Batched queries of the raw box at one instruction-set level of query_many's lanes
// (query_lanes.cpp), 1000 probes a call: time per query = 1 / items_per_second.
void query_many_bench(benchmark::State& state, hb::LaneIsa isa) {
  const Setup& s = setup();
  hb::set_lane_isa_cap(isa);
  if (hb::lane_isa() != isa) {
    hb::set_lane_isa_cap(hb::LaneIsa::avx512);
    state.SkipWithError("this CPU lacks the instruction set");
    return;
  }
  constexpr std::size_t kBatch = 1000;
  std::vector<hb::Contact> out(kBatch);
  const hb::ForceLaw law;
  std::size_t first = 0;
  for (auto _ : state) {
    s.raw->query_many(s.probes.data() + first, kBatch, law, out.data());
    benchmark::DoNotOptimize(out.data());
    first = first + 2 * kBatch <= s.probes.size() ? first + kBatch : 0;
  }
  state.SetItemsProcessed(std::int64_t(state.iterations()) * std::int64_t(kBatch));
  hb::set_lane_isa_cap(hb::LaneIsa::avx512);
}

} // namespace

BENCHMARK_CAPTURE(decode_bench, raw_random, hb::CodecId::none, false);
BENCHMARK_CAPTURE(decode_bench, block_random, hb::CodecId::block, false);
BENCHMARK_CAPTURE(decode_bench, haar_random, hb::CodecId::haar, false);
BENCHMARK_CAPTURE(decode_bench, raw_cached, hb::CodecId::none, true);
BENCHMARK_CAPTURE(decode_bench, block_cached, hb::CodecId::block, true);
BENCHMARK_CAPTURE(decode_bench, haar_cached, hb::CodecId::haar, true);
BENCHMARK_CAPTURE(query_bench, raw, hb::CodecId::none);
BENCHMARK_CAPTURE(query_bench, block, hb::CodecId::block);
BENCHMARK_CAPTURE(query_bench, haar, hb::CodecId::haar);
BENCHMARK_CAPTURE(query_many_bench, raw_sse2, hb::LaneIsa::sse2);
BENCHMARK_CAPTURE(query_many_bench, raw_avx, hb::LaneIsa::avx);
BENCHMARK_CAPTURE(query_many_bench, raw_avx2, hb::LaneIsa::avx2);
BENCHMARK_CAPTURE(query_many_bench, raw_avx512, hb::LaneIsa::avx512);

BENCHMARK_MAIN();
