#pragma once
// Seams between pieces: which triangles each piece's box is baked from.
#include "mesh/triangle_mesh.h"
#include <cstdint>
#include <functional>
#include <vector>

namespace hb {

/// How far pieces overlap at their seams.
struct SeamOptions {
  /// Each piece grows by at least this many rings of edge-neighbouring triangles, >= 0.
  int rings = 1;
  /// ... and by every triangle within `cells` position-grid cells of the piece (the cell of
  /// the box the bake fits to it, PieceGrid), measured from the nearest piece triangle the
  /// growth came from, >= 0. Interpolation blends the four corner cells around the entry
  /// point, so a seam closer than about one cell is seen through the cut.
  float cells = 1.5f;
};

/// The position grid of the box baked for a piece: its cell is largest_edge / (m - 1).
struct PieceGrid {
  float largest_edge = 0.f;  ///< largest edge of the piece's PBB, model units.
  int m = 32;                ///< the box's position density, >= 2.
};
/// The grid of the box the bake fits to a piece (its triangle ids); see hb::seamed_piece_lists
/// (recipe/bake_recipe.h), which answers it from the bake's own options.
using PieceGridOf = std::function<PieceGrid(const std::vector<std::uint32_t>& piece)>;

/// The triangle lists to bake, one per piece, from a piece id per triangle: each piece is
/// grown past its seams (SeamOptions, widths in the cells `grid_of` gives each piece; needed
/// only when options.cells > 0), so the seam triangles belong to both boxes.
///
/// Why overlap: a box stores only its own piece, cut open at the seam. A probe entering
/// near the seam meets, in the box of piece A, corner samples that pass through the cut (a
/// back face or a miss) next to samples that hit A; interpolation then drops or bends A's
/// surface up to a cell short of the seam, and piece B's box does the same from the other
/// side, so without overlap a probe crossing the seam falls into a gap between the two
/// (measured on the armadillo: one miss in six within five rings of a seam, one in fifty
/// elsewhere). With the seam zone in both boxes, the scene's rule (the valid contact
/// nearest the handle wins) picks one answer where both report a contact.
///
/// `piece_of_triangle[t]` in 0..K-1 (ids absent from the list give empty pieces, which are
/// dropped; the result is in id order). An empty `piece_of_triangle` means one piece of all
/// triangles. Throws hb::InvalidInput when the list's size differs from the triangle count,
/// the options are out of range, or cells > 0 and there is no grid_of.
std::vector<std::vector<std::uint32_t>> piece_triangle_lists(const TriangleMesh& mesh,
                                                             const std::vector<std::uint32_t>& piece_of_triangle,
                                                             const SeamOptions& options = {},
                                                             const PieceGridOf& grid_of = {});

} // namespace hb
