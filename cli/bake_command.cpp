// hapticbox bake MESH -o BOX.hbox [--budget felt=0.1,raw=on,memory=48] [--json]: the default,
// budgeted bake (hb::default_recipe); or, with any of -m, -n, --cell, --refine, a bake of exactly
// that sampling: [-m 32] [-n 16] [--refine] [--cell C[,max-m=M]] [--pieces auto|FILE|none]
// [--codec none|haar|block[,max-error=E|ratio=R]].
// Through the box cache (hb::bake_cached, the one the window, sweep and report use): a scene
// cached for the model's hash and the whole recipe is copied to -o instead of baked; a fresh
// bake is stored there once and -o copied from it (hb::write_baked_scene). [--cache DIR|none].
// The command parses, calls the core and prints: the default recipe and its overrides are
// hb::default_recipe(overrides), and the help's defaults are read from the recipes.
#include "cli_support.h"
#include "figure_text.h"
#include "commands.h"
#include "errors.h"
#include "recipe/bake_recipe.h"
#include "recipe/box_cache.h"
#include "recipe/recipe_choice.h"
#include "contact/workspace.h"
#include "store/box_file.h"
#include "scene/density_range.h"
#include "scene/scene_codec_stats.h"
#include "mesh/mesh_io.h"
#include "pieces_option.h"
#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <memory>
#include <optional>
#include <unistd.h>

namespace {

// What the command line gave bake.
struct BakeOpts {
  hb::cli::ModelArgs model;
  std::string mesh, out;
  hb::BakeRecipe recipe;
  hb::cli::PiecesArgs pieces;
  std::string codec = "none";
  bool bound_given = false;
  std::string budget;
  std::string cache;
  bool json = false;
  bool strict = false;
};

// --budget's help, every default read from the default recipe (what a bake without options
// uses) and the workspace the budget is judged at.
std::string budget_help(const hb::BakeRecipe& dr) {
  const hb::ErrorBudget& b = dr.budget.budget;
  const hb::WorkspaceOptions w;
  const auto on_off = [](bool on) { return std::string(on ? "on" : "off"); };
  return "The default bake meets this error budget at the lowest cost it finds, against exact Embree: "
         "felt=PERCENT (default " + hb::spec_format(b.perceptible * 100.0) + ": at most that share of probes and of "
         "slide ticks perceptibly different, forces with the model fitted to a " + hb::spec_format(w.diagonal_m * 1000.0) +
         " mm workspace at " + hb::spec_format(w.stiffness_n_per_m) + " N/m); raw=on|off (default " + on_off(b.raw) +
         ": try the paper's raw box first) and memory=MB (its cap, default " + hb::spec_format(b.raw_memory_bytes / 1e6) +
         "); the relative criteria p95=PERCENT,median=PERCENT,dir99=DEGREES,agree=PERCENT (default " +
         (b.relative ? "on" : "off unless named") + "); and for meshes above simplify-above=N triangles (default " +
         std::to_string(dr.budget.simplify_above) + "), simplify=on|off (default " + on_off(dr.budget.simplify) +
         ": bake against the mesh simplified within deviation=F of the diagonal, default " +
         hb::spec_format(dr.budget.simplify_deviation) + ": the depth whose force is a sixteenth of the force threshold, " +
         hb::spec_format(hb::simplification_bound(b)) + "; shaded by a normal map of side shading-map=S, default " +
         std::to_string(dr.budget.shading_map_side) + ": automatic, -1: none; the full mesh instead when it misses the "
         "budget)";
}

void add_bake_options(CLI::App& cmd, const std::shared_ptr<BakeOpts>& opts) {
  const hb::BakeRecipe one;                          // one sampling: -m, -n, --cell or --refine
  const hb::BakeRecipe dr = hb::default_recipe();    // the default bake
  cmd.add_option("MESH", opts->mesh, "Input mesh")->required();
  cmd.add_option("-o,--output", opts->out, "Output box file (.hbox)")->required();
  cmd.add_option("--budget", opts->budget, budget_help(dr))
      ->type_name("KEY=VALUE,...")
      ->group("Default bake");
  hb::cli::add_pieces_options(cmd, opts->pieces, "auto for the default bake, none for one sampling", dr, &one);
  hb::cli::add_codec_option(cmd, opts->codec, opts->recipe.codec, &opts->strict, &opts->bound_given,
                            {"none", "haar", "block"},
                            std::string("Table codec: none, haar (the paper's) or block (ours) (default ") +
                                hb::codec_name(dr.codec.codec) + " for the default bake, " + hb::codec_name(one.codec.codec) +
                                " for one sampling); then max-error=E (bound on |t1 - t0| / box diagonal, default " +
                                hb::spec_format(dr.codec.max_error) +
                                ") or ratio=R (the tightest bound reaching this compression ratio; with strict: fail, "
                                "exit 1, when the codec cannot reach it), normal-bits=B (octahedral bits per "
                                "coordinate, 6-14; default " + std::to_string(dr.codec.normal_bits) + ")")
      ->type_name("NAME[,KEY=VALUE...]");
  const std::string one_group = "One sampling (instead of the default bake)";
  cmd.add_option("-m", opts->recipe.options.params.m,
                 "Position points per PBB face edge (default " + std::to_string(one.options.params.m) + ")")
      ->check(CLI::Range(2, 1024))->group(one_group);
  cmd.add_option("-n", opts->recipe.options.params.n,
                 "Directional points per sub-block face edge (default " + std::to_string(one.options.params.n) + ")")
      ->check(CLI::Range(2, 256))->group(one_group);
  cmd.add_option_function<std::string>(
         "--cell",
         [opts](const std::string& spec) {
           std::string cell;
           hb::cli::parse_spec("--cell", spec, {hb::cli::number_key("max-m", opts->recipe.options.density.max_m, 2, 1024)}, &cell);
           opts->recipe.options.density.cell = float(hb::cli::spec_number_or_usage(cell, "--cell", 0.0, 1.0));
         },
         "Per-box m: the position-cell size, fraction of the mesh diagonal (default " +
             hb::spec_format(one.options.density.cell) + ": -m for every box), then max-m=M: the largest per-box m "
             "(default " + std::to_string(one.options.density.max_m) + "; the default bake keeps its own cells and "
             "takes only max-m, default " + std::to_string(dr.options.density.max_m) + ")")
      ->type_name("C[,max-m=M]")
      ->group(one_group);
  cmd.add_flag("--refine", opts->recipe.options.refine,
               "Store the triangle each sample hit and the mesh's triangles: queries then refine the blend exactly "
               "(2 or 4 bytes more per sample, 64 per triangle)")
      ->group(one_group);
  hb::cli::add_cache_option(cmd, opts->cache);
  cmd.add_flag("--json", opts->json, "Print a JSON summary");
  hb::cli::add_model_options(cmd, opts->model);
}

// The measurement-only switches of the default bake (HB_MEASURE, measurement_switches.h), read
// once.
hb::DefaultRecipeOverrides measured_overrides() {
  hb::DefaultRecipeOverrides ov;
  ov.full_search = hb::cli::measurement("full-search").has_value();
  ov.keep_triangle_ids = hb::cli::measurement("keep-ids").has_value();
  if (const auto shading = hb::cli::measurement("simplify-shading"))
    ov.simplify_shading_deg = hb::cli::spec_number_or_usage(*shading, "HB_MEASURE simplify-shading", 0.0, 180.0);
  if (const auto check = hb::cli::measurement("simplify-shading-check")) {
    if (*check != "fit" && *check != "ring")
      throw hb::cli::UsageError("HB_MEASURE simplify-shading-check: '" + *check + "' is not fit or ring");
    ov.simplify_shading_check =
        *check == "ring" ? hb::DecimationOptions::ShadingCheck::ring : hb::DecimationOptions::ShadingCheck::fit;
  }
  return ov;
}

// The recipe of this bake. Without a sampling option (-m, -n, --cell, --refine) it is the
// default, budgeted one (hb::default_recipe(overrides): --budget, --cell's max-m, --codec's
// bound and the measurement switches); the pieces, codec and seam options given still apply to
// it. With one, exactly that sampling.
void choose_bake_recipe(BakeOpts& o, const CLI::App& cmd) {
  const bool sampling_given = !hb::bakes_default_recipe(hb::cli::sampling_given(cmd));
  hb::DefaultRecipeOverrides ov = measured_overrides();
  ov.budget = o.budget;
  if (sampling_given) {
    if (hb::budget_names_surface_keys(o.budget) || ov.simplify_shading_deg || ov.simplify_shading_check)
      throw hb::cli::UsageError("bake: --budget's simplify keys belong to the default bake; drop -m, -n, --cell and --refine, or them");
    if (ov.full_search)
      throw hb::cli::UsageError("bake: full-search (HB_MEASURE) belongs to the default bake (-m, -n, --cell and --refine bake one sampling); drop it");
    if (ov.keep_triangle_ids)
      throw hb::cli::UsageError("bake: keep-ids (HB_MEASURE) belongs to the default bake (a --refine bake always keeps its ids); drop it");
    if (cmd.count("--budget"))
      throw hb::cli::UsageError("bake: --budget chooses -n, --cell and --refine per piece; drop -m, -n, --cell and --refine, or --budget");
  } else {
    if (cmd.count("--cell")) ov.max_m = o.recipe.options.density.max_m;
    if (o.bound_given) ov.codec_max_error = o.recipe.codec.max_error, ov.codec_ratio = o.recipe.codec.ratio;
    const auto progress = o.recipe.pieces.automatic.progress;
    try {
      o.recipe = hb::default_recipe(ov);
    } catch (const hb::InvalidInput& e) {
      throw hb::cli::UsageError(std::string("bake: ") + e.what());
    }
    o.recipe.pieces.automatic.progress = progress;
    if (!o.pieces.given) o.pieces.spec = "auto";
    if (!cmd.count("--codec")) o.codec = "block";
  }
  o.pieces.apply_tuning(o.recipe);
  o.recipe.codec.codec = hb::parse_codec(o.codec);
  if (o.recipe.codec.codec == hb::CodecId::none && o.bound_given)
    throw hb::cli::UsageError("bake: --codec's max-error and ratio need the codec haar or block");
}

// Each stage of a budgeted bake as it finishes (on stderr, over the progress bar when there
// is one), so a long bake shows where its minutes go before it ends.
void report_bake_stages(hb::BakeRecipe& recipe) {
  if (!hb::cli::communicator().is_root()) return;
  const bool tty = isatty(STDERR_FILENO);
  recipe.budget.on_stage = [tty](const std::string& stage, double seconds) {
    std::fprintf(stderr, "%sstage %s: %s%s\n", tty ? "\r" : "", stage.c_str(), hb::duration_text(seconds).c_str(),
                 tty ? "\033[K" : "");
    std::fflush(stderr);
  };
  recipe.budget.on_note = [tty](const std::string& note) {
    std::fprintf(stderr, "%sbake: %s%s\n", tty ? "\r" : "", note.c_str(), tty ? "\033[K" : "");
    std::fflush(stderr);
  };
}

// How the work was shared: per rank the rays cast, the seconds its share took and the bytes it
// sent; the busiest rank against the mean; the bytes sent against the tables.
void add_rank_work(const hb::BakeStats& stats, nlohmann::json& j) {
  nlohmann::json per_rank = nlohmann::json::array();
  double busiest = 0, mean = 0;
  std::uint64_t sent = 0;
  for (const hb::RankWork& w : stats.ranks) {
    per_rank.push_back({{"rank", w.rank}, {"rays", w.work}, {"seconds", w.seconds}, {"bytes_sent", w.bytes_sent}});
    busiest = std::max(busiest, w.seconds);
    mean += w.seconds / double(stats.ranks.size());
    sent += w.bytes_sent;
  }
  // Rank 0 keeps its own share: the others' shares are what must travel.
  std::uint64_t others_rays = 0;
  for (const hb::RankWork& w : stats.ranks)
    if (w.rank != 0) others_rays += w.work;
  const double expected = stats.rays ? double(stats.table_bytes) * double(others_rays) / double(stats.rays) : 0.0;
  j["rank_work"] = per_rank;
  j["load_balance"] = mean > 0 ? busiest / mean : 1.0;
  j["bytes_sent"] = sent;
  j["bytes_sent_over_tables"] = expected > 0 ? double(sent) / expected : 0.0;
}

// What a bake made, for its JSON and its text.
struct BakeSummary {
  std::vector<int> box_m, box_n;
  std::size_t refined_boxes = 0, id_bytes = 0;
  std::uintmax_t bytes = 0;
  hb::SceneCodecStats codec;
};

BakeSummary summarise_bake(const hb::BoxScene& scene, const std::string& out) {
  BakeSummary s;
  s.codec = hb::scene_codec_stats(scene);
  s.bytes = std::filesystem::file_size(out);
  for (const hb::HapticBox& box : scene.parts().boxes) {
    s.box_m.push_back(box.params().m);
    s.box_n.push_back(box.params().n);
    s.refined_boxes += box.refines() ? 1 : 0;
    s.id_bytes += box.triangle_id_bytes();
  }
  return s;
}

nlohmann::json bake_json(const BakeOpts& o, const hb::TriangleMesh& mesh, const hb::CachedBake& cached,
                         const BakeSummary& s) {
  const hb::BoxScene& scene = cached.result.scene;
  const hb::BakeStats& stats = cached.result.stats;
  const hb::SceneCodecStats& cs = s.codec;
  nlohmann::json j = {{"mesh", o.mesh},
                      {"output", o.out},
                      {"triangles", mesh.triangle_count()},
                      {"boxes", scene.parts().boxes.size()},
                      {"m", o.recipe.options.params.m},
                      {"box_m", s.box_m},
                      {"n", scene.parts().budget.present ? s.box_n.back() : o.recipe.options.params.n},
                      {"box_n", s.box_n},
                      {"refined_boxes", s.refined_boxes},
                      {"from_cache", cached.from_cache},
                      {"cache_path", cached.path},
                      {"seconds", stats.seconds},
                      {"rays", stats.rays},
                      {"rays_per_second", stats.rays_per_second},
                      {"hit_fraction", stats.rays ? double(stats.hits) / double(stats.rays) : 0.0},
                      {"bytes", s.bytes},
                      {"refine", scene.refines()},
                      {"tables", has_tables(scene.parts())},  // false: box frames (answered by exact Embree)
                      {"triangle_id_bytes", s.id_bytes},
                      {"codec", o.codec},
                      {"table_bytes", cs.table_bytes},
                      {"raw_table_bytes", cs.raw_bytes},
                      {"compression_ratio", cs.compression_ratio()},
                      {"max_error_bound", cs.max_error_bound},
                      {"t_error_mean", cs.t_error_mean},
                      {"t_error_max", cs.t_error_max},
                      {"normal_error_mean_deg", cs.normal_error_mean_deg},
                      {"normal_error_max_deg", cs.normal_error_max_deg}};
  if (o.recipe.codec.codec != hb::CodecId::none)
    hb::cli::check_ratio_target(o.recipe.codec.ratio, cs.compression_ratio(), cs.max_error_bound, cs.t_error_mean,
                                o.strict, j);
  add_rank_work(stats, j);
  j["budget"] = hb::cli::budget_json(scene.parts().budget);
  return j;
}

// The first line: what was written, how (baked now or from the cache) and what it holds.
void print_bake_line(const BakeOpts& o, const hb::CachedBake& cached, const BakeSummary& s) {
  const hb::BoxScene& scene = cached.result.scene;
  const hb::BakeStats& stats = cached.result.stats;
  const std::string densities = hb::density_range_text(hb::density_range(scene));
  if (cached.from_cache)
    std::cout << "baked " << o.out << " from cache (" << cached.path << "): " << scene.parts().boxes.size()
              << " box(es), " << densities << ", " << hb::bytes_text(s.bytes);
  else
    std::cout << "baked " << o.out << ": " << scene.parts().boxes.size() << " box(es), " << densities << ", "
              << hb::count_text(double(stats.rays)) << " rays in "
              << hb::duration_text(stats.seconds) << " (" << hb::count_text(stats.rays_per_second) << " rays/s), "
              << hb::bytes_text(s.bytes);
  if (!has_tables(scene.parts()))
    std::cout << " (exact Embree over the surface " << hb::bytes_text(scene.parts().surface->bytes())
              << ": box frames, no tables, no triangle ids)";
  else if (s.refined_boxes > 0)
    std::cout << " (" << (s.refined_boxes == scene.parts().boxes.size() ? std::string("all") : std::to_string(s.refined_boxes))
              << " box(es) with triangle ids and surface for exact refinement)";
  else if (scene.refines())
    std::cout << " (exact through the surface cells: surface " << hb::bytes_text(scene.parts().surface->bytes())
              << (scene.parts().surface->normal_map_bytes() > 0
                      ? " and its normal map " + hb::bytes_text(scene.parts().surface->normal_map_bytes())
                      : std::string())
              << ", no triangle ids"
              << (stroke_mesh(scene) ? "; strokes by exact Embree over the full mesh, " + hb::bytes_text(scene.bytes().embree)
                                      : std::string())
              << ")";
  std::cout << "\n";
}

void print_bake(const BakeOpts& o, const hb::CachedBake& cached, const BakeSummary& s, const nlohmann::json& j) {
  print_bake_line(o, cached, s);
  const hb::BudgetReport& budget = cached.result.scene.parts().budget;
  if (budget.present) {
    std::cout << "budget " << budget.summary() << "; " << budget.candidates_tried << " sampling bake(s)";
    if (budget.seconds > 0) std::cout << ", " << hb::duration_text(budget.seconds) << " in all";
    std::cout << "\n";
    if (!budget.stage_seconds.empty()) {
      std::cout << "stages:";
      for (const auto& st : budget.stage_seconds) std::cout << " " << st.first << " " << hb::duration_text(st.second);
      std::cout << "\n";
    }
  }
  const hb::Communicator& comm = hb::cli::communicator();
  if (comm.size() > 1)
    std::cout << comm.size() << " ranks: busiest " << hb::sig(j["load_balance"].get<double>()) << " x the mean; sent "
              << hb::bytes_text(j["bytes_sent"].get<std::uint64_t>()) << ", "
              << hb::sig(j["bytes_sent_over_tables"].get<double>()) << " x their tables\n";
  const hb::SceneCodecStats& cs = s.codec;
  if (o.recipe.codec.codec != hb::CodecId::none && cached.result.scene.bytes().tables == 0)
    std::cout << "codec " << o.codec << ": nothing to compress (the boxes are frames without tables)\n";
  else if (o.recipe.codec.codec != hb::CodecId::none)
    std::cout << "codec " << o.codec << ": ratio " << hb::sig(cs.compression_ratio()) << ":1, bound "
              << hb::percent(cs.max_error_bound) << " of the box diagonal; t error mean " << hb::percent(cs.t_error_mean)
              << ", max " << hb::percent(cs.t_error_max) << "; normal error mean " << hb::sig(cs.normal_error_mean_deg)
              << " deg, max " << hb::sig(cs.normal_error_max_deg) << " deg (means weighted by box samples)\n";
}

void run_bake(BakeOpts& o, const CLI::App& cmd) {
  hb::cli::check_output_file(o.out);  // an unwritable -o fails now, not after the bake
  if (std::filesystem::path(o.out).extension() != ".hbox")
    std::cerr << "hapticbox: warning: " << o.out
              << ": a box file is written under a name that does not end in .hbox (the window's Open dialog and "
                 "the other commands take it by its content, but look for .hbox)\n";
  choose_bake_recipe(o, cmd);
  const hb::TriangleMesh mesh = hb::cli::load_mesh(o.mesh, o.model);
  hb::SourceInfo source{o.mesh, hb::cli::hash_model(o.mesh, o.model), mesh.triangle_count(), mesh.bounds().diagonal()};
  o.recipe.options.progress = hb::cli::terminal_progress("baking");
  report_bake_stages(o.recipe);
  o.recipe.options.density.min_m = std::min(o.recipe.options.density.min_m, o.recipe.options.density.max_m);
  hb::Communicator& comm = hb::cli::communicator();
  o.recipe.options.communicator = &comm;  // position points dealt across the ranks of an MPI job
  hb::cli::apply_pieces_spec(o.pieces.spec, o.recipe, o.model.face_ids);
  std::optional<hb::BoxCache> cache;
  if (!o.cache.empty()) cache.emplace(o.cache);
  const hb::CachedBake cached = hb::bake_cached(mesh, o.recipe, source, cache ? &*cache : nullptr);
  if (!comm.is_root()) return;  // rank 0 holds the tables and writes the file
  if (!cached.from_cache) hb::cli::print_decomposition(o.recipe, cached.result);
  if (!cached.warning.empty()) std::cerr << "warning: " << cached.warning << "\n";
  const hb::BakedFileWrite written = hb::write_baked_scene(cached, o.out);
  const BakeSummary summary = summarise_bake(cached.result.scene, o.out);
  nlohmann::json j = bake_json(o, mesh, cached, summary);
  j["output_written"] = written == hb::BakedFileWrite::entry  ? "entry"
                        : written == hb::BakedFileWrite::copy ? "copy of the cache entry"
                                                              : "saved";
  if (o.json) hb::cli::print_json(j);
  else print_bake(o, cached, summary, j);
}

} // namespace

void add_bake_command(CLI::App& app) {
  auto* cmd = app.add_subcommand("bake", "Bake a haptic box file from a mesh");
  auto opts = std::make_shared<BakeOpts>();
  add_bake_options(*cmd, opts);
  cmd->callback([opts, cmd] { run_bake(*opts, *cmd); });
}
