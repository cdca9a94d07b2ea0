#pragma once
// Seams between pieces: which triangles each piece's box is baked from.
#include "geometry/obb.h"
#include "haptic_box/sample.h"
#include <cstdint>
#include <vector>

namespace hb {

/// How far pieces overlap at their seams.
struct SeamOptions {
  /// Each piece grows by at least this many rings of edge-neighbouring triangles, >= 0.
  int rings = 1;
  /// ... and by every triangle within `cells` position-grid cells of the piece (the cell of
  /// its PBB at density `m`: the largest box edge / (m - 1)), measured from the nearest piece
  /// triangle the growth came from, >= 0. Interpolation blends the four corner cells around
  /// the entry point, so a seam closer than about one cell is seen through the cut.
  float cells = 1.5f;
  int m = 32;          ///< the bake's position density (BoxParams::m), >= 2.
  /// The bake's per-box density (BakeOptions::density): with density.cell > 0 a piece's cell
  /// is its own box's, density.m_for(m, largest edge, mesh diagonal).
  PositionDensity density;
  ObbOptions obb;      ///< PBB fitting, as the bake does it.
};

/// The triangle lists to bake, one per piece, from a piece id per triangle: each piece is
/// grown past its seams (SeamOptions), so the seam triangles belong to both boxes.
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
/// triangles. Throws hb::InvalidInput when the list's size differs from the triangle count
/// or the options are out of range.
std::vector<std::vector<std::uint32_t>> piece_triangle_lists(const TriangleMesh& mesh,
                                                             const std::vector<std::uint32_t>& piece_of_triangle,
                                                             const SeamOptions& options = {});

} // namespace hb
