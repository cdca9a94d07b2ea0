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
  return BoxScene(compressed(raw, options));
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

void SweepRow::set_accuracy(const ComparisonStats& s, const ErrorBudget& budget) {
  force_error_median = s.force_error_median;
  force_error_p95 = s.force_error_p95;
  contact_agreement = s.contact_agreement;
  angle_error_median_deg = s.angle_error_median_deg;
  angle_error_p99_deg = s.angle_error_p99_deg;
  perceptible_share = s.perceptible_share;
  within_budget = meets_budget(s, budget);
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

namespace {

// One sweep's shared state (the probes, the pieces, the cache, the progress, the ranks' tally)
// and its steps, a method each.
class SweepRun {
public:
  SweepRun(const TriangleMesh& mesh, const SourceInfo& source, const std::vector<SweepReference>& references,
           const SweepOptions& options)
      : mesh_(mesh), source_(source), options_(options),
        cache_(options.cache_dir.empty() ? std::nullopt : std::optional<BoxCache>(BoxCache(options.cache_dir))),
        // The pieces are cut once; every configuration bakes the same ones.
        piece_of_triangle_(resolve_piece_ids(mesh, options.recipe.pieces)),
        probes_(sample_probes(mesh, options.samples, options.probes)), diagonal_(mesh.bounds().diagonal()),
        exact_(*references.front().query),
        steps_(double(references.size() + 2 * options.configs.size() + (options.default_bake ? 2 : 0))),
        comm_(communicator_or_serial(options.communicator)), sent_before_(comm_.bytes_sent()),
        tally_(std::size_t(comm_.size())) {
    for (int r = 0; r < comm_.size(); ++r) tally_[std::size_t(r)].rank = r;
  }

  // Step 2: a reference measured as it is.
  void reference(const SweepReference& ref) {
    if (!ref.query) throw InvalidInput("run_sweep: reference '" + ref.method + "' has no query");
    SweepRow row;
    row.method = ref.method;
    row.memory_bytes = ref.memory_bytes;
    row.bake_seconds = ref.build_seconds;
    measure(row, *ref.query);
    step(1.0);
  }

  // Step 3: a configuration loaded from the cache or baked (and cached), then measured.
  void configuration(const SweepConfig& config) {
    SweepRow row;
    row.method = "haptic_box";
    row.m = config.m;
    row.n = config.n;
    row.codec = config.codec;
    row.refine = config.refine;
    // The cache holds raw scenes; a codec is applied in memory after loading or baking.
    BakeRecipe recipe = options_.recipe;
    recipe.pieces = {};
    if (!piece_of_triangle_.empty()) {
      recipe.pieces.kind = PiecesRecipe::Kind::given;
      recipe.pieces.given = piece_of_triangle_;
    }
    recipe.options.params.m = config.m;
    recipe.options.params.n = config.n;
    recipe.options.refine = config.refine;
    recipe.codec.codec = CodecId::none;
    recipe.options.progress = progress_from(done_);
    recipe.options.communicator = &comm_;  // every rank bakes its share and receives the scene
    recipe.options.scene_on_every_rank = true;
    CachedBake baked = bake_cached(mesh_, recipe, source_, cache_ ? &*cache_ : nullptr);
    BoxScene scene = std::move(baked.result.scene);
    row.bake_seconds = baked.result.stats.seconds;
    add_work(baked.result.stats.ranks);
    if (!baked.warning.empty()) throw IoError(baked.path + ": " + baked.warning);
    row.from_cache = baked.from_cache;
    if (config.codec != "none") scene = compress_scene(scene, config.codec);
    row.memory_bytes = scene.bytes().memory;
    step(1.0);
    measure(row, scene);
    step(1.0);
  }

  // The default bake as a user gets it, measured like the configurations.
  void default_bake() {
    BakeRecipe recipe = default_recipe();
    recipe.options.progress = progress_from(done_);
    const auto t0 = std::chrono::steady_clock::now();
    CachedBake baked = bake_cached(mesh_, recipe, source_, cache_ && comm_.is_root() ? &*cache_ : nullptr);
    if (!baked.warning.empty()) throw IoError(baked.path + ": " + baked.warning);
    const BoxScene& scene = baked.result.scene;
    SweepRow row;
    row.method = "haptic_box";
    const std::size_t boxes = scene.parts().boxes.size();
    row.label = "default bake: " + std::to_string(boxes) + (boxes == 1 ? " box" : " boxes");
    row.refine = scene.parts().surface != nullptr;  // answered exactly on a surface (cells or ids)
    row.codec = scene.parts().boxes.empty() ? "none" : codec_name(scene.parts().boxes.front().codec());
    row.from_cache = baked.from_cache;
    row.bake_seconds = baked.from_cache ? 0.0 : std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    row.memory_bytes = scene.bytes().memory;
    step(1.0);
    measure(row, scene);
    step(1.0);
  }

  // Step 4 and the tally (with SweepOptions::rank_work: every rank's own byte count, to rank 0).
  std::vector<SweepRow> finish() {
    mark_pareto_front(rows_);
    if (options_.rank_work) {
      tally_[std::size_t(comm_.rank())].bytes_sent = comm_.bytes_sent() - sent_before_;
      if (comm_.size() > 1) {
        ByteWriter w;
        w.put(tally_[std::size_t(comm_.rank())].bytes_sent);
        const std::vector<Bytes> all = comm_.gather(w.bytes());
        for (std::size_t r = 0; r < all.size(); ++r) {
          ByteReader reader(all[r], "run_sweep: bytes");
          tally_[r].bytes_sent = reader.get<std::uint64_t>();
        }
      }
      *options_.rank_work = tally_;
    }
    return std::move(rows_);
  }

private:
  void step(double amount) {
    done_ += amount;
    if (options_.progress && !options_.progress(std::min(1.0, done_ / steps_))) throw Cancelled("run_sweep: cancelled");
  }
  // A bake's progress f in [0, 1] as the sweep's, from `base` steps done.
  ProgressCallback progress_from(double base) const {
    const SweepOptions& options = options_;
    const double steps = steps_;
    return [&options, base, steps](double f) {
      return !options.progress || options.progress(std::min(1.0, (base + f) / steps));
    };
  }
  void add_work(const std::vector<RankWork>& shares) {
    for (const RankWork& w : shares) {
      tally_[std::size_t(w.rank)].work += w.work;
      tally_[std::size_t(w.rank)].seconds += w.seconds;
    }
  }
  // Accuracy against the first reference on every rank's share of the probes; the median
  // query time on one core of one rank (the ranks take turns), broadcast.
  void measure(SweepRow row, const ContactQuery& q) {
    std::vector<RankWork> shares;
    const ComparisonStats s =
        compare_queries(q, exact_, probes_, options_.law, diagonal_, nullptr, &comm_, &shares, options_.judge);
    add_work(shares);
    row.set_accuracy(s, options_.budget);
    const int owner = int(measured_++ % std::size_t(comm_.size()));
    double timing_seconds = 0.0;
    if (comm_.rank() == owner) {
      const auto t0 = std::chrono::steady_clock::now();
      row.query_ns = median_query_ns(q, probes_, options_.law, options_.timing_rounds);
      timing_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    }
    if (comm_.size() > 1) {
      ByteWriter w;
      w.put(row.query_ns);
      w.put(timing_seconds);
      comm_.broadcast(w.bytes(), owner);
      ByteReader r(w.bytes(), "run_sweep: timing");
      row.query_ns = r.get<double>();
      timing_seconds = r.get<double>();
    }
    tally_[std::size_t(owner)].work += probes_.size() * std::size_t(options_.timing_rounds);
    tally_[std::size_t(owner)].seconds += timing_seconds;
    if (options_.on_row && comm_.is_root()) options_.on_row(row);
    rows_.push_back(row);
  }

  const TriangleMesh& mesh_;
  const SourceInfo& source_;
  const SweepOptions& options_;
  const std::optional<BoxCache> cache_;
  const std::vector<std::uint32_t> piece_of_triangle_;
  const std::vector<Segment> probes_;
  const float diagonal_;
  const ContactQuery& exact_;
  const double steps_;
  double done_ = 0.0;
  Communicator& comm_;
  const std::uint64_t sent_before_;
  std::vector<RankWork> tally_;
  std::vector<SweepRow> rows_;
  std::size_t measured_ = 0;
};

} // namespace

std::vector<SweepRow> run_sweep(const TriangleMesh& mesh, const SourceInfo& source, const std::vector<SweepReference>& references,
                                const SweepOptions& options) {
  if (references.empty() || !references.front().query)
    throw InvalidInput("run_sweep: needs the exact reference first");
  for (const SweepConfig& c : options.configs) check_sweep_config(c);
  SweepRun run(mesh, source, references, options);
  for (const SweepReference& ref : references) run.reference(ref);
  for (const SweepConfig& config : options.configs) run.configuration(config);
  if (options.default_bake) run.default_bake();
  return run.finish();
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
