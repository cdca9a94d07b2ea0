#pragma once
// The surface a budgeted bake bakes and refines against (step 0 of budgeted_bake.cpp's
// overview): the mesh itself, or above BudgetRecipe::simplify_above triangles the mesh
// simplified within the budget's deviation, measured against the full surface, and shaded by
// a normal map of the full mesh's normals (or, without a map, by corner normals fitted to
// them). Internal to recipe/ (budget_search.cpp).
#include "perception/budget_report.h"
#include "surface/surface_triangles.h"
#include "mesh/triangle_mesh.h"
#include "recipe/bake_recipe.h"
#include "recipe/budget_probes.h"
#include <functional>
#include <memory>

namespace hb {

class EmbreeScene;

/// Called as a stage's work finishes: its name (BudgetReport::stage_seconds) and seconds.
using BudgetStageDone = std::function<void(const char* stage, double seconds)>;

/// The surface of one budgeted bake attempt.
struct BudgetSurface {
  TriangleMesh simplified;     ///< with `use_simplified`: the simplified mesh.
  TriangleMesh shaded;         ///< `simplified` with corner normals fitted to the full mesh's shading (no map only).
  bool use_simplified = false;

  /// What the decomposition, the lists, the ids and the grids use.
  const TriangleMesh& base(const TriangleMesh& full) const { return use_simplified ? simplified : full; }
  /// What the rays hit and the refinement's records shade with (a map, when fitted, overrides).
  const TriangleMesh& cast(const TriangleMesh& full, const BudgetRecipe& br) const {
    return use_simplified && br.shading_map_side < 0 ? shaded : use_simplified ? simplified : full;
  }
};

/// The surface for `recipe` on `mesh`: simplified when the budget says so and the
/// simplification keeps less than 90% of the triangles (pieces from a file or given ids keep
/// the full mesh: they name its triangles). Records the surface's figures in `rep`. Throws
/// hb::InvalidInput for a simplify deviation out of [0, 0.1).
/// With `ref.finest_fraction` > 0 the surface is simplified from `ref.finest` (made on the
/// first call) instead of from `mesh`.
BudgetSurface simplify_for_budget(const TriangleMesh& mesh, const BakeRecipe& recipe, BudgetReport& rep,
                                  const BudgetStageDone& stage_done, BudgetReference& ref);

/// The refinement records of `surface` (SurfaceTriangles of its cast mesh); a simplified
/// surface with BudgetRecipe::shading_map_side >= 0 shades through a normal map of the full
/// mesh's normals, fitted with the full mesh's Embree scene `full` (rep.surface_map_side).
std::shared_ptr<const SurfaceTriangles> refinement_surface(const TriangleMesh& mesh, const BudgetSurface& surface,
                                                           const BudgetRecipe& br, const EmbreeScene& full,
                                                           BudgetReport& rep, const BudgetStageDone& stage_done);

} // namespace hb
