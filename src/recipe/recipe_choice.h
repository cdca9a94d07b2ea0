#pragma once
// "The default recipe or one sampling?", decided once for every front end: `bake`, `report`,
// `field` and the window's Bake make hb::default_recipe() (automatic pieces, the error budget
// choosing n, the cell and refinement per piece) unless the user gave a sampling option, and
// then exactly that sampling, one raw bake.
#include "recipe/bake_recipe.h"

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

} // namespace hb
