// The sweep:
//  1. sample the probes once (the same segments for every method);
//  2. measure each reference: accuracy against the first reference, median query time;
//  3. for each configuration: load the cached box or bake it (and cache it), measure it the
//     same way, drop it before the next one (tables of m=64 n=16 are 600 MB);
//  4. mark the Pareto front.
// Across ranks (SweepOptions::communicator) every step is shared: bakes and evaluations split
// their work over all ranks, each configuration's timing runs on one rank (they take turns)
// and is broadcast; rank 0 keeps the tally of what each rank did.
#include "recipe/sweep.h"
#include "errors.h"
#include "evaluation/query_timing.h"
#include "recipe/box_cache.h"
#include "codec/codec.h"
#include "parallel/byte_buffer.h"
#include <algorithm>
#include <chrono>
#include <cmath>
#include <optional>

namespace hb {
namespace {

// The raw scene compressed with `codec` at the codec's default error bound.
BoxScene compress_scene(const BoxScene& raw, const std::string& codec) {
  CodecOptions options;
  options.codec = parse_codec(codec);
  return raw.compressed(options);
}

} // namespace

void check_sweep_config(const SweepConfig& config) {
  if (config.m < 2 || config.n < 2) throw InvalidInput("sweep: m and n must be >= 2");
  if (config.codec == "none") return;
  (void)parse_codec(config.codec);  // throws hb::InvalidInput naming the accepted values
}

std::vector<SweepConfig> sweep_grid(const std::vector<int>& ms, const std::vector<int>& ns,
                                    const std::vector<std::string>& codecs, const std::vector<bool>& refines) {
  std::vector<SweepConfig> grid;
  for (int m : ms)
    for (int n : ns)
      for (const std::string& c : codecs)
        for (bool r : refines) grid.push_back({m, n, c, r});
  return grid;
}

void mark_pareto_front(std::vector<SweepRow>& rows) {
  for (SweepRow& r : rows) {
    r.pareto = true;
    for (const SweepRow& o : rows) {
      // Accuracy is what a hand feels first (the perceptible share), the median relative
      // error among rows a hand tells apart equally.
      const auto acc = [](const SweepRow& x) { return std::make_pair(x.perceptible_share, x.force_error_median); };
      const bool no_worse = o.query_ns <= r.query_ns && acc(o) <= acc(r);
      const bool better = o.query_ns < r.query_ns || acc(o) < acc(r);
      if (&o != &r && no_worse && better) {
        r.pareto = false;
        break;
      }
    }
  }
}

std::vector<SweepRow> run_sweep(const TriangleMesh& mesh, const SourceInfo& source, const std::vector<SweepReference>& references,
                                const SweepOptions& options) {
  if (references.empty() || !references.front().query)
    throw InvalidInput("run_sweep: needs the exact reference first");
  for (const SweepConfig& c : options.configs) check_sweep_config(c);
  const std::optional<BoxCache> cache =
      options.cache_dir.empty() ? std::nullopt : std::optional<BoxCache>(BoxCache(options.cache_dir));

  // The pieces are cut once; every configuration bakes the same ones.
  const std::vector<std::uint32_t> piece_of_triangle = resolve_piece_ids(mesh, options.recipe.pieces);
  const std::vector<Segment> probes = sample_probes(mesh, options.samples, options.probes);
  const float diagonal = mesh.bounds().diagonal();
  const ContactQuery& exact = *references.front().query;
  const double steps = double(references.size() + 2 * options.configs.size() + (options.default_bake ? 2 : 0));
  double done = 0.0;
  auto step = [&](double amount) {
    done += amount;
    if (options.progress && !options.progress(std::min(1.0, done / steps))) throw Cancelled("run_sweep: cancelled");
  };

  Communicator& comm = communicator_or_serial(options.communicator);
  const std::uint64_t sent_before = comm.bytes_sent();
  std::vector<RankWork> tally(std::size_t(comm.size()));
  for (int r = 0; r < comm.size(); ++r) tally[std::size_t(r)].rank = r;
  auto add_work = [&](const std::vector<RankWork>& shares) {
    for (const RankWork& w : shares) {
      tally[std::size_t(w.rank)].work += w.work;
      tally[std::size_t(w.rank)].seconds += w.seconds;
    }
  };

  std::vector<SweepRow> rows;
  std::size_t measured = 0;
  auto measure = [&](SweepRow row, const ContactQuery& q) {
    std::vector<RankWork> shares;
    const ComparisonStats s = compare_queries(q, exact, probes, options.law, diagonal, nullptr, &comm, &shares, options.judge);
    add_work(shares);
    row.force_error_median = s.force_error_median;
    row.force_error_p95 = s.force_error_p95;
    row.contact_agreement = s.contact_agreement;
    row.angle_error_median_deg = s.angle_error_median_deg;
    row.angle_error_p99_deg = s.angle_error_p99_deg;
    row.perceptible_share = s.perceptible_share;
    row.within_budget = meets_budget(s, options.budget);
    // One core of one rank times the method; the ranks take turns.
    const int owner = int(measured++ % std::size_t(comm.size()));
    double timing_seconds = 0.0;
    if (comm.rank() == owner) {
      const auto t0 = std::chrono::steady_clock::now();
      row.query_ns = median_query_ns(q, probes, options.law, options.timing_rounds);
      timing_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    }
    if (comm.size() > 1) {
      ByteWriter w;
      w.put(row.query_ns);
      w.put(timing_seconds);
      comm.broadcast(w.bytes(), owner);
      ByteReader r(w.bytes(), "run_sweep: timing");
      row.query_ns = r.get<double>();
      timing_seconds = r.get<double>();
    }
    tally[std::size_t(owner)].work += probes.size() * std::size_t(options.timing_rounds);
    tally[std::size_t(owner)].seconds += timing_seconds;
    if (options.on_row && comm.is_root()) options.on_row(row);
    rows.push_back(row);
  };

  for (const SweepReference& ref : references) {
    if (!ref.query) throw InvalidInput("run_sweep: reference '" + ref.method + "' has no query");
    SweepRow row;
    row.method = ref.method;
    row.memory_bytes = ref.memory_bytes;
    row.bake_seconds = ref.build_seconds;
    measure(row, *ref.query);
    step(1.0);
  }

  for (const SweepConfig& config : options.configs) {
    SweepRow row;
    row.method = "haptic_box";
    row.m = config.m;
    row.n = config.n;
    row.codec = config.codec;
    row.refine = config.refine;
    // The cache holds raw scenes; a codec is applied in memory after loading or baking.
    BakeRecipe recipe = options.recipe;
    recipe.pieces = {};
    if (!piece_of_triangle.empty()) {
      recipe.pieces.kind = PiecesRecipe::Kind::given;
      recipe.pieces.given = piece_of_triangle;
    }
    recipe.options.params.m = config.m;
    recipe.options.params.n = config.n;
    recipe.options.refine = config.refine;
    recipe.codec.codec = CodecId::none;
    const double base = done;
    recipe.options.progress = [&](double f) {
      return !options.progress || options.progress(std::min(1.0, (base + f) / steps));
    };
    recipe.options.communicator = &comm;  // every rank bakes its share and receives the scene
    recipe.options.scene_on_every_rank = true;
    CachedBake baked = bake_cached(mesh, recipe, source, cache ? &*cache : nullptr);
    BoxScene scene = std::move(baked.result.scene);
    row.bake_seconds = baked.result.stats.seconds;
    add_work(baked.result.stats.ranks);
    const bool loaded = baked.from_cache;
    if (!baked.warning.empty()) throw IoError(baked.path + ": " + baked.warning);
    row.from_cache = loaded;
    if (config.codec != "none") scene = compress_scene(scene, config.codec);
    row.memory_bytes = scene.memory_bytes();
    step(1.0);
    measure(row, scene);
    step(1.0);
  }
  if (options.default_bake) {
    // The default bake as a user gets it, measured like the configurations.
    BakeRecipe recipe = default_recipe();
    const double base = done;
    recipe.options.progress = [&](double f) {
      return !options.progress || options.progress(std::min(1.0, (base + f) / steps));
    };
    const auto t0 = std::chrono::steady_clock::now();
    CachedBake baked = bake_cached(mesh, recipe, source, cache && comm.is_root() ? &*cache : nullptr);
    if (!baked.warning.empty()) throw IoError(baked.path + ": " + baked.warning);
    const BoxScene& scene = baked.result.scene;
    SweepRow row;
    row.method = "haptic_box";
    const std::size_t boxes = scene.boxes().size();
    row.label = "default bake: " + std::to_string(boxes) + (boxes == 1 ? " box" : " boxes");
    row.refine = scene.surface() != nullptr;  // answered exactly on a surface (cells or ids)
    row.codec = scene.boxes().empty() ? "none" : codec_name(scene.boxes().front().codec());
    row.from_cache = baked.from_cache;
    row.bake_seconds = baked.from_cache ? 0.0 : std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    row.memory_bytes = scene.memory_bytes();
    step(1.0);
    measure(row, scene);
    step(1.0);
  }
  mark_pareto_front(rows);
  if (options.rank_work) {
    tally[std::size_t(comm.rank())].bytes_sent = comm.bytes_sent() - sent_before;
    if (comm.size() > 1) {
      // Every rank's own byte count, to rank 0.
      ByteWriter w;
      w.put(tally[std::size_t(comm.rank())].bytes_sent);
      const std::vector<Bytes> all = comm.gather(w.bytes());
      for (std::size_t r = 0; r < all.size(); ++r) {
        ByteReader reader(all[r], "run_sweep: bytes");
        tally[r].bytes_sent = reader.get<std::uint64_t>();
      }
    }
    *options.rank_work = tally;
  }
  return rows;
}

std::string configuration_name(const SweepRow& r) {
  const std::string base = r.label.empty() ? "m" + std::to_string(r.m) + " n" + std::to_string(r.n) : r.label;
  return base + (r.codec != "none" && !r.codec.empty() ? " " + r.codec : "") + (r.refine ? " ref" : "");
}

const SweepRow* fastest_within_budget(const std::vector<SweepRow>& rows) {
  const SweepRow* best = nullptr;
  for (const SweepRow& r : rows)
    if (r.method == "haptic_box" && r.within_budget && (!best || r.query_ns < best->query_ns)) best = &r;
  return best;
}

} // namespace hb
