// bake(mesh, recipe):
//  1. a piece id per triangle (none, automatic decomposition, a piece file or given ids),
//     numbered compactly 0..K-1 in increasing order of the original ids;
//  2. each piece grown past its seams, in the cells of the box the bake will fit to it
//     (same PBB fit and per-box m as the bake);
//  3. one box per grown piece (bake_scene_from_lists), the piece ids recorded in the scene;
//  4. the codec, when one is asked for.
#include "recipe/bake_recipe.h"
#include "decomposition/piece_file.h"
#include "errors.h"
#include "stopwatch.h"
#include <algorithm>
#include <chrono>

namespace hb {
namespace {

std::vector<std::uint32_t> compact(std::vector<std::uint32_t> ids) {
  std::vector<std::uint32_t> sorted(ids);
  std::sort(sorted.begin(), sorted.end());
  sorted.erase(std::unique(sorted.begin(), sorted.end()), sorted.end());
  if (!sorted.empty() && sorted.back() == sorted.size() - 1) return ids;  // already 0..K-1
  for (auto& id : ids) id = std::uint32_t(std::lower_bound(sorted.begin(), sorted.end(), id) - sorted.begin());
  return ids;
}

} // namespace

PiecesRecipe pieces_from_spec(const std::string& spec) {
  PiecesRecipe p;
  if (spec.empty() || spec == "none") return p;
  if (spec == "auto") {
    p.kind = PiecesRecipe::Kind::automatic;
    return p;
  }
  p.kind = PiecesRecipe::Kind::file;
  p.file = spec;
  return p;
}

std::string pieces_spec(const PiecesRecipe& pieces) {
  switch (pieces.kind) {
  case PiecesRecipe::Kind::none: return "none";
  case PiecesRecipe::Kind::automatic: return "auto";
  case PiecesRecipe::Kind::file: return pieces.file;
  case PiecesRecipe::Kind::given: return "given";
  }
  return "none";
}

std::vector<std::uint32_t> resolve_piece_ids(const TriangleMesh& mesh, const PiecesRecipe& pieces, const EmbreeScene* scene) {
  switch (pieces.kind) {
  case PiecesRecipe::Kind::none: return {};
  case PiecesRecipe::Kind::automatic:
    if (pieces.resolved.empty()) return decompose_auto(mesh, pieces.automatic, scene).piece_of_triangle;
    if (pieces.resolved.size() != mesh.triangle_count())
      throw InvalidInput("bake: " + std::to_string(pieces.resolved.size()) + " decomposed piece ids for " +
                         std::to_string(mesh.triangle_count()) + " triangles");
    return compact(pieces.resolved);
  case PiecesRecipe::Kind::file: return compact(read_piece_file(pieces.file, mesh.triangle_count()));
  case PiecesRecipe::Kind::given:
    if (pieces.given.size() != mesh.triangle_count())
      throw InvalidInput((pieces.file.empty() ? std::string("bake") : pieces.file) + ": " + std::to_string(pieces.given.size()) +
                         " piece ids for the mesh's " + std::to_string(mesh.triangle_count()) + " triangles");
    return compact(pieces.given);
  }
  return {};
}

std::vector<std::vector<std::uint32_t>> seamed_piece_lists(const TriangleMesh& mesh,
                                                           const std::vector<std::uint32_t>& piece_ids,
                                                           const SeamOptions& seams, const BakeOptions& options) {
  const float diagonal = mesh.bounds().diagonal();
  return piece_triangle_lists(mesh, piece_ids, seams, [&](const std::vector<std::uint32_t>& piece) {
    const Obb box = fit_obb(mesh, piece, options.obb);
    const float edge = 2.f * box.half.maxCoeff();
    return PieceGrid{edge, options.density.m_for(options.params.m, edge, diagonal)};
  });
}

BakeOptions search_bake_options(BakeOptions base, std::shared_ptr<const SurfaceTriangles> surface) {
  base.refine = surface != nullptr;
  base.surface = std::move(surface);
  base.scene_grid = false;
  base.communicator = nullptr;
  base.progress = nullptr;
  return base;
}

BakeRecipe default_recipe() {
  BakeRecipe r;
  r.pieces.kind = PiecesRecipe::Kind::automatic;
  r.pieces.automatic.threshold = 0.001;
  r.options.density.cell = r.budget.samplings.back().cell;
  r.options.density.max_m = 128;
  r.options.params.n = r.budget.samplings.back().n;
  r.options.refine = true;
  r.codec = CodecOptions{CodecId::block};
  r.budget.enabled = true;
  return r;
}

BakeResult bake(const TriangleMesh& mesh, const BakeRecipe& recipe, const SourceInfo& source) {
  if (recipe.budget.enabled) return bake_to_budget(mesh, recipe, source);
  BakeResult result;
  const auto t0 = std::chrono::steady_clock::now();
  std::vector<std::uint32_t> ids = resolve_piece_ids(mesh, recipe.pieces);
  if (recipe.pieces.kind == PiecesRecipe::Kind::automatic) result.decompose_seconds = seconds_since(t0);
  const auto lists = seamed_piece_lists(mesh, ids, recipe.seams, recipe.options);
  SourceInfo src = source;
  if (src.triangles == 0) src.triangles = mesh.triangle_count();
  if (!(src.diagonal > 0.f)) src.diagonal = mesh.bounds().diagonal();
  result.scene = bake_scene_from_lists(mesh, lists, recipe.options, src, &result.stats);
  // With several ranks (BakeOptions::communicator) only the ranks that receive the tables
  // have boxes; the others have nothing to record or compress.
  const bool has_boxes = !result.scene.parts().boxes.empty();
  if (!has_boxes) return result;
  SceneParts parts = result.scene.parts();
  if (lists.size() > 1) parts.piece_of_triangle = std::move(ids);
  if (recipe.codec.codec != CodecId::none) {
    const auto tc = std::chrono::steady_clock::now();
    for (HapticBox& box : parts.boxes) box = box.compressed(recipe.codec);
    result.compress_seconds = seconds_since(tc);
  }
  result.scene = BoxScene(std::move(parts));
  return result;
}

} // namespace hb
