#pragma once
// The box cache: baked scenes kept on disk, keyed by the mesh file's hash and the whole bake
// recipe, in one directory that follows the XDG convention. The CLI's sweep and report and
// the window's bakes share it; `hapticbox cache` and the window show its size and clear it.
#include "recipe/bake_recipe.h"
#include <cstdint>
#include <optional>
#include <string>

namespace hb {

/// $XDG_CACHE_HOME/hapticbox/boxes when XDG_CACHE_HOME is set (absolute), else
/// $HOME/.cache/hapticbox/boxes, else /tmp/hapticbox-boxes.
std::string default_box_cache_dir();

/// A 64-bit key of everything in `recipe` that changes the baked scene (densities, per-box
/// density, padding and PBB fit, refinement, scene grid and its options, pieces (a piece file by its contents, given ids
/// by their values, automatic by its options), seams, codec and its bound); progress
/// callbacks and the ranks (communicator, scene_on_every_rank) are not part of it. Throws hb::IoError when a piece file cannot be read.
std::uint64_t recipe_key(const BakeRecipe& recipe);

/// What a cache directory holds.
struct BoxCacheUsage {
  std::size_t files = 0;
  std::uint64_t bytes = 0;
};

/// One cache directory (created on the first store).
class BoxCache {
public:
  explicit BoxCache(std::string dir = default_box_cache_dir());
  const std::string& dir() const { return dir_; }

  /// DIR/<mesh hash>_<recipe key>.hbox (16 hex digits each).
  std::string path_for(std::uint64_t mesh_hash, const BakeRecipe& recipe) const;
  /// The cached scene, or nothing when there is none, it records another mesh hash, or it is
  /// unreadable (a corrupt entry is then removed so the next store replaces it).
  std::optional<BoxScene> load(std::uint64_t mesh_hash, const BakeRecipe& recipe) const;
  /// Stores `scene` (baked from the mesh of scene.parts().source.mesh_hash with `recipe`).
  /// Throws hb::IoError (directory or file not writable, disk full).
  void store(const BoxScene& scene, const BakeRecipe& recipe) const;

  /// The .hbox files in the directory and their total size.
  BoxCacheUsage usage() const;
  /// Removes every .hbox file of the directory (nothing else); returns what was removed.
  /// Throws hb::IoError when a file cannot be removed.
  BoxCacheUsage clear() const;

private:
  std::string dir_;
};

/// bake() through a cache.
struct CachedBake {
  BakeResult result;        ///< stats are zero when the scene came from the cache.
  bool from_cache = false;
  std::string path;         ///< the cache entry (empty without a cache or a mesh hash).
  bool stored = false;      ///< baked now and stored at `path`.
  std::string warning;      ///< set when the scene was baked but could not be stored.
};

/// The cached scene for (source.mesh_hash, recipe) when `cache` has it, else bake(mesh,
/// recipe, source) and store the result. No cache (nullptr) or a zero mesh hash: a plain bake.
CachedBake bake_cached(const TriangleMesh& mesh, const BakeRecipe& recipe, const SourceInfo& source,
                       const BoxCache* cache);

/// How write_baked_scene wrote its file.
enum class BakedFileWrite {
  entry,  ///< the output is the cache entry itself: nothing written.
  copy,   ///< a copy of the cache entry (the scene was serialised once, into the cache).
  saved,  ///< no cache entry: the scene saved (save_box_file).
};

/// Writes `baked`'s scene to `out` serialising it at most once: a scene with a cache entry
/// (loaded from it, or stored by this bake) is copied from the entry byte for byte (through a
/// temporary file and a rename, like save_box_file), else saved. Throws hb::IoError.
BakedFileWrite write_baked_scene(const CachedBake& baked, const std::string& out);

} // namespace hb
