#pragma once
// "The default recipe or one sampling?", decided once for every front end: `bake`, `report`,
// `field` and the window's Bake make hb::default_recipe() (automatic pieces, the error budget
// choosing n, the cell and refinement per piece) unless the user gave a sampling option, and
// then exactly that sampling, one raw bake. What a front end may change of the default bake is
// one DefaultRecipeOverrides, applied by default_recipe(overrides), so `bake --budget ...` and
// any other front end give the same recipe for the same words.
#include "recipe/bake_recipe.h"
#include <optional>
#include <string>

namespace hb {

/// Which sampling options a front end was given: -m, -n, --cell (a per-box density) and
/// --refine. A front end without one of them leaves it false (report and field take -m and
/// -n); the window's Advanced sampling gives -m, -n and --refine (SamplingGiven::advanced).
struct SamplingGiven {
  bool m = false, n = false, cell = false, refine = false;

  /// The window's bake panel: its Advanced sampling sets m, n and refinement; the default
  /// recipe sets none.
  static SamplingGiven advanced(bool on) { return {on, on, false, on}; }
};

/// True when no sampling option was given: the bake is default_recipe().
bool bakes_default_recipe(const SamplingGiven& given);

/// default_recipe() when bakes_default_recipe(given), else `sampling` (the recipe the front end
/// built from the options given).
BakeRecipe choose_recipe(const SamplingGiven& given, BakeRecipe sampling);

/// What a front end may change of the default bake; everything not set is default_recipe()'s.
struct DefaultRecipeOverrides {
  /// The error budget and the simplified surface, as `bake --budget` takes them (see
  /// parse_default_budget): "" or "default" for the defaults.
  std::string budget;
  std::optional<int> max_m;               ///< the largest per-box m (`--cell ...,max-m=M`).
  /// The codec's bound (`--codec block,max-error=E` or `ratio=R`); unset: the codec's default.
  std::optional<float> codec_max_error, codec_ratio;
  /// Measurement-only switches (comparisons, not a user's options; the CLI's HB_MEASURE):
  /// keep the chosen scene's triangle ids, search every sampling, the decimation's shading
  /// check and its bound in degrees.
  bool keep_triangle_ids = false, full_search = false;
  std::optional<DecimationOptions::ShadingCheck> simplify_shading_check;
  std::optional<double> simplify_shading_deg;
};

/// Reads a budget spec into `recipe`: the error budget's keys (hb::parse_budget: felt, raw,
/// memory, relative, p95, median, dir99, agree) and the simplified surface's: simplify=on|off,
/// simplify-above=N (triangles), deviation=F (fraction of the diagonal, [0, 0.099]; 0: the
/// budget's own bound, simplification_bound) and shading-map=S (-1 to 64; 0: automatic, -1:
/// none). Keys not named keep `recipe`'s values. Throws hb::InvalidInput naming the key.
void parse_default_budget(const std::string& spec, BudgetRecipe& recipe);

/// True when `spec` names a key of the simplified surface (they belong to the default bake).
bool budget_names_surface_keys(const std::string& spec);

/// default_recipe() with `overrides` applied. Throws hb::InvalidInput for a bad budget spec.
BakeRecipe default_recipe(const DefaultRecipeOverrides& overrides);

} // namespace hb
