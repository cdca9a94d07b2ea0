#pragma once
// The `--pieces auto|FILE|none` options shared by the commands that bake: they fill the
// pieces and seams of a hb::BakeRecipe (the cutting itself is hb::bake's).
#include "recipe/bake_recipe.h"
#include <CLI/CLI.hpp>
#include <cstdint>
#include <string>
#include <vector>

namespace hb::cli {

/// Adds --pieces (into `spec`), --threshold, --max-pieces (into recipe.pieces.automatic),
/// --seam-rings and --seam-cells (into recipe.seams) to a command.
void add_pieces_options(CLI::App& cmd, std::string& spec, BakeRecipe& recipe);

/// Sets recipe.pieces from `spec` (hb::pieces_from_spec), keeping the automatic options,
/// with a terminal progress bar for an automatic decomposition. "faces" gives a CAD model's
/// faces as the pieces (`face_ids`, one per triangle; UsageError when empty: not a CAD model).
void apply_pieces_spec(const std::string& spec, BakeRecipe& recipe, const std::vector<std::uint32_t>& face_ids = {});

/// Prints "decomposed into K pieces in S s" to stderr after an automatic decomposition.
void print_decomposition(const BakeRecipe& recipe, const BakeResult& result);

} // namespace hb::cli
