#pragma once
// The `--pieces auto|FILE|none` option shared by the commands that bake: how a mesh is cut
// into pieces before one box per piece is baked.
#include "decomposition/auto_decomposition.h"
#include <CLI/CLI.hpp>
#include <string>
#include <vector>

namespace hb::cli {

/// Options behind --pieces.
struct PiecesChoice {
  std::string spec = "none";       ///< "none" (one box), "auto", or a piece file (.txt or .ply).
  AutoDecompositionOptions automatic;
  int seam_rings = 1;              ///< rings of seam triangles each piece shares with its neighbours.
};

/// Adds --pieces, --threshold, --max-pieces and --seam-rings to a command.
void add_pieces_options(CLI::App& cmd, PiecesChoice& choice);

/// The triangle lists to bake (one per piece, seams shared). Prints a one-line summary of an
/// automatic decomposition to stderr. Throws what the reader or the decomposition throws.
std::vector<std::vector<std::uint32_t>> resolve_pieces(const TriangleMesh& mesh, const PiecesChoice& choice);

} // namespace hb::cli
