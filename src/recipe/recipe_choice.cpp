// recipe_choice: the default recipe unless a sampling option was given, and the default
// recipe with a front end's overrides.
#include "recipe/recipe_choice.h"
#include "spec_parse.h"
#include <utility>

namespace hb {
namespace {

const char* const kSurfaceKeys[] = {"simplify", "simplify-above", "deviation", "shading-map"};

bool is_surface_key(const std::string& key) {
  for (const char* k : kSurfaceKeys)
    if (key == k) return true;
  return false;
}

} // namespace

bool bakes_default_recipe(const SamplingGiven& given) {
  return !(given.m || given.n || given.cell || given.refine);
}

BakeRecipe choose_recipe(const SamplingGiven& given, BakeRecipe sampling) {
  return bakes_default_recipe(given) ? default_recipe() : std::move(sampling);
}

void parse_default_budget(const std::string& spec, BudgetRecipe& recipe) {
  if (spec_trim(spec).empty() || spec_trim(spec) == "default") return;
  // The error budget's own keys go to parse_budget together; the surface's are read here.
  std::string budget_keys;
  const auto budget_key = [&budget_keys](const char* key) {
    return SpecKey{key, [&budget_keys, key](const std::string& v, const std::string&) {
                     budget_keys += (budget_keys.empty() ? "" : ",") + std::string(key) + "=" + v;
                   }};
  };
  parse_spec_keys("--budget", spec,
                  {budget_key("felt"), budget_key("raw"), budget_key("memory"), budget_key("relative"),
                   budget_key("p95"), budget_key("median"), budget_key("dir99"), budget_key("agree"),
                   {"simplify", [&recipe](const std::string& value, const std::string& what) {
                      const std::string v = spec_trim(value);
                      if (v.empty() || v == "on" || v == "1" || v == "yes") recipe.simplify = true;
                      else if (v == "off" || v == "0" || v == "no") recipe.simplify = false;
                      else throw InvalidInput(what + ": '" + v + "' is not on or off");
                    }},
                   {"simplify-above", [&recipe](const std::string& v, const std::string& what) {
                      recipe.simplify_above = std::size_t(spec_number(v, what, 0, 1e15));
                    }},
                   {"deviation", [&recipe](const std::string& v, const std::string& what) {
                      recipe.simplify_deviation = spec_number(v, what, 0.0, 0.099);
                    }},
                   {"shading-map", [&recipe](const std::string& v, const std::string& what) {
                      recipe.shading_map_side = int(spec_number(v, what, -1, 64));
                    }}});
  if (!budget_keys.empty()) recipe.budget = parse_budget(budget_keys);
}

bool budget_names_surface_keys(const std::string& spec) {
  std::stringstream ss(spec);
  std::string item;
  while (std::getline(ss, item, ','))
    if (is_surface_key(spec_trim(item.substr(0, item.find('='))))) return true;
  return false;
}

BakeRecipe default_recipe(const DefaultRecipeOverrides& o) {
  BakeRecipe r = default_recipe();
  parse_default_budget(o.budget, r.budget);
  if (o.max_m) r.options.density.max_m = *o.max_m;
  if (o.codec_max_error) r.codec.max_error = *o.codec_max_error;
  if (o.codec_ratio) r.codec.ratio = *o.codec_ratio;
  r.budget.keep_triangle_ids = o.keep_triangle_ids;
  r.budget.full_search = o.full_search;
  if (o.simplify_shading_check) r.budget.simplify_shading_check = *o.simplify_shading_check;
  if (o.simplify_shading_deg) r.budget.simplify_shading_deg = *o.simplify_shading_deg;
  return r;
}

} // namespace hb
