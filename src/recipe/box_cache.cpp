// The box cache:
//  1. the key: xxHash3 of a canonical text of the recipe (every field that changes the
//     scene, floats in hexadecimal so no two values print alike; a piece file by the hash of
//     its bytes, given ids by the hash of their values);
//  2. the entry: DIR/<mesh hash>_<key>.hbox, written through save_box_file (temporary file
//     and rename, so a reader never sees half a file);
//  3. a load checks the recorded mesh hash; an unreadable entry is removed and rebaked;
//  4. a front end's output file is a copy of the entry (write_baked_scene): a fresh bake is
//     serialised once.
#include "recipe/box_cache.h"
#include "errors.h"
#include "store/box_file.h"
#include "mesh/file_hash.h"
#include <xxhash.h>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <sstream>

namespace hb {
namespace {

namespace fs = std::filesystem;

std::string hexfloat(double v) {
  char buf[40];
  std::snprintf(buf, sizeof buf, "%a", v);
  return buf;
}

bool is_box_entry(const fs::directory_entry& e) {
  std::error_code ec;
  return e.is_regular_file(ec) && e.path().extension() == ".hbox";
}

} // namespace

std::string default_box_cache_dir() {
  if (const char* xdg = std::getenv("XDG_CACHE_HOME"); xdg && xdg[0] == '/') return std::string(xdg) + "/hapticbox/boxes";
  if (const char* home = std::getenv("HOME"); home && *home) return std::string(home) + "/.cache/hapticbox/boxes";
  return "/tmp/hapticbox-boxes";
}

std::uint64_t recipe_key(const BakeRecipe& r) {
  std::ostringstream k;
  const BakeOptions& o = r.options;
  // hbcache2: a budgeted bake may carry the stroke route (recipe/stroke_route.h), so entries
  // keyed otherwise are not reused.
  k << "hbcache2 m " << o.params.m << " n " << o.params.n << " cell " << hexfloat(o.density.cell) << " min_m "
    << o.density.min_m << " max_m " << o.density.max_m << " padding " << hexfloat(o.obb.padding) << " obb_iter "
    << o.obb.refine_iterations << " refine " << o.refine;
  // The scene grid is baked into scenes of several boxes only, but the key need not know that.
  k << " grid " << o.scene_grid;
  if (o.scene_grid) k << ' ' << hexfloat(o.grid.cell) << ' ' << o.grid.max_cells;
  const PiecesRecipe& p = r.pieces;
  switch (p.kind) {
  case PiecesRecipe::Kind::none: k << " pieces none"; break;
  case PiecesRecipe::Kind::file: k << " pieces file " << hash_text(hash_file(p.file)); break;
  case PiecesRecipe::Kind::given:
    k << " pieces given " << hash_text(XXH3_64bits(p.given.data(), p.given.size() * sizeof(std::uint32_t)));
    break;
  case PiecesRecipe::Kind::automatic: {
    const AutoDecompositionOptions& a = p.automatic;
    k << " pieces auto " << hexfloat(a.threshold) << ' ' << hexfloat(a.min_area_fraction) << ' ' << a.max_pieces << ' '
      << a.leaves << ' ' << a.lines << ' ' << a.seed;
    break;
  }
  }
  // Seams change nothing with one piece, but the key need not know that.
  k << " seams " << r.seams.rings << ' ' << hexfloat(r.seams.cells);
  k << " codec " << codec_name(r.codec.codec);
  if (r.codec.codec != CodecId::none)
    k << ' ' << hexfloat(r.codec.max_error) << ' ' << hexfloat(r.codec.ratio) << ' ' << r.codec.normal_bits;
  if (r.budget.enabled) {
    const BudgetRecipe& b = r.budget;
    // "timed": the entry holds the query times of every raw sampling tried (an entry without
    // them would give the speed chart nothing to place; it is baked again).
    k << " budget timed " << budget_spec(b.budget) << ' ' << b.probes << ' ' << b.tuning_seed << ' ' << b.check_seed;
    for (const Sampling& s : b.samplings) k << ' ' << hexfloat(s.cell) << ' ' << s.n;
    if (b.surface_tolerance > 0) k << " surface " << hexfloat(float(b.surface_tolerance));
    // "frames": an Embree-routed scene keeps no tables (entries from before held them).
    k << (b.keep_triangle_ids ? " ids kept" : " ids dropped, embree frames");
    if (b.full_search) k << " full search";
    if (b.simplify)
      k << " simplify " << b.simplify_above << ' ' << hexfloat(float(b.simplify_deviation)) << ' '
        << hexfloat(float(b.simplify_shading_deg)) << " fitted-shading "
        << (b.simplify_shading_check == DecimationOptions::ShadingCheck::fit ? "fit" : "ring") << " map "
        << b.shading_map_side;
  }
  const std::string text = k.str();
  return XXH3_64bits(text.data(), text.size());
}

BoxCache::BoxCache(std::string dir) : dir_(std::move(dir)) {
  if (dir_.empty()) throw InvalidInput("box cache: empty directory name");
}

std::string BoxCache::path_for(std::uint64_t mesh_hash, const BakeRecipe& recipe) const {
  return (fs::path(dir_) / (hash_text(mesh_hash) + "_" + hash_text(recipe_key(recipe)) + ".hbox")).string();
}

std::optional<BoxScene> BoxCache::load(std::uint64_t mesh_hash, const BakeRecipe& recipe) const {
  const std::string path = path_for(mesh_hash, recipe);
  std::error_code ec;
  if (!fs::exists(path, ec)) return std::nullopt;
  try {
    BoxScene scene = load_box_file(path);
    if (scene.parts().source.mesh_hash == mesh_hash && !scene.parts().boxes.empty()) return scene;
    return std::nullopt;
  } catch (const Error&) {
    fs::remove(path, ec);  // corrupt or truncated: rebaked and replaced
    return std::nullopt;
  }
}

void BoxCache::store(const BoxScene& scene, const BakeRecipe& recipe) const {
  std::error_code ec;
  fs::create_directories(dir_, ec);
  if (ec) throw IoError(dir_ + ": cannot create the box cache directory (" + ec.message() + ")");
  save_box_file(scene, path_for(scene.parts().source.mesh_hash, recipe));
}

BoxCacheUsage BoxCache::usage() const {
  BoxCacheUsage u;
  std::error_code ec;
  if (!fs::is_directory(dir_, ec)) return u;
  for (const auto& e : fs::directory_iterator(dir_, ec)) {
    if (!is_box_entry(e)) continue;
    ++u.files;
    u.bytes += e.file_size(ec);
  }
  return u;
}

BoxCacheUsage BoxCache::clear() const {
  BoxCacheUsage removed;
  std::error_code ec;
  if (!fs::is_directory(dir_, ec)) return removed;
  std::vector<fs::directory_entry> entries;
  for (const auto& e : fs::directory_iterator(dir_, ec))
    if (is_box_entry(e)) entries.push_back(e);
  for (const auto& e : entries) {
    const std::uint64_t bytes = e.file_size(ec);
    if (!fs::remove(e.path(), ec) && ec)
      throw IoError(e.path().string() + ": cannot remove from the box cache (" + ec.message() + ")");
    ++removed.files;
    removed.bytes += bytes;
  }
  return removed;
}

CachedBake bake_cached(const TriangleMesh& mesh, const BakeRecipe& recipe, const SourceInfo& source,
                       const BoxCache* cache) {
  CachedBake out;
  const bool cached = cache && source.mesh_hash != 0;
  // With several ranks (recipe.options.communicator) all ranks load, or all bake; rank 0 stores.
  Communicator& comm = communicator_or_serial(recipe.options.communicator);
  if (cached) {
    out.path = cache->path_for(source.mesh_hash, recipe);
    std::optional<BoxScene> scene = cache->load(source.mesh_hash, recipe);
    const bool everywhere =
        comm.size() == 1 || comm.sum(std::uint64_t(scene.has_value())) == std::uint64_t(comm.size());
    if (scene && everywhere) {
      out.result.scene = std::move(*scene);
      out.from_cache = true;
      return out;
    }
  }
  out.result = bake(mesh, recipe, source);
  if (cached && comm.is_root()) {
    try {
      cache->store(out.result.scene, recipe);
      out.stored = true;
    } catch (const Error& e) {
      out.warning = std::string("baked, but not cached: ") + e.what();
    }
  }
  return out;
}

BakedFileWrite write_baked_scene(const CachedBake& baked, const std::string& out) {
  std::error_code ec;
  const bool has_entry = !baked.path.empty() && (baked.from_cache || baked.stored) && fs::exists(baked.path, ec);
  if (!has_entry) {
    save_box_file(baked.result.scene, out);
    return BakedFileWrite::saved;
  }
  if (fs::equivalent(baked.path, out, ec)) return BakedFileWrite::entry;
  const std::string tmp = out + ".tmp";
  ec.clear();
  fs::copy_file(baked.path, tmp, fs::copy_options::overwrite_existing, ec);
  if (!ec) fs::rename(tmp, out, ec);
  if (ec) {
    std::error_code ignored;
    fs::remove(tmp, ignored);
    throw IoError(out + ": cannot write the box file (" + ec.message() + ")");
  }
  return BakedFileWrite::copy;
}

} // namespace hb
