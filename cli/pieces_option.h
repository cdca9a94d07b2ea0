#pragma once
// The `--pieces auto|FILE|none` options shared by the commands that bake: they fill the
// pieces and seams of a hb::BakeRecipe (the cutting itself is hb::bake's).
#include "recipe/bake_recipe.h"
#include <CLI/CLI.hpp>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

namespace hb::cli {

/// What --pieces gave: the kind (`spec`: none, auto, faces or a file) and the tuning keys given.
struct PiecesArgs {
  std::string spec = "none";
  bool given = false;  ///< --pieces was on the command line.
  std::optional<double> threshold, seam_cells, padding;
  std::optional<int> max_pieces, seam_rings;
  /// Sets the given keys in `recipe` (automatic pieces, seams, PBB padding); the others keep
  /// the recipe's.
  void apply_tuning(BakeRecipe& recipe) const;
};

/// Adds --pieces KIND[,threshold=T,max=N,seam-rings=R,seam-cells=C,padding=P] to a command;
/// `default_kind` is what the command uses when it is not given (said in the help). The help's
/// defaults are `defaults`' (the recipe the command bakes); with `other` (a command that bakes
/// one of two recipes), a default that differs there is given for both.
void add_pieces_options(CLI::App& cmd, PiecesArgs& args, const std::string& default_kind = "none",
                        const BakeRecipe& defaults = BakeRecipe(), const BakeRecipe* other = nullptr);

/// Sets recipe.pieces from `spec` (hb::pieces_from_spec), keeping the automatic options,
/// with a terminal progress bar for an automatic decomposition. "faces" gives a CAD model's
/// faces as the pieces (`face_ids`, one per triangle; UsageError when empty: not a CAD model).
void apply_pieces_spec(const std::string& spec, BakeRecipe& recipe, const std::vector<std::uint32_t>& face_ids = {});

/// Prints "decomposed into K pieces in S s" to stderr after an automatic decomposition.
void print_decomposition(const BakeRecipe& recipe, const BakeResult& result);

} // namespace hb::cli
