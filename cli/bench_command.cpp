// hapticbox bench BOX MESH [--samples N] [--json]: box and exact query time on the same probes
// (one query at a time, and batched through query_many), the tail of single queries (p99,
// p99.9, max), a verdict per order (faster or slower than exact, by how much), and how many
// boxes a query meets (with the time of queries meeting 1, 2, 3+ boxes).
#include "cli_support.h"
#include "evaluation/comparison.h"
#include "perceptible_text.h"
#include "figure_text.h"
#include "commands.h"
#include "tool_options.h"
#include "evaluation/probe_sampling.h"
#include "evaluation/query_timing.h"
#include "exact/exact_query.h"
#include "store/box_file.h"
#include <algorithm>
#include <filesystem>
#include <iomanip>
#include <iostream>
#include <sstream>
#include <string>

namespace {

struct BenchOpts {
  hb::cli::ModelArgs model;
  std::string box, mesh;
  std::size_t samples = 20000;
  int rounds = 5;
  hb::ProbeOptions probes;
  hb::cli::WorkspaceArgs workspace;
  hb::ForceLaw law;  // the workspace's, set in the callback
  bool json = false;
  bool no_huge_pages = false;
  std::string route = "auto";
  hb::cli::ToolArgs tool;
};

// Strokes: what a 1 kHz loop sees of a hand gliding over the model (consecutive probes
// 1 ms apart, about 15-30 mm/s on a 200 mm model), one query at a time.
constexpr std::size_t kStrokeSteps = 1000;
constexpr float kStrokeRadius = 0.02f;

// The median ns per query of each order, box and exact.
struct OrderTimes {
  double box_ns = 0, exact_ns = 0, box_many_ns = 0, exact_many_ns = 0, box_coherent_ns = 0, exact_coherent_ns = 0;
  double box_stroke_ns = 0, box_stroke_stateless_ns = 0, exact_stroke_ns = 0;
  // A scene whose strokes Embree over the full mesh answers (BoxScene::stroke_route): the
  // cells' walk along the same strokes with a query state, for comparison (0: no such route).
  double box_stroke_cells_ns = 0;
  double state_share = 0;  // strokes' ticks answered from the query state
  // A raw block-coded box: strokes' ticks that blended the kept decoded quads, and that
  // crossed the last settled quadric (DecodedQuads).
  double quads_share = 0, quadric_share = 0;
};

// The box and exact in four orders, interleaved so machine noise hits both alike: random one
// at a time, batched (query_many), coherent (along a space-filling curve) and along strokes.
OrderTimes time_orders(const hb::BoxScene& scene, const hb::ExactQuery& exact, const std::vector<hb::Segment>& probes,
                       const std::vector<hb::Segment>& strokes, const hb::ForceLaw& law, int rounds) {
  OrderTimes t;
  auto probes_coherent = probes;
  hb::sort_probes_coherently(probes_coherent);
  t.box_ns = hb::median_query_ns(scene, probes, law, rounds);
  t.exact_ns = hb::median_query_ns(exact, probes, law, rounds);
  t.box_many_ns = hb::median_query_many_ns(scene, probes, law, rounds);
  t.exact_many_ns = hb::median_query_many_ns(exact, probes, law, rounds);
  t.box_coherent_ns = hb::median_query_ns(scene, probes_coherent, law, rounds);
  t.exact_coherent_ns = hb::median_query_ns(exact, probes_coherent, law, rounds);
  // The box along strokes as a servo loop queries it: one probe with its query state
  // (BoxScene::query with a SceneQueryState: on the cells route a walk that starts where
  // the last full walk was still a cell from the surface, on the boxes' route a bounded
  // walk from the last contact), and
  // without it (every tick the full query) for comparison.
  hb::SceneProbe probe(scene);
  t.box_stroke_ns = hb::median_query_ns(probe, strokes, law, rounds);
  const double ticks = double(probe.state().from_state + probe.state().full);
  if (ticks > 0) {
    t.state_share = double(probe.state().from_state) / ticks;
    t.quads_share = double(probe.state().quads.reused) / ticks;
    t.quadric_share = double(probe.state().quads.settled.reused) / ticks;
  }
  t.box_stroke_stateless_ns = hb::median_query_ns(scene, strokes, law, rounds);
  t.exact_stroke_ns = hb::median_query_ns(exact, strokes, law, rounds);
  if (strokes_by_full_mesh(scene)) {
    hb::SceneParts parts = scene.parts();
    parts.stroke.reset();
    const hb::BoxScene cells(std::move(parts));
    hb::SceneProbe walk(cells);
    t.box_stroke_cells_ns = hb::median_query_ns(walk, strokes, law, rounds);
  }
  return t;
}

// Boxes met per query, box queries per probe, and the box time of the queries that meet
// exactly 1, 2, 3+ boxes.
struct BoxesMet {
  nlohmann::json by_met = nlohmann::json::array();
  double mean_met = 0, mean_asked = 0, share_one = 0;
  std::size_t asked_max = 0;
  std::size_t asked_hist[5] = {0, 0, 0, 0, 0};
};

BoxesMet count_boxes_met(const hb::BoxScene& scene, const std::vector<hb::Segment>& probes, const hb::ForceLaw& law,
                         int rounds) {
  BoxesMet b;
  std::vector<std::vector<hb::Segment>> by_met(4);
  double met_sum = 0.0, asked_sum = 0.0;
  std::size_t asked_one = 0;
  for (const hb::Segment& s : probes) {
    const std::size_t asked = scene.box_queries(s, law);
    asked_sum += double(asked);
    b.asked_max = std::max(b.asked_max, asked);
    asked_one += asked <= 1 ? 1 : 0;
    ++b.asked_hist[std::min<std::size_t>(asked, 4)];
    const std::size_t met = boxes_met(scene, s);
    met_sum += double(met);
    by_met[std::min<std::size_t>(met, 3)].push_back(s);
  }
  for (std::size_t k = 1; k < by_met.size(); ++k) {
    if (by_met[k].size() < 100) continue;
    const double ns = hb::median_query_ns(scene, by_met[k], law, rounds);
    b.by_met.push_back({{"boxes_met", k == 3 ? "3+" : std::to_string(k)},
                        {"queries", by_met[k].size()},
                        {"box_ns", ns},
                        {"box_queries_per_second", ns > 0 ? 1e9 / ns : 0.0}});
  }
  b.mean_met = probes.empty() ? 0.0 : met_sum / double(probes.size());
  b.mean_asked = probes.empty() ? 0.0 : asked_sum / double(probes.size());
  b.share_one = probes.empty() ? 0.0 : double(asked_one) / double(probes.size());
  return b;
}

nlohmann::json tail_json(const hb::QueryLatency& t) {
  return nlohmann::json{{"p50_ns", t.p50_ns}, {"p99_ns", t.p99_ns}, {"p999_ns", t.p999_ns},
                        {"max_ns", t.max_ns}, {"queries", t.queries}, {"clock_ns", t.clock_ns},
                        {"probe_p50_ns", t.probe_p50_ns}, {"probe_p99_ns", t.probe_p99_ns},
                        {"probe_p999_ns", t.probe_p999_ns}, {"probe_max_ns", t.probe_max_ns}};
}

// Everything a bench measured, for its JSON and its text.
struct BenchResult {
  OrderTimes t;
  hb::QueryLatency box_tail, exact_tail;
  hb::ComparisonStats felt, felt_strokes;
  BoxesMet met;
  std::size_t strokes = 0;
  const char* isa_name = "";
  bool lanes = false, walks = false;
  nlohmann::json verdicts;
};

nlohmann::json bench_json(const BenchOpts& o, const hb::TriangleMesh& mesh, const hb::BoxScene& scene, std::size_t probes,
                          const BenchResult& r, const hb::Workspace& ws, const hb::PerceptualJudge& judge) {
  const OrderTimes& t = r.t;
  const BoxesMet& m = r.met;
  return {{"box", o.box},
          {"mesh", o.mesh},
          {"triangles", mesh.triangle_count()},
          {"samples", probes},
          {"box_ns", t.box_ns},
          {"exact_ns", t.exact_ns},
          {"speedup", t.box_ns > 0 ? t.exact_ns / t.box_ns : 0.0},
          {"box_queries_per_second", t.box_ns > 0 ? 1e9 / t.box_ns : 0.0},
          {"box_batched_ns", t.box_many_ns},
          {"exact_batched_ns", t.exact_many_ns},
          {"speedup_batched", t.box_many_ns > 0 ? t.exact_many_ns / t.box_many_ns : 0.0},
          {"batched_isa", r.isa_name},
          {"batched_lanes", r.lanes},
          {"batched_walks_side_by_side", r.walks},
          {"box_coherent_ns", t.box_coherent_ns},
          {"exact_coherent_ns", t.exact_coherent_ns},
          {"speedup_coherent", t.box_coherent_ns > 0 ? t.exact_coherent_ns / t.box_coherent_ns : 0.0},
          {"box_stroke_ns", t.box_stroke_ns},
          {"box_stroke_stateless_ns", t.box_stroke_stateless_ns},
          {"stroke_route", hb::route_name(scene.stroke_route())},
          {"box_stroke_cells_ns", t.box_stroke_cells_ns},
          {"stroke_share_from_state", t.state_share},
          {"stroke_share_quads_kept", t.quads_share},
          {"stroke_share_quadric_kept", t.quadric_share},
          {"exact_stroke_ns", t.exact_stroke_ns},
          {"speedup_stroke", t.box_stroke_ns > 0 ? t.exact_stroke_ns / t.box_stroke_ns : 0.0},
          {"box_single_tail", tail_json(r.box_tail)},
          {"exact_single_tail", tail_json(r.exact_tail)},
          {"verdict", r.verdicts},
          {"boxes", scene.parts().boxes.size()},
          {"mean_boxes_met", m.mean_met},
          {"scene_grid", scene.parts().grid != nullptr},
          {"route", hb::route_name(scene.route())},
          {"mean_box_queries", m.mean_asked},
          {"max_box_queries", m.asked_max},
          {"share_at_most_one_box_query", m.share_one},
          {"probes_by_box_queries", {m.asked_hist[0], m.asked_hist[1], m.asked_hist[2], m.asked_hist[3], m.asked_hist[4]}},
          {"by_boxes_met", m.by_met},
          {"perceptible_share", r.felt.perceptible_share},
          {"perceptible_probes", r.felt.perceptible},
          {"stroke_ticks", r.felt_strokes.samples},
          {"perceptible_stroke_share", r.felt_strokes.perceptible_share},
          {"workspace", hb::workspace_json(ws, judge)}};
}

void print_bench(const BenchOpts& o, const hb::TriangleMesh& mesh, const hb::BoxScene& scene, std::size_t probes,
                 const BenchResult& r, const hb::Workspace& ws) {
  const OrderTimes& t = r.t;
  const BoxesMet& m = r.met;
  const hb::QueryLatency& box_tail = r.box_tail;
  const hb::QueryLatency& exact_tail = r.exact_tail;
  std::cout << std::fixed << std::setprecision(1) << "bench " << o.box << " (" << mesh.triangle_count()
            << " triangles, " << probes << " probes, one core, random order, route " << hb::route_name(scene.route()) << ")\n"
            << "  haptic box  " << t.box_ns << " ns/query (" << 1e9 / t.box_ns / 1e6 << " M queries/s)\n"
            << "  exact       " << t.exact_ns << " ns/query\n"
            << "  box is      " << hb::speed_verdict(t.box_ns, t.exact_ns) << " (same probes, one at a time)\n"
            << "  accuracy    " << hb::perceptible_headline(r.felt) << "; along the strokes "
            << hb::percent(r.felt_strokes.perceptible_share) << " of " << r.felt_strokes.samples << " ticks\n"
            << "  workspace   " << ws.describe() << "\n"
            << std::setprecision(0) << "  single-query tail (" << box_tail.queries
            << " queries each timed alone, clock pair " << box_tail.clock_ns << " ns subtracted):\n"
            << "    haptic box  p50 " << box_tail.p50_ns << "  p99 " << box_tail.p99_ns << "  p99.9 "
            << box_tail.p999_ns << "  max " << box_tail.max_ns << " ns\n"
            << "    exact       p50 " << exact_tail.p50_ns << "  p99 " << exact_tail.p99_ns << "  p99.9 "
            << exact_tail.p999_ns << "  max " << exact_tail.max_ns << " ns\n"
            << "    p99: " << r.verdicts["p99"].get<std::string>() << "; p99.9: " << r.verdicts["p999"].get<std::string>()
            << "\n"
            << "  each probe's median over the " << o.rounds
            << " rounds (the probes' own tail; the machine's one-off stalls filtered out):\n"
            << "    haptic box  p50 " << box_tail.probe_p50_ns << "  p99 " << box_tail.probe_p99_ns << "  p99.9 "
            << box_tail.probe_p999_ns << "  max " << box_tail.probe_max_ns << " ns\n"
            << "    exact       p50 " << exact_tail.probe_p50_ns << "  p99 " << exact_tail.probe_p99_ns << "  p99.9 "
            << exact_tail.probe_p999_ns << "  max " << exact_tail.probe_max_ns << " ns\n"
            << "    p99.9: " << r.verdicts["probe_p999"].get<std::string>() << "\n"
            << std::setprecision(1) << "batched (query_many, 1000 probes a call, random order; "
            << (r.lanes   ? std::string("queries side by side in ") + r.isa_name + " lanes"
                : r.walks ? std::string("the cells route's walks side by side, each prefetching its next step")
                          : std::string("one query at a time: SIMD lanes serve one raw unrefined box, side-by-side "
                                        "walks a surface larger than the last-level cache"))
            << "):\n"
            << "  haptic box  " << t.box_many_ns << " ns/query, exact " << t.exact_many_ns
            << " ns/query (exact traces the batch as one stream of rays): box is "
            << hb::speed_verdict(t.box_many_ns, t.exact_many_ns) << "\n"
            << std::setprecision(1) << "coherent order (probes sorted along a space-filling curve, as a trajectory):\n"
            << "  haptic box  " << t.box_coherent_ns << " ns/query, exact " << t.exact_coherent_ns << " ns/query: box is "
            << hb::speed_verdict(t.box_coherent_ns, t.exact_coherent_ns) << "\n"
            << std::setprecision(1) << "strokes (" << r.strokes / kStrokeSteps
            << " hand-like strokes: circles of 2% of the diagonal, 1000 probes 1 ms apart, as a 1 kHz loop):\n"
            << "  haptic box  " << t.box_stroke_ns << " ns/query, exact " << t.exact_stroke_ns << " ns/query: box is "
            << hb::speed_verdict(t.box_stroke_ns, t.exact_stroke_ns) << "\n"
            << std::setprecision(1);
  if (t.box_stroke_cells_ns > 0) {
    std::cout << "  answered by exact Embree over the full mesh (the bake's stroke route: it measured Embree faster "
                 "along strokes than the cells); the cells' walk with a query state "
              << t.box_stroke_cells_ns << " ns/query";
  } else {
    std::cout << "  with a query state per probe (" << 100.0 * t.state_share << "% of ticks from the state";
    if (t.quads_share > 0)
      std::cout << "; decoded quads kept on " << 100.0 * t.quads_share << "%, the last settled quadric crossed on "
                << 100.0 * t.quadric_share << "%";
    std::cout << ")";
  }
  std::cout << "; without a state " << t.box_stroke_stateless_ns << " ns/query\n"
            << std::setprecision(1) << "  boxes       " << scene.parts().boxes.size() << ", met per query " << m.mean_met
            << " on average; box queries per probe " << std::setprecision(2) << m.mean_asked << " on average (max "
            << m.asked_max << ", " << std::setprecision(1) << 100.0 * m.share_one << "% of probes at most one), "
            << (scene.parts().grid ? "routed by the scene grid" : "no scene grid") << "\n"
            << "    probes by box queries: 0: " << m.asked_hist[0] << ", 1: " << m.asked_hist[1] << ", 2: " << m.asked_hist[2]
            << ", 3: " << m.asked_hist[3] << ", 4+: " << m.asked_hist[4] << "\n";
  for (const auto& k : m.by_met)
    std::cout << "    meeting " << k["boxes_met"].get<std::string>() << " box(es): " << std::setprecision(1)
              << k["box_ns"].get<double>() << " ns/query (" << k["queries"].get<std::size_t>() << " queries)\n";
  const int faster = int(hb::compare_speed(t.box_ns, t.exact_ns) == hb::SpeedComparison::faster) +
                     int(hb::compare_speed(t.box_many_ns, t.exact_many_ns) == hb::SpeedComparison::faster) +
                     int(hb::compare_speed(t.box_coherent_ns, t.exact_coherent_ns) == hb::SpeedComparison::faster) +
                     int(hb::compare_speed(t.box_stroke_ns, t.exact_stroke_ns) == hb::SpeedComparison::faster);
  std::cout << "verdict: the haptic box is faster than exact in " << faster << " of 4 orders: one at a time "
            << hb::speed_verdict(t.box_ns, t.exact_ns) << "; batched " << hb::speed_verdict(t.box_many_ns, t.exact_many_ns)
            << "; coherent " << hb::speed_verdict(t.box_coherent_ns, t.exact_coherent_ns) << "; strokes "
            << hb::speed_verdict(t.box_stroke_ns, t.exact_stroke_ns) << "\n";
}

void run_bench(BenchOpts& o) {
  // Measurement-only (HB_MEASURE): no-huge-pages (query the file mapping, not a copy of the
  // tables in huge pages).
  o.no_huge_pages = hb::cli::measurement("no-huge-pages").has_value();
  hb::LoadOptions load;
  load.huge_pages = !o.no_huge_pages;
  hb::BoxScene scene = hb::load_box_file(o.box, load);
  hb::cli::apply_route(scene, o.route);
  const hb::TriangleMesh mesh = hb::cli::load_mesh(o.mesh, o.model);
  const hb::ExactQuery exact(mesh);
  const auto probes = hb::sample_probes(mesh, o.samples, o.probes);
  const hb::Workspace ws = o.workspace.workspace(mesh.bounds().diagonal());
  const hb::PerceptualJudge judge = o.workspace.judge();
  o.law = ws.law();
  if (o.tool.given()) {
    // A tool with volume: its ticks along slides, timed and judged (the point probes are not run).
    // The distance-field peer at the box file's memory.
    std::error_code ec;
    const auto file_bytes = std::filesystem::file_size(o.box, ec);
    const hb::cli::ToolRun run = hb::cli::run_tool(o.tool, scene, exact, mesh, ws, judge, true, o.rounds,
                                                   ec ? std::size_t(scene.bytes().memory) : std::size_t(file_bytes));
    if (o.json) {
      nlohmann::json j = hb::cli::tool_json(run);
      j["box"] = o.box;
      j["mesh"] = o.mesh;
      j["triangles"] = mesh.triangle_count();
      j["route"] = hb::route_name(scene.route());
      j["workspace"] = hb::workspace_json(ws, judge);
      hb::cli::print_json(j);
    } else {
      std::cout << "bench " << o.box << " (" << mesh.triangle_count() << " triangles, route "
                << hb::route_name(scene.route()) << ", one core)\n  workspace   " << ws.describe() << "\n";
      hb::cli::print_tool_run(run, std::cout);
    }
    return;
  }
  const auto strokes = hb::sample_strokes(mesh, std::max<std::size_t>(1, o.samples / kStrokeSteps), kStrokeSteps,
                                          kStrokeRadius, o.probes);
  BenchResult r;
  r.t = time_orders(scene, exact, probes, strokes, o.law, o.rounds);
  r.strokes = strokes.size();
  // What the times buy: the share a hand would tell apart from exact, on the random probes
  // and on the strokes' ticks (the same answers with or without the query state).
  r.felt = hb::compare_queries(scene, exact, probes, o.law, mesh.bounds().diagonal(), nullptr, nullptr, nullptr, judge);
  r.felt_strokes = hb::compare_queries(scene, exact, strokes, o.law, mesh.bounds().diagonal(), nullptr, nullptr,
                                       nullptr, judge);
  // The tail of single queries (random order), each query timed on its own.
  r.box_tail = hb::single_query_latency(scene, probes, o.law, o.rounds);
  r.exact_tail = hb::single_query_latency(exact, probes, o.law, o.rounds);
  r.met = count_boxes_met(scene, probes, o.law, o.rounds);
  r.isa_name = hb::lane_isa_name(hb::lane_isa());
  // query_many runs queries side by side in SIMD lanes for one raw, unrefined box only ...
  const auto& boxes = scene.parts().boxes;
  r.lanes = boxes.size() == 1 && boxes[0].has_table() && boxes[0].codec() == hb::CodecId::none && !boxes[0].refines() &&
            scene.route() != hb::SceneRoute::embree;
  // ... and, on the cells route, runs several queries' walks side by side on a surface
  // larger than the last-level cache.
  r.walks = scene.parts().grid && scene.route() == hb::SceneRoute::cells && scene.cells()->walks_side_by_side();
  const OrderTimes& t = r.t;
  // The verdict of each order (hb::speed_verdict: the text's words too).
  r.verdicts = {{"random", hb::speed_verdict(t.box_ns, t.exact_ns)},
                {"batched", hb::speed_verdict(t.box_many_ns, t.exact_many_ns)},
                {"coherent", hb::speed_verdict(t.box_coherent_ns, t.exact_coherent_ns)},
                {"strokes", hb::speed_verdict(t.box_stroke_ns, t.exact_stroke_ns)},
                {"p99", hb::speed_verdict(r.box_tail.p99_ns, r.exact_tail.p99_ns)},
                {"p999", hb::speed_verdict(r.box_tail.p999_ns, r.exact_tail.p999_ns)},
                {"probe_p999", hb::speed_verdict(r.box_tail.probe_p999_ns, r.exact_tail.probe_p999_ns)}};
  if (o.json) hb::cli::print_json(bench_json(o, mesh, scene, probes.size(), r, ws, judge));
  else print_bench(o, mesh, scene, probes.size(), r, ws);
}

} // namespace

void add_bench_command(CLI::App& app) {
  auto* cmd = app.add_subcommand("bench", "Time box queries against exact Embree queries (one core)");
  auto opts = std::make_shared<BenchOpts>();
  hb::cli::add_model_options(*cmd, opts->model);
  cmd->add_option("BOX", opts->box, "Box file (.hbox)")->required();
  cmd->add_option("MESH", opts->mesh, "The mesh the box was baked from")->required();
  hb::cli::add_probe_options(*cmd, opts->samples, opts->probes.seed);
  cmd->add_option("--rounds", opts->rounds, "Passes over the probes")->check(CLI::Range(1, 1000))->capture_default_str();
  cmd->add_flag("--json", opts->json, "Print JSON");
  hb::cli::add_route_option(*cmd, opts->route);
  hb::cli::add_workspace_options(*cmd, opts->workspace);
  hb::cli::add_tool_options(*cmd, opts->tool);
  cmd->callback([opts] { run_bench(*opts); });
}
