// hapticbox bake MESH -o BOX.hbox [--budget felt=0.1,raw=on,memory=48] [--json]: the default,
// budgeted bake (hb::default_recipe); or, with any of -m, -n, --cell, --refine, a bake of exactly
// that sampling: [-m 32] [-n 16] [--refine] [--cell C [--max-m 64]] [--pieces auto|FILE|none]
// [--codec none|haar|block] [--max-error E | --ratio R].
// Through the box cache (hb::bake_cached, the one the window, sweep and report use): a scene
// cached for the model's hash and the whole recipe is copied to -o instead of baked; a bake is
// stored there. [--cache DIR] [--no-cache].
#include "cli_support.h"
#include "figure_text.h"
#include "commands.h"
#include "errors.h"
#include "recipe/bake_recipe.h"
#include "recipe/box_cache.h"
#include "haptic_box/box_file.h"
#include "haptic_box/scene_codec_stats.h"
#include "mesh/mesh_io.h"
#include "pieces_option.h"
#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <optional>
#include <unistd.h>

void add_bake_command(CLI::App& app) {
  auto* cmd = app.add_subcommand("bake", "Bake a haptic box file from a mesh");
  struct Opts {
    hb::cli::ModelArgs model;
    std::string mesh, out;
    hb::BakeRecipe recipe;
    std::string pieces;
    std::string codec = "none";
    std::string budget;
    std::string cache = hb::default_box_cache_dir();
    bool no_cache = false;
    bool json = false;
    bool strict = false;
    bool simplify = hb::BudgetRecipe{}.simplify;
    bool keep_ids = false;
    bool full_search = false;
    double simplify_shading = 0.0;
    std::string simplify_shading_check = "fit";
    std::size_t simplify_above = hb::BudgetRecipe{}.simplify_above;
    int shading_map = 0;
    double simplify_deviation = 0.0;
  };
  auto opts = std::make_shared<Opts>();
  hb::cli::add_model_options(*cmd, opts->model);
  cmd->add_option("MESH", opts->mesh, "Input mesh")->required();
  cmd->add_option("-o,--output", opts->out, "Output box file (.hbox)")->required();
  cmd->add_option("-m", opts->recipe.options.params.m, "Position points per PBB face edge")
      ->check(CLI::Range(2, 1024))->capture_default_str();
  cmd->add_option("-n", opts->recipe.options.params.n, "Directional points per sub-block face edge")
      ->check(CLI::Range(2, 256))->capture_default_str();
  cmd->add_option("--cell", opts->recipe.options.density.cell,
                  "Per-box m: target position-cell size, fraction of the mesh diagonal (0: -m for every box)")
      ->check(hb::cli::finite_range(0.0, 1.0))->capture_default_str();
  cmd->add_option("--max-m", opts->recipe.options.density.max_m, "Largest per-box m with --cell")
      ->check(CLI::Range(2, 1024))->capture_default_str();
  cmd->add_option("--padding", opts->recipe.options.obb.padding, "PBB padding, fraction of its diagonal")
      ->check(hb::cli::finite_range(0.0, 1.0))->capture_default_str();
  hb::cli::add_pieces_options(*cmd, opts->pieces, opts->recipe);
  cmd->add_option("--codec", opts->codec, "Table codec: none, haar (the paper's) or block (ours)")
      ->check(CLI::IsMember({"none", "haar", "block"}))->capture_default_str();
  auto* max_error = hb::cli::add_codec_bound_options(*cmd, opts->recipe.codec, &opts->strict);
  cmd->add_flag("--refine", opts->recipe.options.refine,
                "Store the triangle each sample hit and the mesh's triangles: queries then refine the blend exactly "
                "(2 or 4 bytes more per sample, 64 per triangle)");
  cmd->add_option("--budget", opts->budget,
                  "Error budget the default bake meets at the lowest cost it finds, against exact Embree: "
                  "felt=PERCENT (default 0.1: at most 0.1% of probes and of slide ticks perceptibly different, forces "
                  "with the model fitted to an 80 mm workspace at 1500 N/m), raw=on|off (try the paper's raw box "
                  "first), memory=MB (the raw box's cap, 48), and the relative criteria p95=PERCENT,median=PERCENT,"
                  "dir99=DEGREES,agree=PERCENT (off unless named). Not with -m, -n, --cell or --refine, "
                  "which bake one given sampling");
  cmd->add_option("--cache", opts->cache, "Box cache directory (shared with the window, sweep and report)")
      ->capture_default_str();
  cmd->add_flag("--no-cache", opts->no_cache, "Bake even when the cache holds the scene, and store nothing");
  cmd->add_flag("--simplify,!--no-simplify", opts->simplify,
                "Default bake (on by default): above 200,000 triangles, bake and refine against the mesh simplified "
                "within the budget's deviation (3.75e-6 of the diagonal by default), shaded by a normal map of the "
                "full mesh's normals; judged against the full mesh, and the full mesh baked instead when it misses "
                "the budget. --no-simplify: always the full mesh");
  cmd->add_option("--simplify-shading", opts->simplify_shading,
                  "With --simplify: the shading check's bound while simplifying (degrees; 0: none with the normal map, "
                  "else 0.3 x the budget's dir99 with the fit check, 0.2 x with the ring check; 180: no check)")
      ->check(hb::cli::finite_range(0.0, 180.0))->capture_default_str();
  cmd->add_option("--simplify-shading-check", opts->simplify_shading_check,
                  "With --simplify: fit (a collapse is legal when each new face's own corner normals fit the full "
                  "mesh's shading of the vertices it replaced within the bound) or ring (a removed vertex's "
                  "neighbours' normals within the bound of its own: the first check). Either way the simplified "
                  "surface's corner normals are then fitted to the full mesh's shading")
      ->check(CLI::IsMember({"fit", "ring"}))->capture_default_str();
  cmd->add_option("--simplify-deviation", opts->simplify_deviation,
                  "With --simplify: the deviation bound, fraction of the mesh diagonal (0: the budget's share, "
                  "3.75e-6 of the diagonal for the default budget)")
      ->check(CLI::Range(0.0, 0.099))->capture_default_str();
  cmd->add_option("--shading-map", opts->shading_map,
                  "With --simplify: the side of the normal map that carries the full mesh's shading over each "
                  "simplified triangle (0: automatic, the power of two above sqrt(full / simplified triangles), at "
                  "most 16; -1: none, corner normals fitted per face and the shading check while simplifying)")
      ->check(CLI::Range(-1, 64))->capture_default_str();
  cmd->add_option("--simplify-above", opts->simplify_above, "With --simplify: simplify meshes of more triangles than this")
      ->capture_default_str();
  cmd->add_flag("--keep-ids", opts->keep_ids,
                "Default bake: keep every refined box's triangle ids (2-4 bytes a sample) although the surface "
                "cells answer without them, to compare --route boxes on the same bake");
  cmd->add_flag("--full-search", opts->full_search,
                "Default bake: bake every piece at every sampling and search them all although the surface cells "
                "answer the scene exactly at the coarsest (the bakes before 2026-12-04; for before/after figures)");
  cmd->add_flag("--json", opts->json, "Print a JSON summary");
  cmd->callback([opts, max_error, cmd] {
    hb::cli::check_output_file(opts->out);  // an unwritable -o fails now, not after the bake
    // Without a sampling option the bake is the default, budgeted one (hb::default_recipe):
    // the pieces, codec and seam options given still apply to it.
    const bool sampling_given = cmd->count("-m") + cmd->count("-n") + cmd->count("--cell") + cmd->count("--refine") > 0;
    if (sampling_given && (cmd->count("--simplify") || cmd->count("--simplify-shading") || cmd->count("--simplify-above") ||
                           cmd->count("--simplify-shading-check") || cmd->count("--shading-map") ||
                           cmd->count("--simplify-deviation")))
      throw hb::cli::UsageError("bake: --simplify and its options belong to the default bake; drop -m, -n, --cell and --refine, or them");
    if (sampling_given && opts->full_search)
      throw hb::cli::UsageError("bake: --full-search belongs to the default bake (-m, -n, --cell and --refine bake one sampling); drop it");
    if (sampling_given && opts->keep_ids)
      throw hb::cli::UsageError("bake: --keep-ids belongs to the default bake (a --refine bake always keeps its ids); drop it");
    if (sampling_given && cmd->count("--budget"))
      throw hb::cli::UsageError("bake: --budget chooses -n, --cell and --refine per piece; drop -m, -n, --cell and --refine, or --budget");
    if (!sampling_given) {
      hb::BakeRecipe r = hb::default_recipe();
      try {
        r.budget.budget = hb::parse_budget(opts->budget);
      } catch (const hb::InvalidInput& e) {
        throw hb::cli::UsageError(std::string("bake: ") + e.what());
      }
      r.budget.simplify = opts->simplify;
      r.budget.simplify_shading_deg = opts->simplify_shading;
      r.budget.simplify_shading_check = opts->simplify_shading_check == "ring" ? hb::DecimationOptions::ShadingCheck::ring
                                                                               : hb::DecimationOptions::ShadingCheck::fit;
      r.budget.simplify_above = opts->simplify_above;
      r.budget.shading_map_side = opts->shading_map;
      r.budget.simplify_deviation = opts->simplify_deviation;
      r.budget.keep_triangle_ids = opts->keep_ids;
      r.budget.full_search = opts->full_search;
      if (cmd->count("--max-m")) r.options.density.max_m = opts->recipe.options.density.max_m;
      if (cmd->count("--padding")) r.options.obb.padding = opts->recipe.options.obb.padding;
      if (cmd->count("--threshold")) r.pieces.automatic.threshold = opts->recipe.pieces.automatic.threshold;
      if (cmd->count("--max-pieces")) r.pieces.automatic.max_pieces = opts->recipe.pieces.automatic.max_pieces;
      if (cmd->count("--seam-rings")) r.seams.rings = opts->recipe.seams.rings;
      if (cmd->count("--seam-cells")) r.seams.cells = opts->recipe.seams.cells;
      if (!cmd->count("--pieces")) opts->pieces = "auto";
      if (!cmd->count("--codec")) opts->codec = "block";
      if (*max_error || opts->recipe.codec.ratio > 0.f) {
        r.codec.max_error = opts->recipe.codec.max_error;
        r.codec.ratio = opts->recipe.codec.ratio;
      }
      r.pieces.automatic.progress = opts->recipe.pieces.automatic.progress;
      opts->recipe = r;
    }
    opts->recipe.codec.codec = hb::parse_codec(opts->codec);
    if (opts->recipe.codec.codec == hb::CodecId::none && (*max_error || opts->recipe.codec.ratio > 0.f))
      throw hb::cli::UsageError("bake: --max-error and --ratio need --codec haar or block");
    const hb::TriangleMesh mesh = hb::cli::load_mesh(opts->mesh, opts->model);
    hb::SourceInfo source{opts->mesh, hb::cli::hash_model(opts->mesh, opts->model), mesh.triangle_count(), mesh.bounds().diagonal()};
    opts->recipe.options.progress = hb::cli::terminal_progress("baking");
    // Each stage of a budgeted bake as it finishes (on stderr, over the progress bar when there
    // is one), so a long bake shows where its minutes go before it ends.
    if (hb::cli::communicator().is_root()) {
      const bool tty = isatty(STDERR_FILENO);
      opts->recipe.budget.on_stage = [tty](const std::string& stage, double seconds) {
        std::fprintf(stderr, "%sstage %s: %s%s\n", tty ? "\r" : "", stage.c_str(), hb::duration_text(seconds).c_str(),
                     tty ? "\033[K" : "");
        std::fflush(stderr);
      };
    }
    opts->recipe.options.density.min_m = std::min(opts->recipe.options.density.min_m, opts->recipe.options.density.max_m);
    hb::Communicator& comm = hb::cli::communicator();
    opts->recipe.options.communicator = &comm;  // position points dealt across the ranks of an MPI job
    hb::cli::apply_pieces_spec(opts->pieces, opts->recipe, opts->model.face_ids);
    std::optional<hb::BoxCache> cache;
    if (!opts->no_cache) cache.emplace(opts->cache);
    const hb::CachedBake cached = hb::bake_cached(mesh, opts->recipe, source, cache ? &*cache : nullptr);
    if (!comm.is_root()) return;  // rank 0 holds the tables and writes the file
    const hb::BakeResult& baked = cached.result;
    if (!cached.from_cache) hb::cli::print_decomposition(opts->recipe, baked);
    if (!cached.warning.empty()) std::cerr << "warning: " << cached.warning << "\n";
    const hb::BoxScene& scene = baked.scene;
    const hb::BakeStats& stats = baked.stats;
    namespace fs = std::filesystem;
    std::error_code same_ec;
    if (cached.from_cache && fs::equivalent(cached.path, opts->out, same_ec)) {
      // -o is the cache entry itself: nothing to write.
    } else if (cached.from_cache) {
      // The cache entry is the bake's file byte for byte: copy it.
      std::error_code ec;
      fs::copy_file(cached.path, opts->out, fs::copy_options::overwrite_existing, ec);
      if (ec) throw hb::IoError(opts->out + ": cannot write the box file (" + ec.message() + ")");
    } else {
      hb::save_box_file(scene, opts->out);
    }
    const hb::SceneCodecStats cs = hb::scene_codec_stats(scene);
    const hb::BudgetReport& budget = scene.budget_report();
    const auto bytes = std::filesystem::file_size(opts->out);
    std::vector<int> box_m, box_n;
    for (const hb::HapticBox& box : scene.boxes()) box_m.push_back(box.params().m), box_n.push_back(box.params().n);
    const auto range = [](const std::vector<int>& v) {
      const int lo = *std::min_element(v.begin(), v.end()), hi = *std::max_element(v.begin(), v.end());
      return lo == hi ? std::to_string(lo) : std::to_string(lo) + ".." + std::to_string(hi);
    };
    std::size_t refined_boxes = 0, id_bytes = 0;
    for (const hb::HapticBox& box : scene.boxes()) {
      refined_boxes += box.refines() ? 1 : 0;
      id_bytes += box.triangle_id_bytes();
    }
    const nlohmann::json jj = {{"mesh", opts->mesh},
                              {"output", opts->out},
                              {"triangles", mesh.triangle_count()},
                              {"boxes", scene.boxes().size()},
                              {"m", opts->recipe.options.params.m},
                              {"box_m", box_m},
                              {"n", budget.present ? box_n.back() : opts->recipe.options.params.n},
                              {"box_n", box_n},
                              {"refined_boxes", refined_boxes},
                              {"from_cache", cached.from_cache},
                              {"cache_path", cached.path},
                              {"seconds", stats.seconds},
                              {"rays", stats.rays},
                              {"rays_per_second", stats.rays_per_second},
                              {"hit_fraction", stats.rays ? double(stats.hits) / double(stats.rays) : 0.0},
                              {"bytes", bytes},
                              {"refine", scene.refines()},
                              {"triangle_id_bytes", id_bytes},
                              {"codec", opts->codec},
                              {"table_bytes", cs.table_bytes},
                              {"raw_table_bytes", cs.raw_bytes},
                              {"compression_ratio", cs.compression_ratio()},
                              {"max_error_bound", cs.max_error_bound},
                              {"t_error_mean", cs.t_error_mean},
                              {"t_error_max", cs.t_error_max},
                              {"normal_error_mean_deg", cs.normal_error_mean_deg},
                              {"normal_error_max_deg", cs.normal_error_max_deg}};
    nlohmann::json j = jj;
    if (opts->recipe.codec.codec != hb::CodecId::none)
      hb::cli::check_ratio_target(opts->recipe.codec.ratio, cs.compression_ratio(), cs.max_error_bound, cs.t_error_mean,
                                  opts->strict, j);
    // How the work was shared: per rank the rays cast, the seconds its share took and the
    // bytes it sent; the busiest rank against the mean; the bytes sent against the tables.
    {
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
    j["budget"] = hb::cli::budget_json(budget);
    if (opts->json) {
      hb::cli::print_json(j);
    } else {
      if (cached.from_cache)
        std::cout << "baked " << opts->out << " from cache (" << cached.path << "): " << scene.boxes().size()
                  << " box(es), m=" << range(box_m) << " n=" << range(box_n) << ", " << hb::bytes_text(bytes);
      else
        std::cout << "baked " << opts->out << ": " << scene.boxes().size() << " box(es), m=" << range(box_m)
                  << " n=" << range(box_n) << ", " << hb::count_text(double(stats.rays)) << " rays in "
                  << hb::duration_text(stats.seconds) << " (" << hb::count_text(stats.rays_per_second) << " rays/s), "
                  << hb::bytes_text(bytes);
      if (refined_boxes > 0)
        std::cout << " (" << (refined_boxes == scene.boxes().size() ? std::string("all") : std::to_string(refined_boxes))
                  << " box(es) with triangle ids and surface for exact refinement)";
      else if (scene.refines())
        std::cout << " (exact through the surface cells: surface " << hb::bytes_text(scene.surface()->bytes())
                  << (scene.surface()->normal_map_bytes() > 0
                          ? " and its normal map " + hb::bytes_text(scene.surface()->normal_map_bytes())
                          : std::string())
                  << ", no triangle ids)";
      std::cout << "\n";
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
      if (comm.size() > 1)
        std::cout << comm.size() << " ranks: busiest " << hb::sig(j["load_balance"].get<double>()) << " x the mean; sent "
                  << hb::bytes_text(j["bytes_sent"].get<std::uint64_t>()) << ", "
                  << hb::sig(j["bytes_sent_over_tables"].get<double>()) << " x their tables\n";
      if (opts->recipe.codec.codec != hb::CodecId::none)
        std::cout << "codec " << opts->codec << ": ratio " << hb::sig(cs.compression_ratio()) << ":1, bound "
                  << hb::percent(cs.max_error_bound) << " of the box diagonal; t error mean " << hb::percent(cs.t_error_mean)
                  << ", max " << hb::percent(cs.t_error_max) << "; normal error mean " << hb::sig(cs.normal_error_mean_deg)
                  << " deg, max " << hb::sig(cs.normal_error_max_deg) << " deg (means weighted by box samples)\n";
    }
  });
}
