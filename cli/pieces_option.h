#pragma once
// The `--pieces auto|FILE|none` option shared by the commands that bake: how a mesh is cut
// into pieces before one box per piece is baked.
#include "decomposition/auto_decomposition.h"
#include "decomposition/seam_overlap.h"
#include <CLI/CLI.hpp>
#include <string>
#include <vector>

namespace hb::cli {

/// Options behind --pieces.
struct PiecesChoice {
  std::string spec = "none";       ///< "none" (one box), "auto", or a piece file (.txt or .ply).
  AutoDecompositionOptions automatic;
  SeamOptions seams;               ///< how far neighbouring pieces share their seams.
};

/// Adds --pieces, --threshold, --max-pieces, --seam-rings and --seam-cells to a command.
void add_pieces_options(CLI::App& cmd, PiecesChoice& choice);

/// A piece id per triangle per `choice` (empty for "none": one piece). Prints a one-line
/// summary of an automatic decomposition to stderr.
std::vector<std::uint32_t> resolve_piece_ids(const TriangleMesh& mesh, const PiecesChoice& choice);

/// The triangle lists to bake (one per piece, seams shared). Prints a one-line summary of an
/// automatic decomposition to stderr. Throws what the reader or the decomposition throws.
/// `m` is the bake's position density (seam widths are in its cells).
std::vector<std::vector<std::uint32_t>> resolve_pieces(const TriangleMesh& mesh, const PiecesChoice& choice, int m,
                                                       const PositionDensity& density = {});

} // namespace hb::cli
