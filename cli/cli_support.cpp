#include "cli_support.h"
#include "errors.h"
#include "figure_text.h"
#include "recipe/box_cache.h"
#include <chrono>
#include <cctype>
#include <cstdio>
#include <fstream>
#include <iostream>
#include <limits>
#include <optional>

namespace hb::cli {
namespace {
Communicator* the_communicator = nullptr;
std::string the_command_line;
}

const std::string& command_line() { return the_command_line; }

void set_command_line(int argc, char** argv) {
  the_command_line.clear();
  for (int i = 0; i < argc; ++i) {
    std::string a = i == 0 ? std::string("hapticbox") : std::string(argv[i]);
    if (a.find_first_of(" \t'\"") != std::string::npos) a = "'" + a + "'";
    the_command_line += (i ? " " : "") + a;
  }
}

void check_same_mesh(const BoxScene& scene, const std::string& box_path, const std::string& mesh_path,
                     std::uint64_t mesh_hash, bool force) {
  if (scene.parts().source.mesh_hash == 0 || scene.parts().source.mesh_hash == mesh_hash) return;
  const std::string what = box_path + " was baked from a different mesh than " + mesh_path + " (recorded source " +
                           (scene.parts().source.mesh_path.empty() ? std::string("unknown") : scene.parts().source.mesh_path) +
                           ", hashes differ)";
  if (!force) throw InvalidInput(what + ": the comparison would measure nothing; give the mesh it was baked from, or --force");
  if (communicator().is_root()) std::cerr << "hapticbox: warning: " << what << "; going on (--force)\n";
}

void check_ratio_target(double target, double achieved, double bound, double t_error_mean, bool strict,
                        nlohmann::json& j) {
  if (!(target > 0.0)) return;
  const bool reached = achieved >= target * (1.0 - 1e-3);
  j["ratio_target"] = target;
  j["ratio_reached"] = reached;
  if (reached) return;
  const std::string what = "--ratio " + hb::sig(target) + ": target not reached; the codec ends at " + hb::sig(achieved) +
                           ":1 with its error bound at its maximum, " + hb::percent(bound) +
                           " of the box diagonal (t error mean " + hb::percent(t_error_mean) + ")";
  if (strict) throw Error(what + " (--strict)");
  if (communicator().is_root())
    std::cerr << "hapticbox: warning: " << what << "; the file was written (--strict makes this an error)\n";
}

std::string lower_extension(const std::string& path) {
  const std::size_t slash = path.find_last_of('/');
  const std::size_t dot = path.find_last_of('.');
  if (dot == std::string::npos || (slash != std::string::npos && dot < slash)) return {};
  std::string ext = path.substr(dot);
  for (char& c : ext) c = char(std::tolower((unsigned char)c));
  return ext;
}

Communicator& communicator() { return communicator_or_serial(the_communicator); }

void set_communicator(Communicator* communicator) { the_communicator = communicator; }

void add_probe_options(CLI::App& cmd, std::size_t& samples, std::uint64_t& seed, std::size_t min_samples) {
  cmd.add_option("--samples", samples,
                 "Probes (segments sampled over the mesh; the same count and seed give the same probes in every "
                 "command" + std::string(min_samples == 0 ? "; 0: none)" : ")"))
      ->check(CLI::Range(min_samples, std::size_t(100000000)))
      ->capture_default_str();
  cmd.add_option("--seed", seed, "Probe seed")->capture_default_str();
}

void add_cache_option(CLI::App& cmd, std::string& dir) {
  dir = default_box_cache_dir();
  cmd.add_option_function<std::string>(
         "--cache", [&dir](const std::string& d) { dir = d == "none" ? std::string() : d; },
         "Box cache directory, shared by bake, sweep, report, field and the window (default " +
             default_box_cache_dir() + "); none: bake without it and store nothing")
      ->type_name("DIR|none");
}

SamplingGiven sampling_given(const CLI::App& cmd) {
  const auto given = [&cmd](const char* name) {
    const CLI::Option* option = cmd.get_option_no_throw(name);
    return option != nullptr && option->count() > 0;
  };
  return {given("-m"), given("-n"), given("--cell"), given("--refine")};
}

ModelBake bake_model(const TriangleMesh& mesh, const std::string& mesh_path, std::uint64_t mesh_hash,
                     const SamplingGiven& given, const BoxParams& params, const std::string& cache_dir) {
  Communicator& comm = communicator();
  const bool sampling_given = !bakes_default_recipe(given);
  BakeRecipe sampling;
  sampling.options.params = params;
  // Baked across the ranks of an MPI job; every rank needs the scene for the evaluation.
  sampling.options.communicator = &comm;
  sampling.options.scene_on_every_rank = true;
  // The default is one process's bake: each rank of a job bakes it alone.
  BakeRecipe recipe = choose_recipe(given, std::move(sampling));
  recipe.options.progress = terminal_progress("bake");
  // The cache only for the default and one process: ranks must not evaluate different scenes
  // (a cached one and a fresh one of another build).
  std::optional<BoxCache> cache;
  if (!sampling_given && !cache_dir.empty() && comm.size() == 1) cache.emplace(cache_dir);
  const SourceInfo source{mesh_path, mesh_hash, mesh.triangle_count(), mesh.bounds().diagonal()};
  const auto start = std::chrono::steady_clock::now();
  CachedBake baked = bake_cached(mesh, recipe, source, cache ? &*cache : nullptr);
  if (!baked.warning.empty() && comm.is_root()) std::cerr << "hapticbox: warning: " << baked.warning << "\n";
  ModelBake out{std::move(baked.result.scene), baked.from_cache, baked.path, 0.0, !sampling_given};
  out.seconds = baked.from_cache ? 0.0 : std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return out;
}


void add_route_option(CLI::App& cmd, std::string& route) {
  cmd.add_option("--route", route,
                 "Refined scenes: auto (default: the route the bake chose and stored, with its stroke route), cells "
                 "(the first crossing among the surface cells' triangles answers, no box asked; strokes too), embree (exact Embree over the scene's "
                 "surface) or boxes (the grid's boxes answer from their triangle ids, the cells' triangles confirm)")
      ->check(CLI::IsMember({"auto", "boxes", "cells", "embree"}))
      ->capture_default_str();
}

void apply_route(BoxScene& scene, const std::string& name) {
  const std::optional<SceneRoute> route = parse_route(name);
  if (!route) return;  // auto: the route the bake chose
  SceneParts parts = scene.parts();
  parts.stroke.reset();  // a route named answers a probe's strokes too
  parts.route = *route;
  if (*route == SceneRoute::boxes && !has_tables(parts))
    throw UsageError("--route boxes: this scene's boxes are frames without tables (the bake answered it by exact "
                     "Embree and dropped what no other route reads); bake it with HB_MEASURE=keep-ids to compare the routes");
  if (*route == SceneRoute::boxes && scene.refines() && !has_triangle_ids(parts))
    throw UsageError("--route boxes: this scene holds no triangle ids (the default bake drops them: the cells route "
                     "does not read them); bake it with HB_MEASURE=keep-ids to compare the routes");
  try {
    scene = BoxScene(std::move(parts));
  } catch (const InvalidInput& e) {
    throw UsageError("--route " + name + ": " + e.what());
  }
  if (*route == SceneRoute::cells && scene.route() != SceneRoute::cells && scene.refines())
    std::fprintf(stderr, "warning: --route cells: this scene has no surface cells (no grid, or no shared refined "
                         "surface); the boxes answer\n");
}

void print_json(const nlohmann::json& j) {
  nlohmann::json out = j;
  if (out.is_object() && !out.contains("ranks")) out["ranks"] = communicator().size();
  if (communicator().is_root()) std::cout << out.dump(2) << std::endl;
}

bool is_box_file(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  char magic[8] = {};
  in.read(magic, 8);
  return in.gcount() == 8 && std::string(magic, 8) == "HBOXFILE";
}

} // namespace hb::cli
