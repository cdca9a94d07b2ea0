// Where the time of a scene query goes (docs/speed.md, "The refined scene path"): the stages
// of BoxScene::query timed apart on the same probes, in random order, one core.
//   hb_bench_scene_profile BOX MESH [google benchmark flags]
// Stages: exact Embree; the whole scene query; the grid routing alone (handle cell and the
// walk to the first surface cell); the first routed box's query without refinement (geometry,
// sample fetch, codec decode, blend); the same box with refinement (adds the candidates'
// triangles, their exact tests and the walk).
#include "evaluation/probe_sampling.h"
#include "exact/exact_query.h"
#include "store/box_file.h"
#include "mesh/mesh_io.h"
#include <benchmark/benchmark.h>
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <memory>
#include <random>

namespace {

struct Fixture {
  hb::TriangleMesh mesh;
  hb::BoxScene scene;
  std::unique_ptr<hb::ExactQuery> exact;
  std::vector<hb::Segment> probes;
  std::vector<std::uint32_t> first_box;  // the first box the grid routes each probe to (or UINT32_MAX)
  hb::ForceLaw law;
};
Fixture* g = nullptr;

std::uint32_t routed_box(const hb::SceneGrid& grid, const hb::Segment& s) {
  std::uint32_t box = UINT32_MAX;
  if (grid.code_at(s.start) != hb::SceneGrid::kOutside) return box;
  grid.walk_surface(s.start, s.end, [&](std::uint16_t code, float) {
    if (code < hb::SceneGrid::kFirstSurface) return true;
    box = *grid.boxes_begin(code);
    return false;
  });
  return box;
}

void scene_query(benchmark::State& state) {
  std::size_t i = 0;
  for (auto _ : state) {
    benchmark::DoNotOptimize(g->scene.query(g->probes[i], g->law));
    if (++i == g->probes.size()) i = 0;
  }
}
void exact_query(benchmark::State& state) {
  std::size_t i = 0;
  for (auto _ : state) {
    benchmark::DoNotOptimize(g->exact->query(g->probes[i], g->law));
    if (++i == g->probes.size()) i = 0;
  }
}
void grid_routing(benchmark::State& state) {
  std::size_t i = 0;
  const hb::SceneGrid& grid = *g->scene.parts().grid;
  for (auto _ : state) {
    benchmark::DoNotOptimize(routed_box(grid, g->probes[i]));
    if (++i == g->probes.size()) i = 0;
  }
}
// The cells route's first crossing alone (no shading, no force): the clearance walk from the
// handle and the triangles of the surface cells (and sub-cells) it passes.
void cells_walk(benchmark::State& state) {
  std::size_t i = 0;
  const hb::SurfaceCells& sc = *g->scene.cells();
  for (auto _ : state) {
    float s = 0.f;
    bool front = false;
    std::uint32_t id = hb::kNoTriangle;
    benchmark::DoNotOptimize(sc.first_crossing_along(g->probes[i].start, g->probes[i].end, 1.f, s, front, id));
    benchmark::DoNotOptimize(s);
    if (++i == g->probes.size()) i = 0;
  }
}
// The scene's batched query (query_many, 1000 probes a call, as `bench`'s batched order); the
// time is per probe.
void scene_many(benchmark::State& state) {
  constexpr std::size_t kBatch = 1000;
  std::vector<hb::Contact> out(kBatch);
  std::size_t i = 0;
  for (auto _ : state) {
    const std::size_t n = std::min(kBatch, g->probes.size() - i);
    g->scene.query_many(g->probes.data() + i, n, g->law, out.data());
    benchmark::DoNotOptimize(out.data());
    i = i + n == g->probes.size() ? 0 : i + n;
  }
  state.SetItemsProcessed(state.iterations() * std::int64_t(kBatch));
}
// The scene and exact on the first 64 probes only: caches warm, as on a stroke.
void warm_query(benchmark::State& state, bool exact) {
  std::size_t i = 0;
  for (auto _ : state) {
    benchmark::DoNotOptimize(exact ? g->exact->query(g->probes[i], g->law) : g->scene.query(g->probes[i], g->law));
    i = (i + 1) & 63;
  }
}
void box_query(benchmark::State& state, hb::Refine refine) {
  std::size_t i = 0;
  for (auto _ : state) {
    while (g->first_box[i] == UINT32_MAX) i = (i + 1) % g->probes.size();
    hb::Contact c;
    float along = 0.f;
    benchmark::DoNotOptimize(g->scene.parts().boxes[g->first_box[i]].query_into(g->probes[i], g->law, c, along, refine));
    if (++i == g->probes.size()) i = 0;
  }
}

} // namespace

int main(int argc, char** argv) {
  benchmark::Initialize(&argc, argv);
  if (argc < 3) {
    std::fprintf(stderr, "usage: hb_bench_scene_profile BOX MESH [benchmark flags]\n");
    return 2;
  }
  static Fixture f;
  g = &f;
  f.mesh = hb::read_mesh(argv[2]);
  hb::LoadOptions load;
  load.huge_pages = true;
  f.scene = hb::load_box_file(argv[1], load);
  f.exact = std::make_unique<hb::ExactQuery>(f.mesh);
  f.probes = hb::sample_probes(f.mesh, 20000);
  std::shuffle(f.probes.begin(), f.probes.end(), std::mt19937(7));
  std::size_t routed = 0;
  for (const hb::Segment& s : f.probes) {
    f.first_box.push_back(f.scene.parts().grid ? routed_box(*f.scene.parts().grid, s) : 0u);
    routed += f.first_box.back() != UINT32_MAX;
  }
  std::printf("%zu of %zu probes routed by the grid to a first box\n", routed, f.probes.size());
  if (f.scene.parts().grid) {
    // Where the costly probes (4 or more box queries) start: the handle's cell, and whether
    // the segment crosses surface cells at all.
    std::size_t costly = 0, by_code[4] = {0, 0, 0, 0}, no_surface = 0;
    for (const hb::Segment& s : f.probes) {
      if (f.scene.box_queries(s, f.law) < 4) continue;
      ++costly;
      const std::uint16_t code = f.scene.parts().grid->code_at(s.start);
      ++by_code[std::min<std::uint16_t>(code, hb::SceneGrid::kFirstSurface)];
      bool crossed = false;
      f.scene.parts().grid->walk_surface(s.start, s.end, [&](std::uint16_t, float) { return !(crossed = true); });
      no_surface += crossed ? 0 : 1;
    }
    std::printf("%zu probes with 4+ box queries; handle cell outside %zu, inside %zu, unknown %zu, surface %zu; "
                "crossing no surface cell %zu\n",
                costly, by_code[0], by_code[1], by_code[2], by_code[3], no_surface);
  }
  if (f.scene.parts().grid) {
    // The tail of single queries without the machine's noise: each probe's median time over
    // 5 rounds of the whole set in random order (so each query finds the caches as a random
    // query does), and where the slowest 1% and 0.1% go: handle cell and box queries.
    constexpr int kRounds = 5;
    std::vector<std::vector<double>> t(f.probes.size());
    volatile float sink = 0.f;
    for (int r = 0; r < kRounds; ++r)
      for (std::size_t i = 0; i < f.probes.size(); ++i) {
        const auto t0 = std::chrono::steady_clock::now();
        sink = sink + f.scene.query(f.probes[i], f.law).depth;
        const auto t1 = std::chrono::steady_clock::now();
        t[i].push_back(std::chrono::duration<double, std::nano>(t1 - t0).count());
      }
    std::vector<std::pair<double, std::size_t>> med;
    for (std::size_t i = 0; i < t.size(); ++i) {
      std::nth_element(t[i].begin(), t[i].begin() + kRounds / 2, t[i].end());
      med.push_back({t[i][kRounds / 2], i});
    }
    std::sort(med.begin(), med.end());
    const auto at = [&](double q) { return med[std::min(med.size() - 1, std::size_t(q * double(med.size())))].first; };
    std::printf("per-probe median of %d rounds: p50 %.0f ns, p90 %.0f, p99 %.0f, p99.9 %.0f, max %.0f\n", kRounds,
                at(0.5), at(0.9), at(0.99), at(0.999), med.back().first);
    for (double top : {0.01, 0.001}) {
      const std::size_t first = std::size_t((1.0 - top) * double(med.size()));
      std::size_t by_code[4] = {0, 0, 0, 0}, by_asked[6] = {0, 0, 0, 0, 0, 0}, contacts = 0;
      for (std::size_t k = first; k < med.size(); ++k) {
        const hb::Segment& s = f.probes[med[k].second];
        ++by_code[std::min<std::uint16_t>(f.scene.parts().grid->code_at(s.start), hb::SceneGrid::kFirstSurface)];
        ++by_asked[std::min<std::size_t>(f.scene.box_queries(s, f.law), 5)];
        contacts += f.scene.query(s, f.law).contact ? 1 : 0;
      }
      std::printf("slowest %.1f%% (%zu probes, from %.0f ns): handle outside %zu, inside %zu, unknown %zu, surface %zu; "
                  "box queries 0:%zu 1:%zu 2:%zu 3:%zu 4:%zu 5+:%zu; contacts %zu\n",
                  top * 100.0, med.size() - first, med[first].first, by_code[0], by_code[1], by_code[2], by_code[3],
                  by_asked[0], by_asked[1], by_asked[2], by_asked[3], by_asked[4], by_asked[5], contacts);
    }
  }
  benchmark::RegisterBenchmark("exact", exact_query);
  benchmark::RegisterBenchmark("scene", scene_query);
  benchmark::RegisterBenchmark("scene_many", scene_many);
  benchmark::RegisterBenchmark("exact_warm", warm_query, true);
  benchmark::RegisterBenchmark("scene_warm", warm_query, false);
  if (f.scene.parts().grid) benchmark::RegisterBenchmark("grid_routing", grid_routing);
  if (f.scene.parts().grid && f.scene.cells()) benchmark::RegisterBenchmark("cells_walk", cells_walk);
  benchmark::RegisterBenchmark("first_box_blend_only", box_query, hb::Refine::off);
  benchmark::RegisterBenchmark("first_box_refined", box_query, hb::Refine::all);
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
