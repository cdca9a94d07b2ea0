// The sweep:
//  1. sample the probes once (the same segments for every method);
//  2. measure each reference: accuracy against the first reference, median query time;
//  3. for each configuration: load the cached box or bake it (and cache it), measure it the
//     same way, drop it before the next one (tables of m=64 n=16 are 600 MB);
//  4. mark the Pareto front.
#include "evaluation/sweep.h"
#include "errors.h"
#include "evaluation/query_timing.h"
#include "haptic_box/bake_recipe.h"
#include "haptic_box/box_file.h"
#include "codec/codec.h"
#include <xxhash.h>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>

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

std::string sweep_cache_path(const std::string& dir, std::uint64_t mesh_hash, const SweepConfig& config) {
  char name[96];
  std::snprintf(name, sizeof name, "%016llx_m%d_n%d_", static_cast<unsigned long long>(mesh_hash), config.m,
                config.n);
  return (std::filesystem::path(dir) / (std::string(name) + config.codec + (config.refine ? "_refine" : "") + ".hbox"))
      .string();
}

void mark_pareto_front(std::vector<SweepRow>& rows) {
  for (SweepRow& r : rows) {
    r.pareto = true;
    for (const SweepRow& o : rows) {
      const bool no_worse = o.query_ns <= r.query_ns && o.force_error_median <= r.force_error_median;
      const bool better = o.query_ns < r.query_ns || o.force_error_median < r.force_error_median;
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
  const bool use_cache = !options.cache_dir.empty() && source.mesh_hash != 0;
  if (use_cache) std::filesystem::create_directories(options.cache_dir);

  // The pieces are cut once; every configuration bakes the same ones.
  const std::vector<std::uint32_t> piece_of_triangle = resolve_piece_ids(mesh, options.recipe.pieces);
  const std::vector<Segment> probes = sample_probes(mesh, options.samples, options.probes);
  const float diagonal = mesh.bounds().diagonal();
  const ContactQuery& exact = *references.front().query;
  const double steps = double(references.size() + 2 * options.configs.size());
  double done = 0.0;
  auto step = [&](double amount) {
    done += amount;
    if (options.progress && !options.progress(std::min(1.0, done / steps))) throw Cancelled("run_sweep: cancelled");
  };

  std::vector<SweepRow> rows;
  auto measure = [&](SweepRow row, const ContactQuery& q) {
    const ComparisonStats s = compare_queries(q, exact, probes, options.law, diagonal);
    row.force_error_median = s.force_error_median;
    row.force_error_p95 = s.force_error_p95;
    row.contact_agreement = s.contact_agreement;
    row.angle_error_median_deg = s.angle_error_median_deg;
    row.query_ns = median_query_ns(q, probes, options.law, options.timing_rounds);
    if (options.on_row) options.on_row(row);
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
    BoxScene scene;
    // The cache holds raw boxes; a codec is applied in memory after loading or baking.
    const SweepConfig raw_config{config.m, config.n, "none", config.refine};
    std::string cached = use_cache ? sweep_cache_path(options.cache_dir, source.mesh_hash, raw_config) : "";
    if (use_cache && !piece_of_triangle.empty()) {
      // Pieces (and their seams) change the boxes: key the cache by them too.
      char tag[64];
      std::snprintf(tag, sizeof tag, "_pieces%016llx_r%d_c%d.hbox",
                    static_cast<unsigned long long>(XXH3_64bits(piece_of_triangle.data(), piece_of_triangle.size() * 4u)),
                    options.recipe.seams.rings, int(std::lround(options.recipe.seams.cells * 100.f)));
      cached = cached.substr(0, cached.size() - 5) + tag;
    }
    bool loaded = false;
    if (use_cache && std::filesystem::exists(cached)) {
      try {
        scene = load_box_file(cached);
        loaded = scene.source().mesh_hash == source.mesh_hash && !scene.boxes().empty() &&
                 scene.boxes().front().params().m == config.m && scene.boxes().front().params().n == config.n &&
                 scene.boxes().front().refines() == config.refine;
      } catch (const Error&) {
        loaded = false;  // a corrupt cache entry is rebaked and overwritten
      }
    }
    if (!loaded) {
      BakeRecipe recipe = options.recipe;
      recipe.pieces = {};
      if (!piece_of_triangle.empty()) {
        recipe.pieces.kind = PiecesRecipe::Kind::given;
        recipe.pieces.given = piece_of_triangle;
      }
      recipe.options.params.m = config.m;
      recipe.options.params.n = config.n;
      recipe.options.refine = config.refine;
      recipe.codec.codec = CodecId::none;  // the cache holds raw boxes
      const double base = done;
      recipe.options.progress = [&](double f) {
        return !options.progress || options.progress(std::min(1.0, (base + f) / steps));
      };
      BakeResult baked = bake(mesh, recipe, source);
      scene = std::move(baked.scene);
      const BakeStats& stats = baked.stats;
      row.bake_seconds = stats.seconds;
      if (use_cache) save_box_file(scene, cached);
    }
    row.from_cache = loaded;
    if (config.codec != "none") scene = compress_scene(scene, config.codec);
    row.memory_bytes = scene.table_bytes() + scene.refinement_bytes();
    step(1.0);
    measure(row, scene);
    step(1.0);
  }
  mark_pareto_front(rows);
  return rows;
}

} // namespace hb
