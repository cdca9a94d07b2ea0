// recipe_choice: the default recipe unless a sampling option was given.
#include "recipe/recipe_choice.h"
#include <utility>

namespace hb {

bool bakes_default_recipe(const SamplingGiven& given) {
  return !(given.m || given.n || given.cell || given.refine);
}

BakeRecipe choose_recipe(const SamplingGiven& given, BakeRecipe sampling) {
  return bakes_default_recipe(given) ? default_recipe() : std::move(sampling);
}

} // namespace hb
